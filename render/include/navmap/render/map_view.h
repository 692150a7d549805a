// SPDX-License-Identifier: Apache-2.0
#pragma once
// One display's view of a tile store: asks the tile cache for what a camera needs (level of
// detail by screen-space error, plus prefetch ahead), and builds the MapFrame to render from
// what is resident. Never waits for I/O: missing tiles are drawn from their parents.

#include <chrono>
#include <memory>

#include "navmap/map/tile_cache.h"
#include "navmap/map/tile_store.h"
#include "navmap/render/map_frame.h"
#include "navmap/render/terrain_lod.h"

namespace navmap::render {

class MapView {
public:
    /// The cache may be shared between the views of several displays.
    MapView(std::shared_ptr<map::TileCache> cache, LodOptions lod = {});

    /// Selects and requests tiles for `camera` and returns the frame's tile list.
    std::vector<std::shared_ptr<const map::Tile>> tilesFor(const Camera& camera, double aspect, int viewport_height);

    /// tilesFor(frame.camera) into frame.tiles, with each tile's geomorph ranges and targets (its
    /// resident ancestors) in frame.tile_morph (terrain_lod.h), so level switches do not pop.
    void select(MapFrame& frame, double aspect, int viewport_height);

    /// Requests tiles for `camera` until everything it wants is resident or `timeout` passes
    /// (warm-up, tests, benchmarks). Returns true when complete.
    bool warmUp(const Camera& camera, double aspect, int viewport_height, std::chrono::milliseconds timeout);

    /// Height of the finest resident terrain at a store-frame position (0 where none).
    [[nodiscard]] double terrainHeight(double x, double y) const;

    [[nodiscard]] const LodSelection& lastSelection() const { return m_last; }
    [[nodiscard]] map::TileCache& cache() { return *m_cache; }
    /// The cache's loader queue this view requests into (TileCache::request): views sharing a
    /// cache each take their own; lower numbers load first. Default 0.
    void setLoadQueue(int queue) { m_queue = queue; }

private:
    std::shared_ptr<map::TileCache> m_cache;
    int m_queue = 0;
    LodOptions m_lod;
    LodSelection m_last;
};

}  // namespace navmap::render
