// SPDX-License-Identifier: Apache-2.0
// Land and sea from coastline ways (coastline.h): islands, open coastlines closed along the
// data's bounding box (also clipped to tiles), gaps closed, broken coastlines reported.
#include <gtest/gtest.h>

#include <cmath>

#include "navmap/map/compile/coastline.h"

using namespace navmap::map;

namespace {

const Box kBox{0, 0, 10000, 10000};

double seaArea(const Coast& c) {
    double a = 0;
    for (const auto& r : c.sea) a += ringSignedArea(r);
    for (const auto& r : c.islands) a += ringSignedArea(r);  // clockwise: negative
    return a;
}

/// Odd winding over sea and islands, as the triangulation and the DEM use it.
bool wet(const Coast& c, PlanarPoint p) {
    std::vector<std::vector<PlanarPoint>> rings = c.sea;
    rings.insert(rings.end(), c.islands.begin(), c.islands.end());
    return samplesInside(rings, p.x, p.y, 1.0, 1)[0] != 0;
}

CoastWay way(std::int64_t id, std::int64_t first, std::int64_t last, std::vector<PlanarPoint> pts) {
    return {id, first, last, std::move(pts)};
}

}  // namespace

TEST(Coastline, AClosedCounterClockwiseRingIsAnIslandInTheSea) {
    // Land on the left: counter-clockwise. The data's box around it is sea.
    const Coast c = assembleCoast(
        {way(7, 1, 1, {{4000, 4000}, {6000, 4000}, {6000, 6000}, {4000, 6000}, {4000, 4000}})}, kBox, 1000);
    ASSERT_EQ(c.sea.size(), 1u);
    ASSERT_EQ(c.islands.size(), 1u);
    EXPECT_TRUE(c.warnings.empty());
    EXPECT_LT(ringSignedArea(c.islands[0]), 0.0);
    EXPECT_DOUBLE_EQ(seaArea(c), 1e8 - 4e6);
    EXPECT_TRUE(wet(c, {1000, 1000}));
    EXPECT_TRUE(wet(c, {9000, 5000}));
    EXPECT_FALSE(wet(c, {5000, 5000}));
}

TEST(Coastline, AnIslandMadeOfTwoWaysIsJoinedByItsNodes) {
    const Coast c = assembleCoast({way(8, 20, 10, {{6000, 6000}, {4000, 6000}, {4000, 4000}}),
                                   way(7, 10, 20, {{4000, 4000}, {6000, 4000}, {6000, 6000}})},
                                  kBox, 1000);
    ASSERT_EQ(c.islands.size(), 1u);
    EXPECT_DOUBLE_EQ(seaArea(c), 1e8 - 4e6);
    EXPECT_FALSE(wet(c, {5000, 5000}));
}

TEST(Coastline, AnOpenCoastlineIsClosedAlongTheBoxWithTheWaterOnItsRight) {
    // West to east across the box, in two ways: the water is south of it.
    std::vector<CoastWay> ways{way(1, 1, 2, {{0, 5000}, {5000, 4000}}), way(2, 2, 3, {{5000, 4000}, {10000, 5000}})};
    const Coast south = assembleCoast(ways, kBox, 1000);
    ASSERT_EQ(south.sea.size(), 1u);
    EXPECT_TRUE(south.islands.empty());
    EXPECT_NEAR(seaArea(south), 45e6, 1e-3);
    EXPECT_TRUE(wet(south, {5000, 1000}));
    EXPECT_TRUE(wet(south, {9900, 100}));
    EXPECT_FALSE(wet(south, {5000, 7000}));
    EXPECT_FALSE(wet(south, {100, 9900}));

    // The same line drawn east to west: the water is north, round the other corners.
    for (auto& w : ways) {
        std::reverse(w.points.begin(), w.points.end());
        std::swap(w.first_node, w.last_node);
    }
    const Coast north = assembleCoast(ways, kBox, 1000);
    ASSERT_EQ(north.sea.size(), 1u);
    EXPECT_NEAR(seaArea(north), 55e6, 1e-3);
    EXPECT_TRUE(wet(north, {5000, 7000}));
    EXPECT_FALSE(wet(north, {5000, 1000}));
}

