// SPDX-License-Identifier: Apache-2.0
// RouteGuidance: a control route's manoeuvres followed along the pose: the arrows of the next
// manoeuvres, the countdown, a passed manoeuvre dropped, off_route/back_on_route published once
// each with hysteresis, a new or cleared route starting over.

#include <gtest/gtest.h>

#include <vector>

#include "route_guidance.h"

using namespace navmap;
using namespace navmap::daemon;

namespace {

const map::Projection kProjection(42.55, 1.57);

// East 300 m, left (north) 400 m, right (east) 300 m: turn_left at point 1, turn_right at point 2.
std::shared_ptr<const ipc::RouteState> twoTurns(std::uint64_t version = 1) {
    auto r = std::make_shared<ipc::RouteState>();
    r->id = "r1";
    r->version = version;
    for (const map::PlanarPoint p : {map::PlanarPoint{0, 0}, {300, 0}, {300, 400}, {600, 400}}) {
        double lat = 0, lon = 0;
        kProjection.reverse(p, lat, lon);
        r->points.push_back({lat, lon});
    }
    r->maneuvers = {{0, ipc::ManeuverType::Depart, "", {}, {}},
                    {1, ipc::ManeuverType::TurnLeft, "Carrer Nord", {}, {}},
                    {2, ipc::ManeuverType::TurnRight, "Avinguda Est", {}, {}},
                    {3, ipc::ManeuverType::Arrive, "", {}, {}}};
    return r;
}

EstimatedPose poseAt(double x, double y) {
    EstimatedPose p;
    p.valid = true;
    p.x = x;
    p.y = y;
    return p;
}

struct Fixture {
    std::vector<ipc::ControlEvent> events;
    RouteGuidance guidance{kProjection, GuidanceConfig{}, [this](const ipc::ControlEvent& e) { events.push_back(e); },
                           Log(Log::kErr)};
};

}  // namespace

TEST(RouteGuidance, ShowsTheNextManoeuvreItsCountdownAndAFainterOneAfterIt) {
    Fixture f;
    f.guidance.setRoute(twoTurns());
    EXPECT_FALSE(f.guidance.snapshot().active) << "nothing shown before the first pose";
    f.guidance.update(poseAt(20, 0), 0.0);
    const GuidanceSnapshot& s = f.guidance.snapshot();
    ASSERT_TRUE(s.active);
    ASSERT_TRUE(s.next);
    EXPECT_EQ(s.next->type, map::guidance::ManeuverType::TurnLeft);
    EXPECT_EQ(s.street, "Carrer Nord");
    EXPECT_EQ(s.distance_text, "200 m") << "280 m to the turn: the largest step not above it";
    EXPECT_EQ(s.remaining_distance, "980 m");
    EXPECT_EQ(s.remaining_time, "1 min") << "980 m at the default 40 km/h";
    // The right turn follows 400 m after the left one: beyond second_arrow_within_m (250 m).
    ASSERT_EQ(s.arrows.size(), 1u);
    EXPECT_NEAR(s.arrows[0].junction_m, 300.0, 0.5);
    EXPECT_FLOAT_EQ(s.arrows[0].emphasis, 1.0f);

    GuidanceConfig near;
    near.second_arrow_within_m = 500.0;
    f.guidance.setConfig(near);
    f.guidance.update(poseAt(40, 0), 1.0);
    ASSERT_EQ(f.guidance.snapshot().arrows.size(), 2u);
    EXPECT_NEAR(f.guidance.snapshot().arrows[1].junction_m, 700.0, 0.5);
    EXPECT_LT(f.guidance.snapshot().arrows[1].emphasis, 1.0f) << "the one after is fainter";
}

