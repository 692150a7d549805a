// SPDX-License-Identifier: Apache-2.0
#include "navmap/ipc/client/frame_png.h"

#include <OpenImageIO/imageio.h>

#include <cerrno>
#include <cstddef>
#include <cstring>
#include <string>
#include <vector>

namespace navmap::ipc {

Status writeFramePng(const std::string& path, const FrameHeader& header, const std::uint8_t* pixels) {
    const std::size_t w = header.width;
    const std::size_t h = header.height;
    std::vector<std::uint8_t> rgba(w * h * 4);
    for (std::size_t y = 0; y < h; ++y) {
        convertRowToRgba(pixels + y * header.stride, header.format, rgba.data() + y * w * 4, static_cast<int>(w));
    }
    auto out = OIIO::ImageOutput::create(path);
    if (!out) return Error{path + ": " + OIIO::geterror()};
    const OIIO::ImageSpec spec(static_cast<int>(w), static_cast<int>(h), 4, OIIO::TypeDesc::UINT8);
    errno = 0;
    if (!out->open(path, spec) || !out->write_image(OIIO::TypeDesc::UINT8, rgba.data()) || !out->close()) {
        // OpenImageIO's message ("Could not open file ...") leaves out why; the C library's errno
        // of its failed call says it (no such directory, disk full, permission).
        const int err = errno;
        return Error{path + ": " + (err != 0 ? "cannot write: " + std::string(std::strerror(err)) : out->geterror())};
    }
    return {};
}

}  // namespace navmap::ipc
