// SPDX-License-Identifier: Apache-2.0
#include "navmap/map/tile_scheme.h"

#include <algorithm>
#include <cmath>

namespace navmap::map {

TileScheme::TileScheme(double root_min_x, double root_min_y, double root_size_m, int level_count)
    : m_min_x(root_min_x), m_min_y(root_min_y), m_size(root_size_m), m_levels(std::clamp(level_count, 1, 28)) {}

TileScheme::TileScheme(const Projection& frame, WorldTileId root, int level_count)
    : m_levels(std::clamp(level_count, 1, std::min(28, kMaxWorldZoom + 1 - root.z))), m_root(root) {
    const PlanarPoint sw = frame.fromMercator(root.southWest());
    m_min_x = sw.x;
    m_min_y = sw.y;
    m_size = root.size() / frame.scale();
}

TileScheme TileScheme::forData(const Projection& frame, double south, double west, double north, double east,
                               double leaf_size_m) {
    const int leaf_z = worldZoomForGroundSize(leaf_size_m, frame.originLat());
    const WorldTileId root = worldTileCovering(south, west, north, east, leaf_z);
    return TileScheme(frame, root, leaf_z - root.z + 1);
}

WorldTileId TileScheme::worldTile(TileId id) const {
    return {m_root.z + id.level, (m_root.x << id.level) + id.x, (m_root.y << id.level) + id.y};
}

std::optional<TileId> TileScheme::fromWorld(WorldTileId id) const {
    const int level = id.z - m_root.z;
    if (level < 0 || level >= m_levels || !m_root.contains(id)) return std::nullopt;
    const std::uint32_t mask = (std::uint32_t{1} << level) - 1;
    return TileId{static_cast<std::uint8_t>(level), id.x & mask, id.y & mask};
}

double TileScheme::tileSize(int level) const { return std::ldexp(m_size, -level); }

Box TileScheme::bounds(TileId id) const {
    const double s = tileSize(id.level);
    return {m_min_x + id.x * s, m_min_y + id.y * s, m_min_x + (id.x + 1) * s, m_min_y + (id.y + 1) * s};
}

bool TileScheme::valid(TileId id) const {
    if (id.level >= m_levels) return false;
    const std::uint64_t n = std::uint64_t{1} << id.level;
    return id.x < n && id.y < n;
}

std::optional<TileId> TileScheme::tileAt(int level, PlanarPoint p) const {
    if (level < 0 || level >= m_levels) return std::nullopt;
    const double s = tileSize(level);
    const double fx = std::floor((p.x - m_min_x) / s), fy = std::floor((p.y - m_min_y) / s);
    const double n = std::ldexp(1.0, level);
    if (fx < 0 || fy < 0 || fx >= n || fy >= n) return std::nullopt;
    return TileId{static_cast<std::uint8_t>(level), static_cast<std::uint32_t>(fx), static_cast<std::uint32_t>(fy)};
}

TileRange TileScheme::range(int level, const Box& box) const {
    TileRange r;
    if (level < 0 || level >= m_levels) return r;
    const double s = tileSize(level);
    const double n = std::ldexp(1.0, level);
    const double x0 = std::floor((box.min_x - m_min_x) / s), x1 = std::floor((box.max_x - m_min_x) / s);
    const double y0 = std::floor((box.min_y - m_min_y) / s), y1 = std::floor((box.max_y - m_min_y) / s);
    if (x1 < 0 || y1 < 0 || x0 >= n || y0 >= n || x0 > x1 || y0 > y1) return r;
    r.x0 = static_cast<std::uint32_t>(std::max(x0, 0.0));
    r.y0 = static_cast<std::uint32_t>(std::max(y0, 0.0));
    r.x1 = static_cast<std::uint32_t>(std::min(x1, n - 1));
    r.y1 = static_cast<std::uint32_t>(std::min(y1, n - 1));
    r.empty = false;
    return r;
}

int TileScheme::levelForTileSize(double size_m) const {
    for (int l = 0; l < m_levels; ++l) {
        if (tileSize(l) <= size_m) return l;
    }
    return m_levels - 1;
}

}  // namespace navmap::map
