// SPDX-License-Identifier: Apache-2.0
#pragma once
// Hand-made map tiles for renderer tests: a 1 km tile away from the store origin (so
// camera-relative rendering matters) with a DEM from a height function, and roads.

#include <functional>
#include <memory>
#include <vector>

#include "navmap/map/tile.h"

namespace navmap::test {

/// Tile 10/5/7 at (20000, -15000), 1000 m across, `dem` x `dem` samples of height(x, y)
/// (tile-local metres).
std::shared_ptr<map::Tile> makeTile(const std::function<float(float, float)>& height, int dem = 33);

map::Road road(map::RoadClass cls, std::vector<map::LocalPoint> points);

}  // namespace navmap::test
