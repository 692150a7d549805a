// SPDX-License-Identifier: Apache-2.0
#pragma once
// A tile with hand-made orthoimage layers (seed 6.5) for the tests of the orthoimage inputs and
// of its generation on the GPU: the default store is compiled without the layers.

#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>

#include "navmap/map/ortho/climate.h"
#include "navmap/map/ortho/ortho_layers.h"
#include "navmap/map/ortho/super_land_cover.h"
#include "navmap/map/tile.h"

namespace navmap::test {

/// Orthoimage layers over a tile square of `size_m`: land cover cover(x, y) (tile-local metres) on
/// 256 x 256 texels, elevation height(x, y) on 33 x 33 samples; climate Cfb, December 2 C, July
/// 18 C, 80 mm of rain each month, no lights.
inline map::ortho::OrthoLayers orthoLayers(double size_m,
                                           const std::function<map::ortho::SuperLandCover(double, double)>& cover,
                                           const std::function<float(double, double)>& height) {
    namespace mo = map::ortho;
    mo::OrthoLayers o;
    constexpr int kCover = 256, kGrid = 33;
    o.cover_size = kCover;
    o.grid_size = kGrid;
    o.cover.resize(std::size_t{kCover} * kCover);
    for (int r = 0; r < kCover; ++r) {
        for (int c = 0; c < kCover; ++c) {
            o.cover[static_cast<std::size_t>(r * kCover + c)] =
                static_cast<std::uint8_t>(cover((c + 0.5) * size_m / kCover, (r + 0.5) * size_m / kCover));
        }
    }
    const std::size_t n = std::size_t{kGrid} * kGrid;
    o.climate.assign(n, static_cast<std::uint8_t>(mo::ClimateClass::Cfb));
    o.temp_dec.assign(n, mo::temperatureCode(2.0f));
    o.temp_jul.assign(n, mo::temperatureCode(18.0f));
    o.precip_dec.assign(n, mo::precipitationCode(80.0f));
    o.precip_jul.assign(n, mo::precipitationCode(80.0f));
    o.lights.assign(n, 0);
    o.slope.assign(n, 0);
    o.aspect.assign(n, 0);
    o.elevation.resize(n);
    const double spacing = size_m / (kGrid - 1);
    for (int r = 0; r < kGrid; ++r) {
        for (int c = 0; c < kGrid; ++c)
            o.elevation[static_cast<std::size_t>(r * kGrid + c)] =
                static_cast<std::int16_t>(height(c * spacing, r * spacing));
    }
    return o;
}

/// Tile 6/33/17 at (4000, -2000), `size_m` across, with orthoLayers() and no DEM of its own.
inline std::shared_ptr<map::Tile> orthoTile(const std::function<map::ortho::SuperLandCover(double, double)>& cover,
                                            const std::function<float(double, double)>& height,
                                            double size_m = 2000.0) {
    auto t = std::make_shared<map::Tile>();
    t->id = {6, 33, 17};
    t->origin_x = 4000;
    t->origin_y = -2000;
    t->size_m = size_m;
    t->ortho = orthoLayers(size_m, cover, height);
    return t;
}

}  // namespace navmap::test
