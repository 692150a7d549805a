// SPDX-License-Identifier: Apache-2.0
// TerrainHorizon (MapLayers::cull_hidden_roads): a box is called hidden only if every line of
// sight to it passes below the drawn terrain first.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <numbers>
#include <random>
#include <vector>

#include "terrain_horizon.h"

namespace {

using navmap::render::TerrainFloor;
using navmap::render::terrainFloor;
using navmap::render::TerrainHorizon;

constexpr int kGrid = 101;        // vertices per side
constexpr double kSize = 2000.0;  // metres: 20 m between vertices

// A tile at `origin` whose vertex heights come from f(x, y) (store frame).
TerrainFloor tile(glm::dvec2 origin, const std::function<double(double, double)>& f) {
    std::vector<float> heights(kGrid * kGrid);
    const double spacing = kSize / (kGrid - 1);
    for (int r = 0; r < kGrid; ++r) {
        for (int c = 0; c < kGrid; ++c)
            heights[static_cast<std::size_t>(r * kGrid + c)] = float(f(origin.x + c * spacing, origin.y + r * spacing));
    }
    return terrainFloor(origin, kSize, kGrid, heights, {});
}

// Looking north from (1000, 100), 50 m above flat ground at 0 m.
constexpr glm::dvec3 kEye{1000.0, 100.0, 50.0};
constexpr double kKeep = 0.98;

TerrainHorizon horizonOver(const std::vector<const TerrainFloor*>& floors, double ground_m = 0.0) {
    TerrainHorizon h;
    const double north = 0.5 * std::numbers::pi;
    h.build(kEye, ground_m, floors, north - 1.0, north + 1.0, 200, 6000.0);
    return h;
}

// A ridge 100 m high along y = 600..800, except where `notch` says. (The lines of sight are
// sampled 10 % of their length apart: a much thinner wall can fall between two samples, and is
// then not counted, which only hides less.)
std::function<double(double, double)> wall(const std::function<bool(double)>& notch = [](double) { return false; }) {
    return [notch](double x, double y) { return y >= 600.0 && y <= 800.0 && !notch(x) ? 100.0 : 0.0; };
}

const glm::dvec3 kBehindLo{950.0, 1500.0, 0.0}, kBehindHi{1050.0, 1600.0, 5.0};

TEST(TerrainHorizon, AWallHidesWhatLiesLowBehindIt) {
    const TerrainFloor f = tile({0.0, 0.0}, wall());
    const TerrainHorizon h = horizonOver({&f});
    ASSERT_FALSE(h.empty());
    EXPECT_TRUE(h.hides(kBehindLo, kBehindHi, kKeep));
    // What rises above the line of sight over the wall's top, or lies before the wall, shows.
    EXPECT_FALSE(h.hides(kBehindLo, {1050.0, 1600.0, 400.0}, kKeep));
    EXPECT_FALSE(h.hides({950.0, 300.0, 0.0}, {1050.0, 400.0, 5.0}, kKeep));
    // Off to the side, outside the horizon's azimuths: nothing is known there.
    EXPECT_FALSE(h.hides({3000.0, 50.0, 0.0}, {3100.0, 150.0, 5.0}, kKeep));
}

TEST(TerrainHorizon, FlatGroundHidesNothing) {
    const TerrainFloor f = tile({0.0, 0.0}, [](double, double) { return 0.0; });
    EXPECT_FALSE(horizonOver({&f}).hides(kBehindLo, kBehindHi, kKeep));
}

TEST(TerrainHorizon, ANotchInTheWallLetsTheBoxShow) {
    const TerrainFloor f = tile({0.0, 0.0}, wall([](double x) { return x > 970.0 && x < 1030.0; }));
    EXPECT_FALSE(horizonOver({&f}).hides(kBehindLo, kBehindHi, kKeep));
    // A box whose lines of sight all miss the notch stays hidden.
    EXPECT_TRUE(horizonOver({&f}).hides({1400.0, 1500.0, 0.0}, {1500.0, 1600.0, 5.0}, kKeep));
}

// A store's quadtree is laid from its world root's corner: tile corners lie on multiples of the
// tile size from there, not from the frame's origin. A notch in the wall just east of the border
// between two tiles is looked up in the tile that has it, and the box behind it shows.
TEST(TerrainHorizon, TilesOffTheFramesMultiplesOfTheirSizeAreLookedUpWhereTheyAre) {
    const glm::dvec2 corner{-433.7, -217.3};  // the west tiles end at x = 1566.3
    const auto notched = wall([](double x) { return x > 1570.0 && x < 1860.0; });
    const TerrainFloor a = tile(corner, notched), b = tile(corner + glm::dvec2(0.0, kSize), notched);
    const TerrainFloor c = tile(corner + glm::dvec2(kSize, 0.0), notched);
    const TerrainHorizon h = horizonOver({&a, &b, &c});
    EXPECT_FALSE(h.hides({2640.0, 1500.0, 0.0}, {2740.0, 1600.0, 5.0}, kKeep));
    EXPECT_TRUE(h.hides(kBehindLo, kBehindHi, kKeep));  // behind the wall west of the notch
}

TEST(TerrainHorizon, AnEyeNotAboveTheGroundUnderItHidesNothing) {
    const TerrainFloor f = tile({0.0, 0.0}, wall());
    const TerrainHorizon h = horizonOver({&f}, 60.0);
    EXPECT_TRUE(h.empty());
    EXPECT_FALSE(h.hides(kBehindLo, kBehindHi, kKeep));
}

TEST(TerrainHorizon, GroundWithNoDrawnTileEndsTheLinesOfSight) {
    // Three tiles northwards: the eye's, a flat one, and one with the wall and the box.
    auto far_wall = [](double, double y) { return y >= 4100.0 && y <= 4500.0 ? 100.0 : 0.0; };
    const TerrainFloor first = tile({0.0, 0.0}, far_wall), middle = tile({0.0, 2000.0}, far_wall);
    const TerrainFloor last = tile({0.0, 4000.0}, far_wall);
    const glm::dvec3 lo{950.0, 4800.0, 0.0}, hi{1050.0, 4900.0, 5.0};
    EXPECT_TRUE(horizonOver({&first, &middle, &last}).hides(lo, hi, kKeep));
    // Without the middle tile a line of sight may pass under the wall's tile from the gap.
    EXPECT_FALSE(horizonOver({&first, &last}).hides(lo, hi, kKeep));
}

// On rolling hills, every box called hidden is checked along lines of sight to points all over
// it: each must pass below the surface (either triangulation of a cell, the lower) before keep of
// its length. Many boxes must be called hidden, so the check means something.
TEST(TerrainHorizon, EveryLineOfSightToAHiddenBoxMeetsTheSurfaceFirst) {
    auto hills = [](double x, double y) { return 120.0 + 100.0 * std::sin(x / 170.0) * std::cos(y / 230.0); };
    const TerrainFloor f = tile({0.0, 0.0}, hills);
    const glm::dvec3 eye{1000.0, 100.0, hills(1000.0, 100.0) + 20.0};
    TerrainHorizon h;
    h.build(eye, hills(1000.0, 100.0) + 5.0, std::vector<const TerrainFloor*>{&f}, 0.3, std::numbers::pi - 0.3, 300,
            3000.0);
    ASSERT_FALSE(h.empty());
    const double spacing = kSize / (kGrid - 1);
    auto surface_low = [&](double x, double y) {  // the lower of the cell's two triangulations
        const double gx = x / spacing, gy = y / spacing;
        const int c = std::clamp(int(gx), 0, kGrid - 2), r = std::clamp(int(gy), 0, kGrid - 2);
        const double u = gx - c, v = gy - r;
        const double h00 = hills(c * spacing, r * spacing), h01 = hills((c + 1) * spacing, r * spacing);
        const double h10 = hills(c * spacing, (r + 1) * spacing), h11 = hills((c + 1) * spacing, (r + 1) * spacing);
        const double a = u >= v ? h00 + u * (h01 - h00) + v * (h11 - h01) : h00 + v * (h10 - h00) + u * (h11 - h10);
        const double b = u + v <= 1.0 ? h00 + u * (h01 - h00) + v * (h10 - h00)
                                      : h11 + (1.0 - u) * (h10 - h11) + (1.0 - v) * (h01 - h11);
        return std::min(a, b);
    };
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> px(50.0, 1950.0), py(400.0, 1950.0), size(10.0, 150.0), dz(0.0, 40.0);
    int hidden = 0;
    for (int i = 0; i < 400; ++i) {
        const glm::dvec2 at(px(rng), py(rng));
        const double s = size(rng);
        const double base = hills(at.x, at.y) - 5.0;
        const glm::dvec3 lo(at.x - s, at.y - s, base), hi(at.x + s, at.y + s, base + dz(rng));
        if (!h.hides(lo, hi, kKeep)) continue;
        ++hidden;
        std::uniform_real_distribution<double> bx(lo.x, hi.x), by(lo.y, hi.y), bz(lo.z, hi.z);
        for (int k = 0; k < 24; ++k) {
            const glm::dvec3 p = k < 8 ? glm::dvec3((k & 1) ? hi.x : lo.x, (k & 2) ? hi.y : lo.y, (k & 4) ? hi.z : lo.z)
                                       : glm::dvec3(bx(rng), by(rng), bz(rng));
            const double length = glm::length(glm::dvec2(p - eye));
            bool met = false;
            for (double t = 1.0; t < kKeep * length && !met; t += 1.0) {
                const glm::dvec3 q = eye + (p - eye) * (t / length);
                met = q.z < surface_low(q.x, q.y);
            }
            ASSERT_TRUE(met) << "box " << i << " point " << k << " is in sight";
        }
    }
    std::printf("[ measure  ] %d of 400 boxes on the hills called hidden\n", hidden);
    EXPECT_GT(hidden, 40);
}

}  // namespace
