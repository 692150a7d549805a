// SPDX-License-Identifier: Apache-2.0
#include "frame_blit.h"

#include <algorithm>
#include <cstring>

namespace navmap::ipc::wayland {

namespace {

struct Rgb {
    std::uint8_t r = 0, g = 0, b = 0;
};

// Source pixel `x` of a row in `format`; RGB565 widened as convertRowToRgba() does (0x1F -> 255).
inline Rgb readPixel(const std::uint8_t* row, PixelFormat format, int x) noexcept {
    if (format == PixelFormat::Rgb565) {
        const auto v = static_cast<unsigned>(row[2 * x] | (row[2 * x + 1] << 8));
        const unsigned r = (v >> 11) & 0x1F, g = (v >> 5) & 0x3F, b = v & 0x1F;
        return {static_cast<std::uint8_t>((r << 3) | (r >> 2)), static_cast<std::uint8_t>((g << 2) | (g >> 4)),
                static_cast<std::uint8_t>((b << 3) | (b >> 2))};
    }
    const std::uint8_t* p = row + static_cast<std::size_t>(x) * 4;
    return {p[0], p[1], p[2]};
}

inline void writePixel(std::uint8_t* row, ShmFormat format, int x, Rgb c) noexcept {
    switch (format) {
        case ShmFormat::Xrgb8888: {
            std::uint8_t* p = row + static_cast<std::size_t>(x) * 4;
            p[0] = c.b, p[1] = c.g, p[2] = c.r, p[3] = 0xFF;
            return;
        }
        case ShmFormat::Xbgr8888: {
            std::uint8_t* p = row + static_cast<std::size_t>(x) * 4;
            p[0] = c.r, p[1] = c.g, p[2] = c.b, p[3] = 0xFF;
            return;
        }
        case ShmFormat::Rgb565: {
            const auto v = static_cast<std::uint16_t>(((c.r & 0xF8U) << 8) | ((c.g & 0xFCU) << 3) | (c.b >> 3));
            std::memcpy(row + static_cast<std::size_t>(x) * 2, &v, 2);
            return;
        }
    }
}

// The formats whose rows are byte for byte the same.
bool sameLayout(PixelFormat src, ShmFormat dst) noexcept {
    return (src == PixelFormat::Rgba8 && dst == ShmFormat::Xbgr8888) ||
           (src == PixelFormat::Rgb565 && dst == ShmFormat::Rgb565);
}

void blackRows(const TargetPixels& dst, int y0, int y1) noexcept {
    const std::size_t row_bytes = static_cast<std::size_t>(dst.width) * shmBytesPerPixel(dst.format);
    for (int y = y0; y < y1; ++y) {
        std::uint8_t* row = dst.pixels + static_cast<std::size_t>(y) * dst.stride;
        if (dst.format == ShmFormat::Rgb565) {
            std::memset(row, 0, row_bytes);
        } else {
            for (int x = 0; x < dst.width; ++x) writePixel(row, dst.format, x, Rgb{});
        }
    }
}

}  // namespace

int shmBytesPerPixel(ShmFormat format) noexcept { return format == ShmFormat::Rgb565 ? 2 : 4; }

const char* shmFormatName(ShmFormat format) noexcept {
    switch (format) {
        case ShmFormat::Xrgb8888: return "XRGB8888";
        case ShmFormat::Xbgr8888: return "XBGR8888";
        case ShmFormat::Rgb565: return "RGB565";
    }
    return "?";
}

ShmFormat chooseShmFormat(PixelFormat stream, bool has_xbgr8888, bool has_rgb565) noexcept {
    if (stream == PixelFormat::Rgba8 && has_xbgr8888) return ShmFormat::Xbgr8888;
    if (stream == PixelFormat::Rgb565 && has_rgb565) return ShmFormat::Rgb565;
    return ShmFormat::Xrgb8888;
}

Placement fitCentred(int src_width, int src_height, int dst_width, int dst_height) noexcept {
    Placement p;
    if (src_width == dst_width && src_height == dst_height) {
        p.width = dst_width;
        p.height = dst_height;
        return p;
    }
    p.scaled = true;
    if (src_width <= 0 || src_height <= 0) return p;
    // Compare dst_w / src_w with dst_h / src_h without division: the smaller scale wins.
    const auto wide = static_cast<std::int64_t>(dst_width) * src_height;
    const auto tall = static_cast<std::int64_t>(dst_height) * src_width;
    if (wide <= tall) {
        p.width = dst_width;
        p.height = static_cast<int>(std::max<std::int64_t>(1, wide / src_width));
    } else {
        p.width = static_cast<int>(std::max<std::int64_t>(1, tall / src_height));
        p.height = dst_height;
    }
    p.x = (dst_width - p.width) / 2;
    p.y = (dst_height - p.height) / 2;
    return p;
}

Placement blitFrame(const SourcePixels& src, const TargetPixels& dst) noexcept {
    const Placement p = fitCentred(src.width, src.height, dst.width, dst.height);
    if (!p.scaled && sameLayout(src.format, dst.format)) {
        const std::size_t row_bytes = static_cast<std::size_t>(dst.width) * shmBytesPerPixel(dst.format);
        for (int y = 0; y < dst.height; ++y) {
            std::memcpy(dst.pixels + static_cast<std::size_t>(y) * dst.stride,
                        src.pixels + static_cast<std::size_t>(y) * src.stride, row_bytes);
        }
        return p;
    }
    blackRows(dst, 0, p.y);
    for (int y = 0; y < p.height; ++y) {
        // floor((y + 0.5) * src_h / h) in integers
        const auto sy = static_cast<int>((2 * static_cast<std::int64_t>(y) + 1) * src.height / (2 * p.height));
        const std::uint8_t* in = src.pixels + static_cast<std::size_t>(sy) * src.stride;
        std::uint8_t* out = dst.pixels + static_cast<std::size_t>(p.y + y) * dst.stride;
        for (int x = 0; x < p.x; ++x) writePixel(out, dst.format, x, Rgb{});
        for (int x = 0; x < p.width; ++x) {
            const auto sx = static_cast<int>((2 * static_cast<std::int64_t>(x) + 1) * src.width / (2 * p.width));
            writePixel(out, dst.format, p.x + x, readPixel(in, src.format, sx));
        }
        for (int x = p.x + p.width; x < dst.width; ++x) writePixel(out, dst.format, x, Rgb{});
    }
    blackRows(dst, p.y + p.height, dst.height);
    return p;
}

void clearTarget(const TargetPixels& dst) noexcept { blackRows(dst, 0, dst.height); }

}  // namespace navmap::ipc::wayland
