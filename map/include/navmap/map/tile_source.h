// SPDX-License-Identifier: Apache-2.0
#pragma once
// What the tile cache and the renderer's tile selection read tiles from: one store
// (TileStore) or several stores mounted together in one frame (StoreSet).

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "navmap/map/tile.h"
#include "navmap/map/tile_scheme.h"

namespace navmap::map {

struct TileLoadResult {
    std::shared_ptr<const Tile> tile;  ///< null on error
    std::string error;                 ///< "<file>: tile L/X/Y: <problem>"
    bool missing = false;              ///< the source has no such tile (not an error)
};

class TileSource {
public:
    virtual ~TileSource() = default;
    /// The quadtree the tile ids are addresses in, in the source's frame.
    [[nodiscard]] virtual const TileScheme& scheme() const = 0;
    /// The tiles a traversal starts from: the scheme's root for one store; each store's root
    /// for a set of stores whose common root no store holds.
    [[nodiscard]] virtual std::vector<TileId> roots() const { return {TileId{}}; }
    [[nodiscard]] virtual bool contains(TileId id) const = 0;
    /// Reads one tile, in the source's frame. Thread-safe; never throws.
    [[nodiscard]] virtual TileLoadResult load(TileId id) const = 0;
    /// DEM samples per tile side (0: no DEM grids).
    [[nodiscard]] virtual std::uint32_t demSamples() const = 0;
};

}  // namespace navmap::map
