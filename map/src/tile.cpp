// SPDX-License-Identifier: Apache-2.0
#include "navmap/map/tile.h"

namespace navmap::map {

std::string TileId::toString() const {
    return std::to_string(level) + "/" + std::to_string(x) + "/" + std::to_string(y);
}

namespace {

std::size_t polygonBytes(const Polygon& p) {
    return p.vertices.capacity() * sizeof(LocalPoint) +
           (p.ring_ends.capacity() + p.indices.capacity()) * sizeof(std::uint32_t);
}

std::size_t stringBytes(const std::string& s) { return s.capacity() > 15 ? s.capacity() + 1 : 0; }

}  // namespace

std::size_t Tile::byteSize() const {
    std::size_t bytes = sizeof(Tile);
    bytes += roads.capacity() * sizeof(Road);
    for (const auto& r : roads)
        bytes += r.points.capacity() * sizeof(LocalPoint) + stringBytes(r.name) + stringBytes(r.ref);
    bytes += buildings.capacity() * sizeof(Building);
    for (const auto& b : buildings) bytes += polygonBytes(b.footprint);
    bytes += areas.capacity() * sizeof(Area);
    for (const auto& a : areas) bytes += polygonBytes(a.polygon) + stringBytes(a.name);
    bytes += labels.capacity() * sizeof(Label);
    for (const auto& l : labels) bytes += stringBytes(l.name);
    bytes += dem.heights.capacity() * sizeof(float);
    for (const auto& edge : dem.beyond) bytes += edge.capacity() * sizeof(float);
    bytes += ortho.byteSize();
    return bytes;
}

void attachDemBorders(Tile& tile, const std::function<std::shared_ptr<const Tile>(TileId)>& neighbour) {
    TileDem& dem = tile.dem;
    for (auto& edge : dem.beyond) edge.clear();
    const int n = dem.size;
    if (n < 3 || dem.heights.size() != static_cast<std::size_t>(n) * n) return;
    const TileId id = tile.id;
    auto take = [&](DemEdge edge, TileId across, int row, int col, int row_step, int col_step) {
        const std::shared_ptr<const Tile> other = neighbour(across);
        if (!other || other->dem.size != dem.size || other->dem.heights.size() != dem.heights.size()) return;
        std::vector<float>& out = dem.beyond[edge];
        out.resize(static_cast<std::size_t>(n));
        for (int i = 0; i < n; ++i)
            out[static_cast<std::size_t>(i)] = other->dem.at(row + i * row_step, col + i * col_step);
    };
    // The level's last index: a tile on the scheme's edge has no tile across it.
    const std::uint32_t last = id.level >= 32 ? ~std::uint32_t{0} : (std::uint32_t{1} << id.level) - 1;
    if (id.x > 0) take(kDemWest, {id.level, id.x - 1, id.y}, 0, n - 2, 1, 0);
    if (id.x < last) take(kDemEast, {id.level, id.x + 1, id.y}, 0, 1, 1, 0);
    if (id.y > 0) take(kDemSouth, {id.level, id.x, id.y - 1}, n - 2, 0, 0, 1);
    if (id.y < last) take(kDemNorth, {id.level, id.x, id.y + 1}, 1, 0, 0, 1);
}

}  // namespace navmap::map
