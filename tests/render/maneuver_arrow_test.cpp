// SPDX-License-Identifier: Apache-2.0
// Route guidance geometry without GL: the arrow cut from the route, its shape (shaft, head,
// casing) as the arrow shader widens it, the roads cut around a junction, and the manoeuvre
// symbols of the guidance overlay.
#include <gtest/gtest.h>

#include <algorithm>
#include <memory>

#include "navmap/map/road_class.h"
#include "navmap/render/guidance_symbol.h"
#include "navmap/render/maneuver_arrow.h"
#include "synthetic_tile.h"

namespace {

using namespace navmap::render;
namespace map = navmap::map;

// An L-shaped route: 200 m north, then 100 m west (a left turn at measure 200).
RouteGeometry lRoute() {
    RouteGeometry r;
    r.points = {{1000.0, 0.0, 5.0}, {1000.0, 100.0, 5.0}, {1000.0, 200.0, 5.0}, {900.0, 200.0, 5.0}};
    r.measure_m = {0.0, 100.0, 200.0, 300.0};
    return r;
}

TEST(CutManeuverArrow, TakesTheRouteAroundTheJunction) {
    const ManeuverArrow a = cutManeuverArrow(lRoute(), 200.0, 40.0, 25.0);
    ASSERT_EQ(a.points.size(), 3u);
    EXPECT_DOUBLE_EQ(a.points[0].y, 160.0);
    EXPECT_DOUBLE_EQ(a.points[0].x, 1000.0);
    EXPECT_DOUBLE_EQ(a.points[1].y, 200.0);  // the junction kept
    EXPECT_DOUBLE_EQ(a.points[2].x, 975.0);  // 25 m into the outgoing road
    EXPECT_FLOAT_EQ(a.emphasis, 1.0f);
}

TEST(CutManeuverArrow, ClampsToTheRouteAndRejectsBadRoutes) {
    const ManeuverArrow start = cutManeuverArrow(lRoute(), 10.0, 40.0, 25.0);
    ASSERT_GE(start.points.size(), 2u);
    EXPECT_DOUBLE_EQ(start.points.front().y, 0.0);
    EXPECT_DOUBLE_EQ(start.points.back().y, 35.0);
    const ManeuverArrow end = cutManeuverArrow(lRoute(), 300.0, 40.0, 25.0);
    EXPECT_DOUBLE_EQ(end.points.back().x, 900.0);
    RouteGeometry bad = lRoute();
    bad.measure_m.pop_back();
    EXPECT_TRUE(cutManeuverArrow(bad, 200.0, 40.0, 25.0).points.empty());
    EXPECT_TRUE(cutManeuverArrow(lRoute(), 500.0, 40.0, 25.0).points.empty());  // beyond the route
}

TEST(ArrowShape, ShaftHeadAndCasingWidths) {
    MapStyle style;
    style.arrow_width_m = 6.0f;
    style.arrow_casing_m = 1.5f;
    style.arrow_head_width_m = 16.0f;
    style.arrow_head_length_m = 12.0f;
    const ArrowShape s = arrowShape(cutManeuverArrow(lRoute(), 200.0, 40.0, 25.0), style);
    EXPECT_DOUBLE_EQ(s.tip_m, 65.0);
    EXPECT_DOUBLE_EQ(s.head_m, 53.0);
    EXPECT_GT(s.casing_tip_m, s.tip_m + 1.5);  // the casing reaches beyond the fill's tip
    // Breakpoints are vertices of the line, which ends at the casing's tip, straight on west.
    const auto& m = s.line.measure_m;
    EXPECT_NE(std::find(m.begin(), m.end(), s.head_m), m.end());
    EXPECT_NE(std::find(m.begin(), m.end(), s.head_m - 1.5), m.end());
    EXPECT_DOUBLE_EQ(m.back(), s.casing_tip_m);
    EXPECT_NEAR(s.line.points.back().y, 200.0, 1e-9);
    EXPECT_LT(s.line.points.back().x, 975.0);
    ASSERT_TRUE(std::is_sorted(m.begin(), m.end()));
    // Fill: the shaft, the head's base wider, zero at the tip.
    EXPECT_FLOAT_EQ(arrowHalfWidth(s, 10.0, false, true), 3.0f);
    EXPECT_FLOAT_EQ(arrowHalfWidth(s, s.head_m, false, false), 3.0f);
    EXPECT_NEAR(arrowHalfWidth(s, s.head_m, false, true), 8.0f, 1e-3);
    EXPECT_NEAR(arrowHalfWidth(s, 59.0, false, true), 4.0f, 1e-3);
    EXPECT_NEAR(arrowHalfWidth(s, s.tip_m, false, false), 0.0f, 1e-3);
    EXPECT_FLOAT_EQ(arrowHalfWidth(s, s.casing_tip_m - 0.5, false, true), 0.0f);
    // Casing: the fill plus its width everywhere, still there past the fill's tip.
    EXPECT_FLOAT_EQ(arrowHalfWidth(s, 10.0, true, true), 4.5f);
    EXPECT_GT(arrowHalfWidth(s, s.head_m, true, true), 8.0f + 1.5f);
    EXPECT_GT(arrowHalfWidth(s, s.tip_m, true, true), 1.5f);
    EXPECT_NEAR(arrowHalfWidth(s, s.casing_tip_m, true, false), 0.0f, 1e-2);
}

TEST(ArrowShape, ShortArrowsKeepHalfForTheShaftAndDegenerateOnesAreEmpty) {
    MapStyle style;
    ManeuverArrow a;
    a.points = {{0.0, 0.0, 0.0}, {0.0, 10.0, 0.0}};
    const ArrowShape s = arrowShape(a, style);
    EXPECT_NEAR(s.head_m, 10.0 * 2.0 / 3.0, 1e-9);  // a third of the arrow
    // Narrowed in proportion to its shortening, but never narrower than the shaft.
    EXPECT_FLOAT_EQ(
        s.head_half_width_m,
        std::max(0.5f * style.arrow_head_width_m * (10.0f / 3.0f) / style.arrow_head_length_m, s.half_width_m));
    a.points = {{0.0, 0.0, 0.0}, {0.0, 0.0, 3.0}};
    EXPECT_TRUE(arrowShape(a, style).line.points.empty());
}

TEST(JunctionRoads, ClipsRoadsToTheDiscAndLeavesOutTunnels) {
    auto tile = navmap::test::makeTile([](float, float) { return 0.0f; });
    tile->roads.push_back(navmap::test::road(map::RoadClass::Residential, {{0.0f, 500.0f}, {1000.0f, 500.0f}}));
    tile->roads.push_back(navmap::test::road(map::RoadClass::Residential, {{500.0f, 0.0f}, {500.0f, 1000.0f}}));
    map::Road tunnel = navmap::test::road(map::RoadClass::Primary, {{400.0f, 400.0f}, {600.0f, 600.0f}});
    tunnel.flags = map::road_flags::kTunnel;
    tile->roads.push_back(tunnel);
    tile->roads.push_back(navmap::test::road(map::RoadClass::Residential, {{0.0f, 0.0f}, {100.0f, 0.0f}}));  // far away
    const glm::dvec2 junction(tile->origin_x + 500.0, tile->origin_y + 500.0);
    const std::vector<std::shared_ptr<const map::Tile>> tiles = {tile};
    const auto roads = junctionRoads(tiles, junction, 60.0);
    ASSERT_EQ(roads.size(), 2u);
    for (const auto& r : roads) {
        ASSERT_EQ(r.size(), 2u);
        EXPECT_NEAR(glm::length(glm::dvec2(r.front()) - junction), 60.0, 1e-6);
        EXPECT_NEAR(glm::length(glm::dvec2(r.back()) - junction), 60.0, 1e-6);
    }
}

// Bounds of a symbol's primary triangles, relative to its centre.
struct Bounds {
    glm::vec2 lo{1e9f}, hi{-1e9f};
};
Bounds bounds(const std::vector<glm::vec2>& v, glm::vec2 c) {
    Bounds b;
    for (const glm::vec2 p : v) {
        b.lo = glm::min(b.lo, p - c);
        b.hi = glm::max(b.hi, p - c);
    }
    return b;
}

TEST(GuidanceSymbol, EverySymbolStaysInItsSquare) {
    const glm::vec2 c(100.0f, 120.0f);
    for (int s = 0; s <= static_cast<int>(ManeuverSymbol::Merge); ++s) {
        const auto g = guidanceSymbol(static_cast<ManeuverSymbol>(s), 2, c, 150.0f);
        EXPECT_FALSE(g.primary.empty()) << "symbol " << s;
        EXPECT_EQ(g.primary.size() % 3, 0u);
        const Bounds b = bounds(g.primary, c);
        EXPECT_GE(b.lo.x, -75.0f) << "symbol " << s;
        EXPECT_LE(b.hi.x, 75.0f) << "symbol " << s;
        EXPECT_GE(b.lo.y, -75.0f) << "symbol " << s;
        EXPECT_LE(b.hi.y, 75.0f) << "symbol " << s;
    }
}

TEST(GuidanceSymbol, TurnsPointToTheirSide) {
    const glm::vec2 c(0.0f);
    const Bounds left = bounds(guidanceSymbol(ManeuverSymbol::TurnLeft, 0, c, 100.0f).primary, c);
    const Bounds right = bounds(guidanceSymbol(ManeuverSymbol::TurnRight, 0, c, 100.0f).primary, c);
    EXPECT_LT(left.lo.x, -30.0f);
    EXPECT_LT(left.hi.x, 30.0f);
    EXPECT_GT(right.hi.x, 30.0f);
    EXPECT_GT(right.lo.x, -30.0f);
    // The roundabout's exit number goes in its ring; other symbols have none.
    EXPECT_GT(guidanceSymbol(ManeuverSymbol::Roundabout, 2, c, 100.0f).exit_label_px, 10.0f);
    EXPECT_EQ(guidanceSymbol(ManeuverSymbol::Straight, 0, c, 100.0f).exit_label_px, 0.0f);
    // The third exit leaves to the left (counter-clockwise), the first to the right.
    const Bounds third = bounds(guidanceSymbol(ManeuverSymbol::Roundabout, 3, c, 100.0f).primary, c);
    const Bounds first = bounds(guidanceSymbol(ManeuverSymbol::Roundabout, 1, c, 100.0f).primary, c);
    EXPECT_LT(third.lo.x, -35.0f);
    EXPECT_GT(first.hi.x, 35.0f);
}

}  // namespace
