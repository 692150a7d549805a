// SPDX-License-Identifier: Apache-2.0
#include "navmap/render/map_view.h"

#include <thread>

#include "road_draping.h"

namespace navmap::render {

MapView::MapView(std::shared_ptr<map::TileCache> cache, LodOptions lod) : m_cache(std::move(cache)), m_lod(lod) {
    if (m_cache->source().demSamples() >= 2) m_lod.dem_samples = static_cast<int>(m_cache->source().demSamples());
}

std::vector<std::shared_ptr<const map::Tile>> MapView::tilesFor(const Camera& camera, double aspect,
                                                                int viewport_height) {
    const map::TileSource& source = m_cache->source();
    m_last = selectLod(
        source.scheme(), camera, aspect, viewport_height, [&](map::TileId id) { return source.contains(id); },
        [&](map::TileId id) { return m_cache->find(id); }, m_lod, source.roots());
    // Keep what is drawn fresh in the LRU and queue what is missing, drawn tiles first.
    std::vector<map::TileRequest> requests;
    requests.reserve(m_last.draw.size() + m_last.wanted.size());
    for (const auto& t : m_last.draw) requests.push_back({t->id, 1e6f});
    requests.insert(requests.end(), m_last.wanted.begin(), m_last.wanted.end());
    (void)m_cache->request(requests, m_queue);
    return m_last.draw;
}

void MapView::select(MapFrame& frame, double aspect, int viewport_height) {
    frame.tiles = tilesFor(frame.camera, aspect, viewport_height);
    frame.tile_morph = m_last.morph;
}

bool MapView::warmUp(const Camera& camera, double aspect, int viewport_height, std::chrono::milliseconds timeout) {
    const auto deadline = std::chrono::steady_clock::now() + timeout;
    while (std::chrono::steady_clock::now() < deadline) {
        (void)tilesFor(camera, aspect, viewport_height);
        if (m_last.wanted.empty()) return true;
        (void)m_cache->waitIdle(std::chrono::milliseconds(200));
    }
    return false;
}

double MapView::terrainHeight(double x, double y) const {
    const map::TileScheme& scheme = m_cache->source().scheme();
    for (int level = scheme.leafLevel(); level >= 0; --level) {
        const auto id = scheme.tileAt(level, {x, y});
        if (!id) return 0.0;
        const auto tile = m_cache->find(*id);
        if (!tile || tile->dem.size < 2) continue;
        const HeightGrid grid{tile->dem.size, tile->size_m / (tile->dem.size - 1), tile->dem.heights.data()};
        return grid.heightAt(x - tile->origin_x, y - tile->origin_y);
    }
    return 0.0;
}

}  // namespace navmap::render
