// SPDX-License-Identifier: Apache-2.0
#include "synthetic_tile.h"

#include <utility>

namespace navmap::test {

std::shared_ptr<map::Tile> makeTile(const std::function<float(float, float)>& height, int dem) {
    auto tile = std::make_shared<map::Tile>();
    tile->id = {10, 5, 7};
    tile->origin_x = 20000.0;
    tile->origin_y = -15000.0;
    tile->size_m = 1000.0;
    tile->dem.size = static_cast<std::uint16_t>(dem);
    tile->dem.spacing_m = 1000.0f / static_cast<float>(dem - 1);
    tile->dem.coverage = 1.0f;
    for (int r = 0; r < dem; ++r)
        for (int c = 0; c < dem; ++c)
            tile->dem.heights.push_back(
                height(static_cast<float>(c) * tile->dem.spacing_m, static_cast<float>(r) * tile->dem.spacing_m));
    return tile;
}

map::Road road(map::RoadClass cls, std::vector<map::LocalPoint> points) {
    map::Road r;
    r.cls = cls;
    r.points = std::move(points);
    return r;
}

}  // namespace navmap::test
