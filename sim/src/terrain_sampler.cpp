// SPDX-License-Identifier: Apache-2.0
#include "navmap/sim/terrain_sampler.h"

#include <algorithm>
#include <cmath>

namespace navmap::sim {

TerrainSampler::TerrainSampler(std::shared_ptr<const map::TileStore> store) : m_store(std::move(store)) {}

double TerrainSampler::heightAt(map::PlanarPoint p) {
    if (!m_store) return 0.0;
    const auto id = m_store->scheme().tileAt(m_store->scheme().leafLevel(), p);
    if (!id) return 0.0;
    auto it = m_tiles.find(id->key());
    if (it == m_tiles.end()) {
        if (m_tiles.size() >= 16) m_tiles.clear();  // a drive crosses few leaf tiles; keep it simple
        auto loaded = m_store->load(*id);
        it = m_tiles.emplace(id->key(), loaded.tile).first;  // null (missing/broken) is cached too
    }
    const auto& tile = it->second;
    if (!tile || tile->dem.size < 2 || tile->dem.spacing_m <= 0.0f) return 0.0;
    const map::TileDem& dem = tile->dem;
    const double n = dem.size - 1;
    const double c = std::clamp((p.x - tile->origin_x) / dem.spacing_m, 0.0, n);
    const double r = std::clamp((p.y - tile->origin_y) / dem.spacing_m, 0.0, n);
    const int c0 = std::min(static_cast<int>(c), dem.size - 2);
    const int r0 = std::min(static_cast<int>(r), dem.size - 2);
    const double fc = c - c0;
    const double fr = r - r0;
    const double h0 = dem.at(r0, c0) * (1 - fc) + dem.at(r0, c0 + 1) * fc;
    const double h1 = dem.at(r0 + 1, c0) * (1 - fc) + dem.at(r0 + 1, c0 + 1) * fc;
    return h0 * (1 - fr) + h1 * fr;
}

}  // namespace navmap::sim
