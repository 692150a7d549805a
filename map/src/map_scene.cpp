// SPDX-License-Identifier: Apache-2.0
#include "navmap/map/map_scene.h"

#include <algorithm>
#include <cmath>

namespace navmap::map {

MapScene MapScene::open(const std::filesystem::path& store_path, std::size_t budget_bytes) {
    return open(std::vector<std::filesystem::path>{store_path}, budget_bytes);
}

MapScene MapScene::open(const std::vector<std::filesystem::path>& store_paths, std::size_t budget_bytes) {
    if (store_paths.empty()) throw StoreError("no store to open");
    MapScene s;
    s.store = TileStore::open(store_paths.front());
    std::shared_ptr<const TileSource> source = s.store;
    if (store_paths.size() > 1) {
        std::vector<std::shared_ptr<const TileStore>> stores{s.store};
        for (std::size_t i = 1; i < store_paths.size(); ++i) stores.push_back(TileStore::open(store_paths[i]));
        s.set = StoreSet::mount(std::move(stores), s.store->projection());
        source = s.set;
    }
    TileCacheOptions options;
    options.budget_bytes = budget_bytes;
    s.cache = std::make_shared<TileCache>(source, options);
    auto graph = s.store->tryLoadGraph();
    s.graph = std::move(graph.graph);
    s.graph_problem = std::move(graph.problem);
    s.graph_error = std::move(graph.error);
    return s;
}

double MapScene::reachM() const { return set ? reachM(projection()) : 0.0; }

double MapScene::reachM(const Projection& frame) const {
    double reach = 0.0;
    const std::size_t stores = set ? set->storeCount() : 1;
    for (std::size_t i = 0; i < stores; ++i) {
        const StoreInfo& info = set ? set->store(i).info() : store->info();
        for (const double lat : {info.south, info.north}) {
            for (const double lon : {info.west, info.east}) {
                const PlanarPoint p = frame.forward(lat, lon);
                reach = std::max(reach, std::hypot(p.x, p.y));
            }
        }
    }
    return reach;
}

}  // namespace navmap::map
