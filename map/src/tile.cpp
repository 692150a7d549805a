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
    bytes += ortho.byteSize();
    return bytes;
}

}  // namespace navmap::map
