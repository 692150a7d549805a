// SPDX-License-Identifier: Apache-2.0
#include "navmap/map/guidance/way_names.h"

#include <unordered_set>

namespace navmap::map::guidance {

WayNames WayNames::alongRoute(const TileStore& store, std::span<const PlanarPoint> route) {
    WayNames names;
    const TileScheme& scheme = store.scheme();
    const int leaf = scheme.leafLevel();
    std::unordered_set<TileId, TileIdHash> seen;
    // Leaf tiles hold every road class (coarser levels drop minor roads). A route vertex lies in
    // every tile its segment touches except where a segment crosses a tile corner without a
    // vertex inside; the junction points manoeuvres need are vertices, so that loses nothing.
    for (const PlanarPoint& p : route) {
        const auto id = scheme.tileAt(leaf, p);
        if (!id || !seen.insert(*id).second || !store.contains(*id)) continue;
        TileStore::LoadResult r;
        const auto tile = store.loadAlone(*id, r);  // roads only: not the heights beyond its edges
        if (!tile) {
            if (!r.missing) {
                ++names.m_load_errors;
                names.m_last_error = r.error;
            }
            continue;
        }
        for (const Road& road : tile->roads) names.add(road.osm_id, road.name, road.ref);
    }
    return names;
}

void WayNames::add(std::int64_t way_id, std::string_view name, std::string_view ref) {
    if (!name.empty()) {
        m_names[way_id] = std::string(name);
    } else if (!ref.empty()) {
        m_names[way_id] = std::string(ref);
    }
}

std::string_view WayNames::lookup(std::int64_t way_id) const {
    const auto it = m_names.find(way_id);
    return it == m_names.end() ? std::string_view() : std::string_view(it->second);
}

}  // namespace navmap::map::guidance
