// SPDX-License-Identifier: Apache-2.0
// Procedural fields (seed 6.7.2): the grid covers every farmland texel and no point outside the
// farmland's cells, is aligned to the major roads, keeps parcels within the area threshold, picks
// crop patterns by a random walk and varies colours in pairs that cancel (seed 6.7.5).

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>

#include "navmap/map/ortho/super_land_cover.h"
#include "ortho/field_grid.h"
#include "ortho_test_tile.h"

namespace {

using navmap::map::ortho::SuperLandCover;
using namespace navmap::render::ortho;

constexpr int kTexels = 256;
constexpr float kTexel = 2000.0f / kTexels;

// An irregular farmland: a disc and a slanted band joined to it, forest elsewhere.
SuperLandCover farmland(double x, double y) {
    const double dx = x - 800, dy = y - 900;
    const bool disc = dx * dx + dy * dy < 450.0 * 450.0;
    const double u = (x - 1000) * std::cos(0.4) + (y - 1200) * std::sin(0.4);
    const double v = -(x - 1000) * std::sin(0.4) + (y - 1200) * std::cos(0.4);
    const bool band = std::abs(u) < 700 && std::abs(v) < 120;
    return disc || band ? SuperLandCover::Farmland : SuperLandCover::Forest;
}

float flat(double, double) { return 400.0f; }

bool covered(const FieldGrid& grid, glm::vec2 p) {
    return std::any_of(grid.parcels.begin(), grid.parcels.end(),
                       [&](const FieldParcel& q) { return parcelContains(q, p); });
}

TEST(FieldGrid, CoversItsFarmlandWholeAndReachesNoFurtherThanTheTexelsBeside) {
    const auto tile = navmap::test::orthoTile(farmland, flat);
    const FieldGrid grid = buildFieldGrid(*tile);
    ASSERT_GT(grid.parcels.size(), 20u);
    const std::vector<std::uint8_t> mask = farmlandMask(*tile);
    // Every farmland texel is covered whole: its centre and four points near its corners.
    int farm = 0, outside_points = 0, outside_covered = 0;
    for (int r = 0; r < kTexels; ++r) {
        for (int c = 0; c < kTexels; ++c) {
            const glm::vec2 centre((c + 0.5f) * kTexel, (r + 0.5f) * kTexel);
            if (mask[static_cast<std::size_t>(r) * kTexels + static_cast<std::size_t>(c)] != 0) {
                ++farm;
                for (const glm::vec2 d : {glm::vec2(0), glm::vec2(-0.45f), glm::vec2(0.45f), glm::vec2(-0.45f, 0.45f),
                                          glm::vec2(0.45f, -0.45f)}) {
                    ASSERT_TRUE(covered(grid, centre + d * kTexel))
                        << "farmland texel " << r << ", " << c << " (offset " << d.x << ", " << d.y
                        << ") has no parcel";
                }
            } else if (r % 4 == 0 && c % 4 == 0) {
                ++outside_points;
                outside_covered += covered(grid, centre);
            }
        }
    }
    EXPECT_GT(farm, 10000);
    // The parcels stay near the farmland: the drawn mask cuts off the rest, but a grid spreading
    // over the whole tile would be wasted work.
    EXPECT_LT(outside_covered, outside_points / 4) << outside_covered << " of " << outside_points;
    FieldOptions o;
    for (const auto& q : grid.parcels) {
        float area = 0;
        for (std::size_t i = 0; i < 4; ++i)
            area += q.corners[i].x * q.corners[(i + 1) % 4].y - q.corners[(i + 1) % 4].x * q.corners[i].y;
        EXPECT_GT(area, 0.0f) << "corners not counter-clockwise";
        EXPECT_LE(0.5f * area, o.max_parcel_m2 + 1.0f);
        EXPECT_GE(q.pattern, 0);
        EXPECT_LT(q.pattern, kCropPatterns);
    }
    // Pair-wise colour changes, weighted by the farmland in each parcel, cancel (seed 6.7.5).
    double sum = 0, hue = 0, total = 0;
    for (std::size_t i = 0; i + 1 < grid.parcels.size(); i += 2) {
        for (const FieldParcel* q : {&grid.parcels[i], &grid.parcels[i + 1]}) {
            sum += q->variation * std::max(q->farm_texels, 1);
            hue += q->hue * std::max(q->farm_texels, 1);
            total += std::abs(q->variation) * std::max(q->farm_texels, 1);
        }
    }
    EXPECT_GT(total, 100.0);
    EXPECT_NEAR(sum, 0.0, 1e-3 * total);
    EXPECT_NEAR(hue, 0.0, 1e-3 * total);
}

TEST(FieldGrid, NoFarmlandNoParcels) {
    const auto forest = navmap::test::orthoTile([](double, double) { return SuperLandCover::Forest; }, flat);
    EXPECT_TRUE(buildFieldGrid(*forest).parcels.empty());
    navmap::map::Tile bare;
    EXPECT_TRUE(buildFieldGrid(bare).parcels.empty());
}

TEST(FieldGrid, IsAlignedToTheMajorRoads) {
    auto tile = navmap::test::orthoTile(farmland, flat);
    EXPECT_EQ(roadGridAngle(*tile), 0.0f);
    navmap::map::Road road;
    road.cls = navmap::map::RoadClass::Primary;
    const double a = 30.0 * std::numbers::pi / 180.0;
    for (int i = 0; i <= 10; ++i) {
        road.points.push_back(
            {static_cast<float>(200 + 150 * i * std::cos(a)), static_cast<float>(100 + 150 * i * std::sin(a))});
    }
    tile->roads.push_back(road);
    navmap::map::Road path;  // a long footpath at another angle weighs less
    path.cls = navmap::map::RoadClass::Path;
    path.points = {{0, 1900}, {1900, 1950}};
    tile->roads.push_back(path);
    EXPECT_NEAR(roadGridAngle(*tile), a, 1.0 * std::numbers::pi / 180.0);
    const FieldGrid grid = buildFieldGrid(*tile);
    EXPECT_NEAR(grid.angle, a, 1.0 * std::numbers::pi / 180.0);
    // Parcel sides run along or across the road (mod 90 degrees), up to the silhouette's pull.
    int aligned = 0;
    for (const auto& q : grid.parcels) {
        const glm::vec2 e = q.corners[1] - q.corners[0];
        double d = std::fmod(std::atan2(e.y, e.x) - a + 4 * std::numbers::pi, std::numbers::pi / 2);
        d = std::min(d, std::numbers::pi / 2 - d);
        aligned += d < 10.0 * std::numbers::pi / 180.0;
    }
    EXPECT_GT(aligned, static_cast<int>(grid.parcels.size()) / 2);
    // Still every farmland texel centre covered on the rotated grid.
    const std::vector<std::uint8_t> mask = farmlandMask(*tile);
    for (int r = 0; r < kTexels; ++r) {
        for (int c = 0; c < kTexels; ++c) {
            if (mask[static_cast<std::size_t>(r) * kTexels + static_cast<std::size_t>(c)] == 0) continue;
            ASSERT_TRUE(covered(grid, {(c + 0.5f) * kTexel, (r + 0.5f) * kTexel})) << r << ", " << c;
        }
    }
}

TEST(FieldGrid, CropPatternsFollowARandomWalk) {
    const auto tile = navmap::test::orthoTile([](double, double) { return SuperLandCover::Farmland; }, flat);
    const FieldGrid grid = buildFieldGrid(*tile);
    ASSERT_GT(grid.parcels.size(), 100u);
    // Consecutive parcels draw from overlapping windows [o, o + m) whose offset moves by at most one
    // step of the walk, while the walk still visits the whole atlas.
    std::array<int, kCropPatterns> used{};
    int far_jumps = 0;
    for (std::size_t i = 0; i < grid.parcels.size(); ++i) {
        ++used[static_cast<std::size_t>(grid.parcels[i].pattern)];
        if (i > 0 && std::abs(grid.parcels[i].pattern - grid.parcels[i - 1].pattern) > kCropPatterns / 2 + 1)
            ++far_jumps;
    }
    EXPECT_EQ(far_jumps, 0);
    EXPECT_GE(std::count_if(used.begin(), used.end(), [](int n) { return n > 0; }), kCropPatterns - 1);
    // Deterministic per tile.
    const FieldGrid again = buildFieldGrid(*tile);
    ASSERT_EQ(again.parcels.size(), grid.parcels.size());
    for (std::size_t i = 0; i < grid.parcels.size(); ++i) {
        ASSERT_EQ(again.parcels[i].pattern, grid.parcels[i].pattern);
        ASSERT_EQ(again.parcels[i].corners, grid.parcels[i].corners);
    }
}

}  // namespace
