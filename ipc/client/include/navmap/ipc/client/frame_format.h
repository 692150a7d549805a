// SPDX-License-Identifier: Apache-2.0
#pragma once
// Pixel formats of streamed frames and the row conversions between them (docs/frame-protocol.md).

#include <cstdint>
#include <optional>
#include <string_view>

#include "navmap/ipc/net/client_api.h"

namespace navmap::ipc {

/// Wire value of a frame's pixel format. Rows are top to bottom; RGBA8 is R,G,B,A bytes;
/// RGB565 is a little-endian 16-bit word r<<11 | g<<5 | b.
enum class PixelFormat : std::uint32_t {
    Rgba8 = 1,
    Rgb565 = 2,
};

/// Bytes per pixel of a valid format, 0 for an unknown wire value.
NAVMAP_CLIENT_API int bytesPerPixel(PixelFormat format) noexcept;
/// "rgba8", "rgb565", or "unknown".
NAVMAP_CLIENT_API const char* pixelFormatName(PixelFormat format) noexcept;
/// Parses "rgba8" / "rgb565" (the handshake spelling).
NAVMAP_CLIENT_API std::optional<PixelFormat> parsePixelFormat(std::string_view name) noexcept;
/// True for a wire value this version knows.
NAVMAP_CLIENT_API bool isKnownPixelFormat(std::uint32_t value) noexcept;

/// Converts `width` RGBA8 pixels into `dst` in format `to` (to == Rgba8 copies).
NAVMAP_CLIENT_API void convertRowFromRgba(const std::uint8_t* rgba, PixelFormat to, std::uint8_t* dst,
                                          int width) noexcept;
/// Converts `width` pixels in format `from` into RGBA8 (alpha 255 for RGB565).
NAVMAP_CLIENT_API void convertRowToRgba(const std::uint8_t* src, PixelFormat from, std::uint8_t* rgba,
                                        int width) noexcept;

}  // namespace navmap::ipc
