// SPDX-License-Identifier: Apache-2.0
#pragma once
// A map scene over a compiled tile store: the store, its tile cache, the projection and the road
// graph, opened together (navmapd's map, the tools and the tests open their stores this way).

#include <cstddef>
#include <filesystem>
#include <memory>
#include <string>

#include "navmap/map/projection.h"
#include "navmap/map/road_graph.h"
#include "navmap/map/tile_cache.h"
#include "navmap/map/tile_store.h"

namespace navmap::map {

struct MapScene {
    std::shared_ptr<TileStore> store;
    std::shared_ptr<TileCache> cache;
    RoadGraph graph;  ///< empty when the store's graph is unavailable
    /// Why the road graph is unavailable ("checksum mismatch", "the store has none"); empty when
    /// it loaded. The map still renders; routing and map matching go without.
    std::string graph_problem;
    std::string graph_error;  ///< the same naming the file: "<store>: road graph: checksum mismatch"

    /// Opens a store (throws StoreError naming the file when its header or index is unusable)
    /// with a cache of `budget_bytes`. A damaged road graph is not fatal: graph_problem.
    static MapScene open(const std::filesystem::path& store_path, std::size_t budget_bytes = std::size_t{128} << 20);

    [[nodiscard]] Projection projection() const { return store->projection(); }
    [[nodiscard]] PlanarPoint toPlanar(double lat, double lon) const { return projection().forward(lat, lon); }
};

}  // namespace navmap::map