TEST(RouteGuidance, APassedManoeuvreIsDropped) {
    Fixture f;
    f.guidance.setRoute(twoTurns());
    double t = 0.0;
    for (double x = 0; x <= 300; x += 10) f.guidance.update(poseAt(x, 0), t += 0.5);
    EXPECT_EQ(f.guidance.snapshot().next->type, map::guidance::ManeuverType::TurnLeft) << "at the junction";
    EXPECT_EQ(f.guidance.snapshot().distance_text, "now");
    for (double y = 10; y <= 60; y += 10) f.guidance.update(poseAt(300, y), t += 0.5);
    const GuidanceSnapshot& s = f.guidance.snapshot();
    ASSERT_TRUE(s.next);
    EXPECT_EQ(s.next->type, map::guidance::ManeuverType::TurnRight) << "the left turn is behind";
    ASSERT_FALSE(s.arrows.empty());
    EXPECT_NEAR(s.arrows[0].junction_m, 700.0, 0.5) << "no arrow at the passed junction";
    EXPECT_TRUE(f.events.empty()) << "on the route all the way";
}

TEST(RouteGuidance, LeavingTheRouteIsReportedOnceWithHysteresis) {
    Fixture f;
    f.guidance.setRoute(twoTurns());
    double t = 0.0;
    for (double x = 0; x <= 200; x += 10) f.guidance.update(poseAt(x, 0), t += 0.5);
    // A road south, away from the route: 10 m per half second.
    for (double y = -10; y >= -45; y -= 10) f.guidance.update(poseAt(200, y), t += 0.5);
    EXPECT_TRUE(f.events.empty()) << "up to 40 m off: not beyond the threshold";
    for (int k = 0; k < 8; ++k) f.guidance.update(poseAt(200, -50), t += 0.5);
    ASSERT_EQ(f.events.size(), 1u);
    EXPECT_EQ(f.events[0].kind, ipc::ControlEventKind::OffRoute);
    EXPECT_EQ(f.events[0].route_id, "r1");
    EXPECT_NEAR(f.events[0].offset_m, 50.0, 1.0);
    EXPECT_TRUE(f.guidance.snapshot().off_route);
    EXPECT_TRUE(f.guidance.snapshot().arrows.empty()) << "no arrows while off the route";
    // Flapping around the return threshold does not bring it back.
    for (int k = 0; k < 10; ++k) f.guidance.update(poseAt(200, k % 2 ? -19 : -21), t += 0.5);
    EXPECT_EQ(f.events.size(), 1u);
    for (int k = 0; k < 6; ++k) f.guidance.update(poseAt(210 + 10 * k, -5), t += 0.5);
    ASSERT_EQ(f.events.size(), 2u);
    EXPECT_EQ(f.events[1].kind, ipc::ControlEventKind::BackOnRoute);
    EXPECT_FALSE(f.guidance.snapshot().off_route);
    EXPECT_FALSE(f.guidance.snapshot().arrows.empty());
}

TEST(RouteGuidance, ANewRouteReplacesTheOldAndAClearedOneShowsNothing) {
    Fixture f;
    f.guidance.setRoute(twoTurns());
    f.guidance.update(poseAt(100, 0), 0.0);
    ASSERT_TRUE(f.guidance.snapshot().next);
    auto other = std::make_shared<ipc::RouteState>(*twoTurns(2));
    other->id = "r2";
    other->maneuvers = {{2, ipc::ManeuverType::Roundabout, "CG-2", 2u, 3u}};
    f.guidance.setRoute(other);
    f.guidance.update(poseAt(110, 0), 0.5);
    const GuidanceSnapshot& s = f.guidance.snapshot();
    ASSERT_TRUE(s.next);
    EXPECT_EQ(s.next->type, map::guidance::ManeuverType::Roundabout);
    EXPECT_EQ(s.next->exit, 2);
    ASSERT_EQ(s.arrows.size(), 1u);
    EXPECT_NEAR(s.arrows[0].junction_m, 700.0, 0.5);
    EXPECT_NEAR(s.arrows[0].end_m, 1000.0, 0.5) << "the arrow runs to the roundabout's exit (end_index)";
    f.guidance.setRoute(nullptr);
    f.guidance.update(poseAt(120, 0), 1.0);
    EXPECT_FALSE(f.guidance.snapshot().active);
    EXPECT_FALSE(f.guidance.snapshot().next);
}

