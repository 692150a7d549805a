// SPDX-License-Identifier: Apache-2.0
#pragma once
// The raster layers of one tile from which its synthetic orthoimage is generated (seed 6.5:
// "rasterized georeferenced tiles, each containing disjoint, congruent data layers"), made by
// sampleOrthoLayers (map/compile: compile/ortho/ortho_preprocess.h) and kept in the tile store as
// plain bytes (tile_codec.h). Encodings in docs/orthoimage.md "Tile layers".

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

namespace navmap::map::ortho {

/// How many codes the class layers have; a stored tile with a larger code is refused. The
/// codes are SuperLandCover (super_land_cover.h) and ClimateClass (climate.h), which assert
/// these counts; the layers themselves are plain bytes.
inline constexpr int kCoverCodeCount = 21;
inline constexpr int kClimateCodeCount = 30;

struct OrthoLayers {
    /// Super land cover (SuperLandCover) on cover_size^2 texels spanning the tile square,
    /// texel (r, c) centred at local ((c + 0.5) * size / cover_size, (r + 0.5) * ...); row 0 south.
    std::uint16_t cover_size = 0;
    std::vector<std::uint8_t> cover;
    /// The other layers on grid_size^2 samples spanning the tile edge to edge like the DEM
    /// (sample (r, c) at local (c, r) * size / (grid_size - 1)), so tile borders match.
    std::uint16_t grid_size = 0;
    std::vector<std::uint8_t> climate;                 ///< ClimateClass of the nearest climate cell
    std::vector<std::uint8_t> temp_dec, temp_jul;      ///< temperatureFromCode()
    std::vector<std::uint8_t> precip_dec, precip_jul;  ///< precipitationFromCode()
    std::vector<std::uint8_t> lights;                  ///< city lights, code / 255
    std::vector<std::int16_t> elevation;  ///< metres; the region's DEM where it covers, else global (bathymetry < 0)
    std::vector<std::uint8_t> slope;      ///< degrees
    std::vector<std::uint8_t> aspect;     ///< downhill azimuth, code * 360 / 256 degrees clockwise from north

    [[nodiscard]] bool empty() const { return cover_size == 0; }
    [[nodiscard]] std::size_t byteSize() const {
        return cover.capacity() + climate.capacity() + temp_dec.capacity() + temp_jul.capacity() +
               precip_dec.capacity() + precip_jul.capacity() + lights.capacity() + 2 * elevation.capacity() +
               slope.capacity() + aspect.capacity();
    }
};

// Layer encodings.
inline float temperatureFromCode(std::uint8_t code) { return static_cast<float>(code) * 0.5f - 70.0f; }
inline std::uint8_t temperatureCode(float celsius) {
    return static_cast<std::uint8_t>(std::clamp(std::lround((celsius + 70.0f) * 2.0f), 0L, 255L));
}
inline float precipitationFromCode(std::uint8_t code) {
    const float v = static_cast<float>(code) / 255.0f;
    return 2048.0f * v * v;
}
inline std::uint8_t precipitationCode(float mm) {
    return static_cast<std::uint8_t>(
        std::clamp(std::lround(std::sqrt(std::max(mm, 0.0f) / 2048.0f) * 255.0f), 0L, 255L));
}

}  // namespace navmap::map::ortho
