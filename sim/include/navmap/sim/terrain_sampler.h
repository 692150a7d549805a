// SPDX-License-Identifier: Apache-2.0
#pragma once
// Terrain height from the store's leaf-tile DEM grids (bilinear), for NAV_Altitude. Keeps the
// last few tiles; a position without DEM (or a tile that fails to load) gives 0 m.
// Not thread-safe (one generator owns it).

#include <cstdint>
#include <memory>
#include <unordered_map>

#include "navmap/map/tile_store.h"

namespace navmap::sim {

class TerrainSampler {
public:
    explicit TerrainSampler(std::shared_ptr<const map::TileStore> store);
    /// Metres above sea level at a store-frame position.
    double heightAt(map::PlanarPoint p);

private:
    std::shared_ptr<const map::TileStore> m_store;
    std::unordered_map<std::uint64_t, std::shared_ptr<const map::Tile>> m_tiles;
};

}  // namespace navmap::sim
