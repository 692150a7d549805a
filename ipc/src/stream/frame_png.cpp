// SPDX-License-Identifier: Apache-2.0
#include "navmap/ipc/frame_png.h"

#include <zlib.h>

#include <cerrno>
#include <cstdio>
#include <cstring>

#include "navmap/ipc/net/sys_error.h"

namespace navmap::ipc {
namespace {

void putBe32(std::vector<std::uint8_t>& out, std::uint32_t v) {
    out.push_back(static_cast<std::uint8_t>(v >> 24));
    out.push_back(static_cast<std::uint8_t>(v >> 16));
    out.push_back(static_cast<std::uint8_t>(v >> 8));
    out.push_back(static_cast<std::uint8_t>(v));
}

void chunk(std::vector<std::uint8_t>& out, const char* type, const std::uint8_t* data, std::size_t n) {
    putBe32(out, static_cast<std::uint32_t>(n));
    const std::size_t start = out.size();
    out.insert(out.end(), type, type + 4);
    if (n > 0) {
        out.insert(out.end(), data, data + n);
    }
    const uLong crc = crc32(0L, out.data() + start, static_cast<uInt>(n + 4));
    putBe32(out, static_cast<std::uint32_t>(crc));
}

}  // namespace

std::vector<std::uint8_t> encodeFramePng(const FrameHeader& header, const std::uint8_t* pixels) {
    const std::size_t w = header.width;
    const std::size_t h = header.height;
    // Filter byte 0 (none) per row, then RGBA8.
    std::vector<std::uint8_t> raw((w * 4 + 1) * h);
    for (std::size_t y = 0; y < h; ++y) {
        std::uint8_t* row = raw.data() + y * (w * 4 + 1);
        row[0] = 0;
        convertRowToRgba(pixels + y * header.stride, header.format, row + 1, static_cast<int>(w));
    }
    uLongf zlen = compressBound(static_cast<uLong>(raw.size()));
    std::vector<std::uint8_t> z(zlen);
    compress2(z.data(), &zlen, raw.data(), static_cast<uLong>(raw.size()), 3);
    z.resize(zlen);

    std::vector<std::uint8_t> out = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1A, '\n'};
    std::vector<std::uint8_t> ihdr;
    putBe32(ihdr, static_cast<std::uint32_t>(w));
    putBe32(ihdr, static_cast<std::uint32_t>(h));
    ihdr.insert(ihdr.end(), {8, 6, 0, 0, 0});  // 8 bits, RGBA, deflate, no filter set, no interlace
    chunk(out, "IHDR", ihdr.data(), ihdr.size());
    chunk(out, "IDAT", z.data(), z.size());
    chunk(out, "IEND", nullptr, 0);
    return out;
}

Status writeFramePng(const std::string& path, const FrameHeader& header, const std::uint8_t* pixels) {
    const auto png = encodeFramePng(header, pixels);
    std::FILE* f = std::fopen(path.c_str(), "wb");
    if (f == nullptr) {
        return Error{net::sysError("fopen", path)};
    }
    const bool ok = std::fwrite(png.data(), 1, png.size(), f) == png.size();
    const int err = errno;
    if (std::fclose(f) != 0 || !ok) {
        return Error{net::sysError("write", path, ok ? errno : err)};
    }
    return {};
}

}  // namespace navmap::ipc
