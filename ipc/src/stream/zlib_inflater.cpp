// SPDX-License-Identifier: Apache-2.0
#include "navmap/ipc/zlib_inflater.h"

#include <zlib.h>

namespace navmap::ipc {

FrameInflater zlibInflater() {
    return [](const std::uint8_t* in, std::size_t inBytes, std::uint8_t* out, std::size_t outBytes) {
        uLongf len = static_cast<uLongf>(outBytes);
        const int r = uncompress(out, &len, in, static_cast<uLong>(inBytes));
        return r == Z_OK && len == outBytes;
    };
}

}  // namespace navmap::ipc
