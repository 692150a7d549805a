// SPDX-License-Identifier: Apache-2.0
#pragma once
// Pre-processing of the global orthoimage inputs onto the store's tiles (seed 6.5): a tile's
// OrthoLayers are the global rasters sampled at the tile's texels and samples, the land
// cover unified into the super land cover with the region's own OSM areas where they lie, and
// elevation, slope and aspect from the region's DEM where it covers the tile.

#include <cstdint>

#include <vector>

#include "navmap/map/compile/ortho/global_inputs.h"
#include "navmap/map/ortho/ortho_layers.h"
#include "navmap/map/projection.h"
#include "navmap/map/tile.h"

namespace navmap::map::ortho {

/// Texels per side of the stored super land cover (8 m on the 2 km leaf tiles) and samples per
/// side of the other layers (as the DEM: 62.5 m on the leaf tiles).
inline constexpr int kOrthoCoverSize = 256;
inline constexpr int kOrthoGridSize = 33;

/// The tile's layers from the inputs; `proj` is the store's projection. Uses the tile's areas and
/// DEM.
OrthoLayers sampleOrthoLayers(const Tile& tile, const GlobalInputs& inputs, const Projection& proj,
                              int cover_size = kOrthoCoverSize, int grid_size = kOrthoGridSize);

/// Rasterizes the tile's OSM areas at texel centres into `cover` (cover_size^2, row 0 south):
/// SuperLandCover + 1 where an area lies, 0 elsewhere.
void rasterizeAreas(const Tile& tile, int cover_size, std::vector<std::uint8_t>& cover);

}  // namespace navmap::map::ortho
