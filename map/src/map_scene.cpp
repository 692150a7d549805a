// SPDX-License-Identifier: Apache-2.0
#include "navmap/map/map_scene.h"

namespace navmap::map {

MapScene MapScene::open(const std::filesystem::path& store_path, std::size_t budget_bytes) {
    MapScene s;
    s.store = TileStore::open(store_path);
    TileCacheOptions options;
    options.budget_bytes = budget_bytes;
    s.cache = std::make_shared<TileCache>(s.store, options);
    auto graph = s.store->tryLoadGraph();
    s.graph = std::move(graph.graph);
    s.graph_problem = std::move(graph.problem);
    s.graph_error = std::move(graph.error);
    return s;
}

}  // namespace navmap::map
