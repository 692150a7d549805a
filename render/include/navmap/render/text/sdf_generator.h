// SPDX-License-Identifier: Apache-2.0
#pragma once
// Signed distance fields from high-resolution coverage bitmaps (Felzenszwalb-Huttenlocher
// exact Euclidean distance transform), for the SDF glyph atlas.

#include <cstdint>
#include <span>
#include <vector>

namespace navmap::render::text {

/// An 8-bit single-channel image, rows top to bottom, tightly packed.
struct GrayImage {
    int width = 0;
    int height = 0;
    std::vector<std::uint8_t> pixels;
};

/// Builds a signed distance field of `coverage` (width x height, pitch bytes per row, >= 128
/// counts as inside), downsampled by `downsample` (coverage width and height must be multiples
/// of it). Output texel = 0.5 + d / (2 * spread_px) in [0, 1] as a byte, d = signed distance of
/// the texel center to the shape edge in output pixels, positive inside. So inside > 127.5 >
/// outside and the edge is at 0.5; distances beyond +-spread_px saturate.
GrayImage makeSdf(std::span<const std::uint8_t> coverage, int width, int height, int pitch, int downsample,
                  float spread_px);

}  // namespace navmap::render::text
