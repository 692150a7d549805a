// SPDX-License-Identifier: Apache-2.0
#pragma once
// High-resolution terrain from a coarse DEM (issue #8, seed 3.7): a tile's DEM resampled
// bicubically to a fine spacing (about 10 m instead of the store's 62.5 m) with deterministic
// fractal detail added, so the terrain has the small-scale relief of a LiDAR-class DEM. Used to
// show where geometric road draping fails and shadow-volume roads still drape pixel-exactly.
// GL-free.

#include <cstdint>
#include <memory>

#include "navmap/map/tile.h"

namespace navmap::render {

struct DemRefineOptions {
    double spacing_m = 10.0;             ///< target sample spacing (the grid spans the tile edge to edge)
    float detail_amplitude_m = 4.0f;     ///< amplitude of the largest detail octave; each next one halves
    double detail_wavelength_m = 120.0;  ///< wavelength of the largest detail octave; each next one halves
    int detail_octaves = 4;
    std::uint32_t seed = 1;  ///< same seed, same detail (value noise on a hashed lattice)
};

/// Resamples `coarse` (a tile DEM spanning `tile_size_m`) with Catmull-Rom bicubic interpolation
/// to about options.spacing_m and adds fractal value noise in store-frame coordinates (`origin_x`,
/// `origin_y`: the tile's south-west corner), so neighbouring tiles get the same detail on their
/// shared border. Coverage is kept. A DEM without samples comes back unchanged.
map::TileDem refineDem(const map::TileDem& coarse, double tile_size_m, double origin_x, double origin_y,
                       const DemRefineOptions& options = {});

/// A copy of `tile` whose DEM is refined with refineDem.
std::shared_ptr<map::Tile> refineTile(const map::Tile& tile, const DemRefineOptions& options = {});

/// The fractal detail alone at store-frame (x, y), metres (what refineDem adds).
double demDetail(double x, double y, const DemRefineOptions& options);

}  // namespace navmap::render
