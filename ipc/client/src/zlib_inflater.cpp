// SPDX-License-Identifier: Apache-2.0
#include "navmap/ipc/client/zlib_inflater.h"

#include <zlib.h>

namespace navmap::ipc {

FrameInflater zlibInflater() {
    return [](const std::uint8_t* in, std::size_t in_bytes, std::uint8_t* out, std::size_t out_bytes) {
        uLongf len = static_cast<uLongf>(out_bytes);
        const int r = uncompress(out, &len, in, static_cast<uLong>(in_bytes));
        return r == Z_OK && len == out_bytes;
    };
}

}  // namespace navmap::ipc
