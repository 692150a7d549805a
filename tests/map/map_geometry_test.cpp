// SPDX-License-Identifier: Apache-2.0
// Planar geometry: triangulation with holes, self-touching and self-intersecting rings (area
// as the odd winding rule gives it), label anchors (seed 4.4.2),
// simplification and clipping to tiles.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "navmap/map/compile/triangulator.h"
#include "navmap/map/geometry.h"
#include "navmap/map/projection.h"
#include "navmap/map/tile_scheme.h"

using namespace navmap::map;

namespace {

std::vector<PlanarPoint> square(double x0, double y0, double s) {
    return {{x0, y0}, {x0 + s, y0}, {x0 + s, y0 + s}, {x0, y0 + s}};
}

bool allCcw(const Triangulation& t) {
    for (std::size_t i = 0; i < t.indices.size(); i += 3) {
        const auto& a = t.vertices[t.indices[i]];
        const auto& b = t.vertices[t.indices[i + 1]];
        const auto& c = t.vertices[t.indices[i + 2]];
        if ((b.x - a.x) * (c.y - a.y) - (c.x - a.x) * (b.y - a.y) <= 0) return false;
    }
    return true;
}

}  // namespace

TEST(Triangulator, SquareWithHolePreservesArea) {
    std::vector<std::vector<PlanarPoint>> rings{square(0, 0, 100), square(25, 25, 50)};
    const Triangulation t = triangulate(rings);
    ASSERT_TRUE(t.ok);
    EXPECT_EQ(t.indices.size() % 3, 0u);
    EXPECT_NEAR(triangulatedArea(t), 100.0 * 100 - 50 * 50, 1e-6);
    EXPECT_TRUE(allCcw(t));
    EXPECT_EQ(t.vertices.size(), 8u);  // no extra vertices for a simple polygon
}

TEST(Triangulator, ConcaveMultiHoleFarFromOrigin) {
    // An L-shape 5 000 km from the frame origin with two holes; holes given counter-clockwise
    // (odd winding ignores orientation).
    const double ox = 5e6, oy = -3e6;
    std::vector<PlanarPoint> l{{ox, oy},           {ox + 30, oy},      {ox + 30, oy + 10},
                               {ox + 10, oy + 10}, {ox + 10, oy + 30}, {ox, oy + 30}};
    std::vector<std::vector<PlanarPoint>> rings{l, square(ox + 2, oy + 2, 4), square(ox + 20, oy + 2, 5)};
    const Triangulation t = triangulate(rings);
    ASSERT_TRUE(t.ok);
    EXPECT_NEAR(triangulatedArea(t), 30 * 10 + 10 * 20 - 16 - 25, 1e-4);
    EXPECT_TRUE(allCcw(t));
}

TEST(Triangulator, SelfIntersectionAddsVertices) {
    // Bow tie: two triangles meeting at (5,5); odd winding fills both lobes.
    std::vector<std::vector<PlanarPoint>> rings{{{0, 0}, {10, 10}, {10, 0}, {0, 10}}};
    const Triangulation t = triangulate(rings);
    ASSERT_TRUE(t.ok);
    EXPECT_NEAR(triangulatedArea(t), 50.0, 1e-6);
    EXPECT_EQ(t.vertices.size(), 5u);
    EXPECT_NEAR(t.vertices[4].x, 5.0, 1e-9);
}

namespace {

bool indicesInRange(const Triangulation& t) {
    for (auto i : t.indices) {
        if (i >= t.vertices.size()) return false;
    }
    return true;
}

}  // namespace

TEST(Triangulator, IslandInAHoleIsFilled) {
    // Odd winding: outer square, a hole, and an island inside the hole (all counter-clockwise).
    std::vector<std::vector<PlanarPoint>> rings{square(0, 0, 100), square(25, 25, 50), square(40, 40, 20)};
    const Triangulation t = triangulate(rings);
    ASSERT_TRUE(t.ok);
    EXPECT_NEAR(triangulatedArea(t), 100.0 * 100 - 50 * 50 + 20 * 20, 1e-6);
    EXPECT_TRUE(allCcw(t));
    EXPECT_TRUE(indicesInRange(t));
    EXPECT_EQ(t.vertices.size(), 12u);
}

TEST(Triangulator, OuterRingsSharingAnEdgeAreBothFilled) {
    // Two outer rings of a multipolygon side by side: the shared edge is crossed twice.
    std::vector<std::vector<PlanarPoint>> rings{square(0, 0, 10), square(10, 0, 10)};
    const Triangulation t = triangulate(rings);
    ASSERT_TRUE(t.ok);
    EXPECT_NEAR(triangulatedArea(t), 200.0, 1e-9);
    EXPECT_TRUE(allCcw(t));
}