TEST(RouteGuidance, RemainingDistanceAndTimeReadAsDriversExpect) {
    EXPECT_EQ(formatRemainingDistance(4260.0), "4.2 km") << "rounded down: never more than is left";
    EXPECT_EQ(formatRemainingDistance(846.0), "850 m");
    EXPECT_EQ(formatRemainingDistance(996.0), "1.0 km");
    EXPECT_EQ(formatRemainingDistance(120000.0), "120.0 km");
    EXPECT_EQ(formatRemainingTime(20.0), "< 1 min");
    EXPECT_EQ(formatRemainingTime(420.0), "7 min");
    EXPECT_EQ(formatRemainingTime(4500.0), "1 h 15 min");
}

// The lanes before the next manoeuvre, from the road graph under the control route: the left
// turn's road has "left|through", within [guidance] lane_distance_m of the junction; the right
// turn after it has none of its own (the left turn's lanes lead to the left turn).
namespace {

map::RoadGraph twoTurnsGraph() {
    namespace la = map::lane_arrow;
    map::RoadGraph g;
    const map::PlanarPoint pts[] = {{0, 0}, {300, 0}, {300, 400}, {600, 400}};
    for (std::size_t i = 0; i < 4; ++i) {
        g.nodes.push_back({pts[i].x, pts[i].y, static_cast<std::int64_t>(i + 1)});
        g.shape.push_back({static_cast<float>(pts[i].x), static_cast<float>(pts[i].y)});
    }
    g.lane_arrows = {la::kLeft, la::kThrough};
    for (std::uint32_t i = 0; i < 3; ++i) {
        map::GraphEdge e{i, i + 1, i == 1 ? 400.0f : 300.0f, 50.0f, map::RoadClass::Secondary, 0, i, i + 2, 100 + i};
        if (i == 0) e.lane_count = 2;
        g.edges.push_back(e);
    }
    map::indexEdges(g);
    return g;
}

}  // namespace

TEST(RouteGuidance, TheLanesBeforeTheNextManoeuvre) {
    namespace la = map::lane_arrow;
    Fixture f;
    f.guidance.setGraph(std::make_shared<const map::RoadGraph>(twoTurnsGraph()), kProjection);
    f.guidance.setRoute(twoTurns());
    f.guidance.update(poseAt(20, 0), 0.0);
    ASSERT_TRUE(f.guidance.snapshot().next);
    ASSERT_TRUE(f.guidance.snapshot().lanes) << "280 m before the left turn";
    EXPECT_EQ(f.guidance.snapshot().lanes->lanes, (std::vector<std::uint16_t>{la::kLeft, la::kThrough}));
    EXPECT_EQ(f.guidance.snapshot().lanes->recommended, 0b01u);
    EXPECT_EQ(f.guidance.snapshot().lanes->way_id, 100);

    GuidanceConfig near;
    near.lane_distance_m = 200.0;
    f.guidance.setConfig(near);
    f.guidance.update(poseAt(40, 0), 1.0);
    EXPECT_FALSE(f.guidance.snapshot().lanes) << "260 m out: not yet";
    f.guidance.update(poseAt(150, 0), 2.0);
    EXPECT_TRUE(f.guidance.snapshot().lanes) << "150 m out";

    // Past the left turn: the right turn's road has no lanes, and the left turn's are not its.
    f.guidance.setConfig(GuidanceConfig{});
    f.guidance.update(poseAt(300, 100), 3.0);
    ASSERT_TRUE(f.guidance.snapshot().next);
    EXPECT_EQ(f.guidance.snapshot().next->type, map::guidance::ManeuverType::TurnRight);
    EXPECT_FALSE(f.guidance.snapshot().lanes);

    // Without a graph there are no lanes.
    Fixture bare;
    bare.guidance.setRoute(twoTurns());
    bare.guidance.update(poseAt(20, 0), 0.0);
    ASSERT_TRUE(bare.guidance.snapshot().next);
    EXPECT_FALSE(bare.guidance.snapshot().lanes);
}
