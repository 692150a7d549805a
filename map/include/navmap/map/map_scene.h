// SPDX-License-Identifier: Apache-2.0
#pragma once
// A map scene over compiled tile stores: the first store (its frame and road graph), the tiles of
// every store mounted together, their tile cache, opened together (navmapd's map, the tools and
// the tests open their stores this way).

#include <cstddef>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "navmap/map/projection.h"
#include "navmap/map/road_graph.h"
#include "navmap/map/store_set.h"
#include "navmap/map/tile_cache.h"
#include "navmap/map/tile_store.h"

namespace navmap::map {

struct MapScene {
    std::shared_ptr<TileStore> store;  ///< the first store: the scene's frame and road graph
    /// Every store, mounted in the first store's frame; null with one store (the cache then reads
    /// `store` itself).
    std::shared_ptr<StoreSet> set;
    std::shared_ptr<TileCache> cache;
    RoadGraph graph;  ///< empty when the store's graph is unavailable
    /// Why the road graph is unavailable ("checksum mismatch", "the store has none"); empty when
    /// it loaded. The map still renders; routing and map matching go without.
    std::string graph_problem;
    std::string graph_error;  ///< the same naming the file: "<store>: road graph: checksum mismatch"

    /// Opens a store (throws StoreError naming the file when its header or index is unusable)
    /// with a cache of `budget_bytes`. A damaged road graph is not fatal: graph_problem.
    static MapScene open(const std::filesystem::path& store_path, std::size_t budget_bytes = std::size_t{128} << 20);
    /// Opens and mounts several stores (StoreSet; throws StoreError naming the store that cannot
    /// be opened or mounted). The road graph is the first store's.
    static MapScene open(const std::vector<std::filesystem::path>& store_paths,
                         std::size_t budget_bytes = std::size_t{128} << 20);
    /// The source the cache reads: the set, or the one store.
    [[nodiscard]] const TileSource& tiles() const { return set ? static_cast<const TileSource&>(*set) : *store; }

    [[nodiscard]] Projection projection() const { return store->projection(); }
    /// How far the mounted stores reach from the frame's origin: the farthest corner of any
    /// store's data box, in frame metres (0 with one store: its own data is near its origin).
    [[nodiscard]] double reachM() const;
    /// How far the mounted stores reach from `frame`'s origin (any frame: the daemon re-centres
    /// its frame on the vehicle): the farthest corner of any store's data box, in metres.
    [[nodiscard]] double reachM(const Projection& frame) const;
    [[nodiscard]] PlanarPoint toPlanar(double lat, double lon) const { return projection().forward(lat, lon); }
};

}  // namespace navmap::map