TEST(Coastline, AnOpenCoastlineClippedToTilesKeepsItsAreaAcrossTileBorders) {
    // A bay: in from the north edge, south, west, and out again (the water on the right: inside).
    const Coast c = assembleCoast({way(3, 1, 2, {{8000, 9600}, {8000, 3000}, {5000, 3000}}),
                                   way(4, 2, 3, {{5000, 3000}, {2000, 3000}, {2000, 10000}})},
                                  kBox, 1000);
    ASSERT_EQ(c.sea.size(), 1u);
    // The start 400 m short of the border is taken to it; the bay is 6 km x 7 km.
    EXPECT_NEAR(seaArea(c), 42e6, 1e-3);
    double tiled = 0;
    int wet_tiles = 0;
    for (int ty = 0; ty < 4; ++ty) {
        for (int tx = 0; tx < 4; ++tx) {
            const Box tile{tx * 2500.0, ty * 2500.0, (tx + 1) * 2500.0, (ty + 1) * 2500.0};
            const std::vector<PlanarPoint> piece = clipRing(c.sea[0], tile);
            const double a = piece.size() >= 3 ? ringSignedArea(piece) : 0.0;
            tiled += a;
            wet_tiles += a > 0 ? 1 : 0;
            // The tile's 3 x 3 DEM samples at sea level: exactly those inside the bay.
            const std::vector<char> s = samplesInside({piece}, tile.min_x, tile.min_y, 1250.0, 3);
            for (int r = 0; r < 3; ++r) {
                for (int k = 0; k < 3; ++k) {
                    const double x = tile.min_x + k * 1250.0, y = tile.min_y + r * 1250.0;
                    const bool inside = x > 2000 && x < 8000 && y > 3000;
                    if (x == 2000 || x == 8000 || y == 3000) continue;  // on the coast
                    EXPECT_EQ(s[static_cast<std::size_t>(r) * 3 + k] != 0, inside) << x << ", " << y;
                }
            }
        }
    }
    EXPECT_NEAR(tiled, 42e6, 1.0);
    EXPECT_EQ(wet_tiles, 12);  // the bay spans 3 x 4 of the 4 x 4 tiles
}

TEST(Coastline, AGapWithinTheToleranceIsClosed) {
    const Coast c = assembleCoast(
        {way(11, 1, 2, {{0, 5000}, {4800, 5000}}), way(12, 3, 4, {{5200, 5000}, {10000, 5000}})}, kBox, 1000);
    EXPECT_EQ(c.gaps_closed, 1u);
    EXPECT_EQ(c.ways_left_out, 0u);
    ASSERT_EQ(c.sea.size(), 1u);
    EXPECT_NEAR(seaArea(c), 50e6, 1e-3);
    ASSERT_EQ(c.warnings.size(), 1u);
    EXPECT_NE(c.warnings[0].find("gap of 400 m"), std::string::npos) << c.warnings[0];
    EXPECT_NE(c.warnings[0].find("way 11"), std::string::npos) << c.warnings[0];

    // A ring whose last way stops 300 m short of its first node closes on itself.
    const Coast ring = assembleCoast(
        {way(13, 1, 2, {{4000, 4000}, {6000, 4000}, {6000, 6000}, {4000, 6000}, {4000, 4300}})}, kBox, 1000);
    EXPECT_EQ(ring.gaps_closed, 1u);
    ASSERT_EQ(ring.islands.size(), 1u);
    EXPECT_FALSE(wet(ring, {5000, 5000}));
}

TEST(Coastline, ABrokenCoastlineIsLeftOutWithAWarningNamingItsWays) {
    // 2 km apart in the middle of the data: no repair; the split would flood the land otherwise.
    const Coast c = assembleCoast(
        {way(21, 1, 2, {{0, 5000}, {4000, 5000}}), way(22, 3, 4, {{6000, 5000}, {10000, 5000}})}, kBox, 1000);
    EXPECT_TRUE(c.empty());
    EXPECT_EQ(c.ways_left_out, 2u);
    ASSERT_EQ(c.warnings.size(), 2u);
    EXPECT_NE(c.warnings[0].find("broken coastline: ways 21"), std::string::npos) << c.warnings[0];
    EXPECT_NE(c.warnings[1].find("broken coastline: ways 22"), std::string::npos) << c.warnings[1];
    EXPECT_NE(c.warnings[0].find("within 1000 m"), std::string::npos) << c.warnings[0];

    // A good coastline beside a broken piece keeps its sea.
    const Coast mixed = assembleCoast(
        {way(31, 1, 2, {{0, 2000}, {10000, 2000}}), way(32, 5, 6, {{3000, 7000}, {5000, 7000}})}, kBox, 1000);
    ASSERT_EQ(mixed.sea.size(), 1u);
    EXPECT_NEAR(seaArea(mixed), 20e6, 1e-3);
    EXPECT_EQ(mixed.ways_left_out, 1u);
    ASSERT_EQ(mixed.warnings.size(), 1u);
    EXPECT_NE(mixed.warnings[0].find("ways 32"), std::string::npos) << mixed.warnings[0];
}