TEST(Triangulator, SelfTouchingRingFillsBothLobesWithoutNewVertices) {
    // One ring through (5,5) twice: two squares touching at a corner.
    std::vector<std::vector<PlanarPoint>> rings{{{0, 0}, {5, 0}, {5, 5}, {10, 5}, {10, 10}, {5, 10}, {5, 5}, {0, 5}}};
    const Triangulation t = triangulate(rings);
    ASSERT_TRUE(t.ok);
    EXPECT_NEAR(triangulatedArea(t), 50.0, 1e-9);
    EXPECT_TRUE(allCcw(t));
    EXPECT_TRUE(indicesInRange(t));
    EXPECT_EQ(t.vertices.size(), 8u);
}

TEST(Triangulator, ZeroWidthBridgeToAHoleEnclosesNothing) {
    // A keyhole ring as clipRing makes them: the outer square, a bridge along y = 5 walked there
    // and back, and the hole [3,7]^2 at its end. The bridge is an edge given twice.
    std::vector<std::vector<PlanarPoint>> rings{
        {{0, 0}, {10, 0}, {10, 10}, {0, 10}, {0, 5}, {3, 5}, {3, 7}, {7, 7}, {7, 3}, {3, 3}, {3, 5}, {0, 5}}};
    const Triangulation t = triangulate(rings);
    ASSERT_TRUE(t.ok);
    EXPECT_NEAR(triangulatedArea(t), 100.0 - 16.0, 1e-9);
    EXPECT_TRUE(allCcw(t));
    EXPECT_TRUE(indicesInRange(t));
}

TEST(Triangulator, SelfIntersectingRingFollowsTheOddRule) {
    // The edge (5,10)->(5,-5) crosses (0,0)->(10,0) at (5,0). Odd winding fills [5,10]x[0,10]
    // and [0,5]x[-5,0]; [0,5]x[0,10] lies inside twice and stays empty.
    std::vector<std::vector<PlanarPoint>> rings{{{0, 0}, {10, 0}, {10, 10}, {5, 10}, {5, -5}, {0, -5}}};
    const Triangulation t = triangulate(rings);
    ASSERT_TRUE(t.ok);
    EXPECT_NEAR(triangulatedArea(t), 50.0 + 25.0, 1e-9);
    EXPECT_TRUE(allCcw(t));
    EXPECT_TRUE(indicesInRange(t));
    ASSERT_EQ(t.vertices.size(), 7u);  // the crossing point is added after the ring's 6
    EXPECT_NEAR(t.vertices[6].x, 5.0, 1e-9);
    EXPECT_NEAR(t.vertices[6].y, 0.0, 1e-9);
}

TEST(Triangulator, RepeatedConsecutivePointsAreSkipped) {
    std::vector<std::vector<PlanarPoint>> rings{{{0, 0}, {0, 0}, {10, 0}, {10, 10}, {10, 10}, {0, 10}, {0, 0}}};
    const Triangulation t = triangulate(rings);
    ASSERT_TRUE(t.ok);
    EXPECT_NEAR(triangulatedArea(t), 100.0, 1e-9);
    EXPECT_TRUE(indicesInRange(t));
}

TEST(Triangulator, DegenerateRingsGiveNoTrianglesAndNoError) {
    const std::vector<std::vector<PlanarPoint>> collinear{{{0, 0}, {5, 0}, {10, 0}, {5, 0}}};
    const Triangulation line = triangulate(collinear);
    EXPECT_TRUE(line.ok);
    EXPECT_TRUE(line.indices.empty());
    EXPECT_EQ(triangulatedArea(line), 0.0);

    const std::vector<std::vector<PlanarPoint>> point{{{3, 3}, {3, 3}, {3, 3}}};
    const Triangulation one = triangulate(point);
    EXPECT_TRUE(one.ok);
    EXPECT_TRUE(one.indices.empty());

    const std::vector<std::vector<PlanarPoint>> too_short{{{0, 0}, {1, 1}}};
    EXPECT_TRUE(triangulate(too_short).indices.empty());
}

TEST(Triangulator, NonFiniteCoordinateIsAnError) {
    const std::vector<std::vector<PlanarPoint>> rings{{{0, 0}, {10, 0}, {std::nan(""), 10}}};
    const Triangulation t = triangulate(rings);
    EXPECT_FALSE(t.ok);
    EXPECT_TRUE(t.indices.empty());
}

