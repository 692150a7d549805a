// SPDX-License-Identifier: Apache-2.0
#pragma once
// frameBlit(): the one copy of a streamed frame into a display buffer of navmap-wayland
// (docs/wayland.md). The frame (RGBA8 or RGB565, as navmapd sends it) lands in a wl_shm buffer
// of the window's size in a wl_shm format: same size, it is copied row by row (a plain memcpy
// where the formats agree); another size, it is scaled to fit (nearest neighbour, aspect ratio
// kept) and centred on black. Pure memory work: no Wayland call, no allocation.

#include <cstddef>
#include <cstdint>

#include "navmap/ipc/client/frame_format.h"

namespace navmap::ipc::wayland {

/// The wl_shm formats a frame is written in (values are not wl_shm's enum: no Wayland header here).
enum class ShmFormat {
    Xrgb8888,  ///< 32-bit word 0xXXRRGGBB, little-endian: bytes B,G,R,X (every compositor has it)
    Xbgr8888,  ///< bytes R,G,B,X: an RGBA8 frame's rows copied as they are
    Rgb565,    ///< 16-bit word r<<11 | g<<5 | b: an RGB565 frame's rows copied as they are
};

int shmBytesPerPixel(ShmFormat format) noexcept;
const char* shmFormatName(ShmFormat format) noexcept;

/// The buffer format for frames in `stream`: the one that needs no conversion when the
/// compositor offers it, else XRGB8888.
ShmFormat chooseShmFormat(PixelFormat stream, bool has_xbgr8888, bool has_rgb565) noexcept;

/// Pixels of a frame as received: `stride` bytes per row, rows top to bottom.
struct SourcePixels {
    const std::uint8_t* pixels = nullptr;
    int width = 0;
    int height = 0;
    std::size_t stride = 0;
    PixelFormat format = PixelFormat::Rgba8;
};

/// A display buffer: `stride` bytes per row.
struct TargetPixels {
    std::uint8_t* pixels = nullptr;
    int width = 0;
    int height = 0;
    std::size_t stride = 0;
    ShmFormat format = ShmFormat::Xrgb8888;
};

/// Where a frame of one size lands in a buffer of another: the largest rectangle of the frame's
/// aspect ratio that fits, centred (the left and top margins round down). Equal sizes: all of it.
struct Placement {
    int x = 0;
    int y = 0;
    int width = 0;
    int height = 0;
    bool scaled = false;  ///< the frame's size is not the buffer's
};
Placement fitCentred(int src_width, int src_height, int dst_width, int dst_height) noexcept;

/// Writes `src` into `dst` at fitCentred() (target pixel (x, y) of the placement shows source
/// pixel (floor((x + 0.5) * src_w / w), floor((y + 0.5) * src_h / h))) and paints the margins
/// black. Returns the placement.
Placement blitFrame(const SourcePixels& src, const TargetPixels& dst) noexcept;

/// Paints all of `dst` black (the window before its first frame).
void clearTarget(const TargetPixels& dst) noexcept;

}  // namespace navmap::ipc::wayland