TEST(LabelAnchors, PolylineCenterIsHalfTheArcLength) {
    const std::vector<PlanarPoint> line{{0, 0}, {10, 0}, {10, 30}};
    const PlanarPoint c = polylineCenter(line);
    EXPECT_NEAR(c.x, 10.0, 1e-9);
    EXPECT_NEAR(c.y, 10.0, 1e-9);
    EXPECT_NEAR(polylineLength(line), 40.0, 1e-9);
}

TEST(LabelAnchors, LongestStraightSegmentMergesNearlyStraightRuns) {
    // 3 short nearly collinear segments (total ~30 m) beat a single 25 m segment after a turn.
    const std::vector<PlanarPoint> line{{0, 0}, {10, 0.5}, {20, 0.5}, {30, 1}, {30, 25}};
    const Segment s = longestStraightSegment(line, 10.0);
    EXPECT_NEAR(s.a.x, 0, 1e-9);
    EXPECT_NEAR(s.b.x, 30, 1e-9);
    EXPECT_NEAR(s.b.y, 1, 1e-9);
    // With zero tolerance the single longest segment wins.
    const Segment strict = longestStraightSegment(line, 0.0);
    EXPECT_NEAR(strict.a.y, 1, 1e-9);
    EXPECT_NEAR(strict.b.y, 25, 1e-9);
}

TEST(LabelAnchors, BarycenterOfPolygonWithHole) {
    // 10x10 square with a 4x4 hole in its right half: the barycenter shifts left.
    const std::vector<std::vector<PlanarPoint>> outer{square(0, 0, 10)};
    const std::vector<std::vector<PlanarPoint>> hole{square(5, 3, 4)};
    const PlanarPoint c = polygonBarycenter(outer, hole);
    // (100*5 - 16*7) / 84 = 4.619...
    EXPECT_NEAR(c.x, (100.0 * 5 - 16.0 * 7) / 84.0, 1e-9);
    EXPECT_NEAR(c.y, 5.0, 1e-9);
    const PlanarPoint plain = polygonBarycenter(outer, {});
    EXPECT_NEAR(plain.x, 5.0, 1e-9);
}

TEST(Geometry, SimplifyKeepsShapeWithinTolerance) {
    std::vector<PlanarPoint> line;
    for (int i = 0; i <= 100; ++i) line.push_back({static_cast<double>(i), (i % 2) * 0.1});
    line.push_back({100, 50});
    const auto s = simplifyPolyline(line, 0.5);
    ASSERT_EQ(s.size(), 3u);
    EXPECT_NEAR(s[1].x, 100, 1e-9);
    const auto ring = simplifyRing(square(0, 0, 10), 0.1);
    EXPECT_EQ(ring.size(), 4u);
}

TEST(Geometry, ClipPolylineAndRingToTile) {
    const Box box{0, 0, 10, 10};
    const std::vector<PlanarPoint> line{{-5, 5}, {5, 5}, {5, 15}, {8, 15}, {8, 5}, {20, 5}};
    const auto pieces = clipPolyline(line, box);
    ASSERT_EQ(pieces.size(), 2u);
    EXPECT_DOUBLE_EQ(pieces[0].front().x, 0.0);
    EXPECT_DOUBLE_EQ(pieces[0].back().y, 10.0);
    EXPECT_DOUBLE_EQ(pieces[1].back().x, 10.0);
    const auto ring = clipRing(square(-5, -5, 10), box);
    EXPECT_NEAR(std::abs(ringSignedArea(ring)), 25.0, 1e-9);
    EXPECT_TRUE(clipRing(square(20, 20, 5), box).empty());
}

TEST(TileScheme, FindsTilesAndRangesInTheStoreFrame) {
    const Projection frame(42.55, 1.55);
    const TileScheme s = TileScheme::forData(frame, 42.3, 1.2, 42.8, 1.9, 2000);
    const int leaf = s.leafLevel();
    const auto id = s.tileAt(leaf, {0, 0});
    ASSERT_TRUE(id);
    EXPECT_TRUE(s.bounds(*id).contains({0, 0}));
    EXPECT_EQ(id->parent().level, leaf - 1);
    EXPECT_FALSE(s.tileAt(leaf, {1e7, 0}));
    const double t = s.tileSize(leaf);
    const Box b = s.bounds(*id);
    const TileRange r = s.range(leaf, {b.min_x + 1, b.min_y + 1, b.max_x + 1, b.min_y + 2});
    EXPECT_FALSE(r.empty);
    EXPECT_EQ(r.x1 - r.x0, 1u);  // the box reaches 1 m into the next column
    EXPECT_EQ(r.y1, r.y0);
    EXPECT_EQ(s.levelForTileSize(8.5 * t), leaf - 3);
}
