// SPDX-License-Identifier: Apache-2.0
// RouteState: the control socket's route is converted once per version into one RouteLine, the
// renderers' geometry carries that line's points and measures, and the estimator's distances
// along it agree with the route length the daemon reports.

#include <gtest/gtest.h>

#include <cmath>

#include "navmap/daemon/vehicle/vehicle_state_estimator.h"
#include "route_state.h"

using namespace navmap;
using namespace navmap::daemon;

namespace {

const map::Projection kProjection(42.55, 1.57);  // the Andorra store's origin

// A control snapshot of planar points (east/north metres), given in degrees as set_route gives them.
std::shared_ptr<const ipc::RouteState> controlRoute(const std::vector<map::PlanarPoint>& points, std::uint64_t version,
                                                    const std::string& id = "r1") {
    auto r = std::make_shared<ipc::RouteState>();
    r->id = id;
    r->version = version;
    for (const auto& p : points) {
        double lat = 0, lon = 0;
        kProjection.reverse(p, lat, lon);
        r->points.push_back({lat, lon});
    }
    return r;
}

ipc::CanTime at(double s) {
    return ipc::CanTime{} +
           std::chrono::duration_cast<ipc::CanTime::duration>(std::chrono::duration<double>(1.7e9 + s));
}

}  // namespace

TEST(RouteState, ConvertsEachControlRouteVersionOnce) {
    RouteState route(kProjection);
    EXPECT_EQ(route.geometry(), nullptr);
    EXPECT_FALSE(route.update(nullptr)) << "no route set: nothing to convert";
    const auto r1 = controlRoute({{0, 0}, {300, 0}, {300, 400}}, 1);
    EXPECT_TRUE(route.update(r1));
    EXPECT_FALSE(route.update(r1)) << "the same version again is not converted again";
    EXPECT_FALSE(route.update(controlRoute({{0, 0}, {10, 0}}, 1))) << "a snapshot of the same version";
    EXPECT_EQ(route.conversions(), 1u);
    EXPECT_EQ(route.id(), "r1");
    EXPECT_EQ(route.controlPoints(), 3u);
    const std::uint64_t geometry_version = route.geometry()->version;

    EXPECT_TRUE(route.update(controlRoute({{0, 0}, {0, 500}}, 2, "r2")));
    EXPECT_EQ(route.conversions(), 2u);
    EXPECT_EQ(route.id(), "r2");
    EXPECT_GT(route.geometry()->version, geometry_version) << "renderers re-drape a new route";
    const std::uint64_t before_clear = route.geometry()->version;
    EXPECT_TRUE(route.update(nullptr)) << "clear_route drops the route";
    EXPECT_EQ(route.id(), "");
    EXPECT_EQ(route.line(), nullptr);
    EXPECT_EQ(route.geometry(), nullptr) << "nothing left to draw";
    EXPECT_DOUBLE_EQ(route.lengthM(), 0.0);
    EXPECT_FALSE(route.update(nullptr)) << "cleared once";
    EXPECT_TRUE(route.update(controlRoute({{0, 0}, {0, 200}}, 4, "r3")));
    EXPECT_GT(route.geometry()->version, before_clear) << "the next route is draped afresh";
}

TEST(RouteState, OneLineServesTheEstimatorAndTheRenderersWithOneDistance) {
    RouteState route(kProjection);
    // 300 m east, a repeated point, 400 m north: 700 m.
    ASSERT_TRUE(route.update(controlRoute({{0, 0}, {300, 0}, {300, 0}, {300, 400}}, 7)));
    ASSERT_NE(route.line(), nullptr);
    EXPECT_NEAR(route.lengthM(), 700.0, 1e-6);
    EXPECT_EQ(route.line()->lengthM(), route.lengthM());
    const render::RouteGeometry* g = route.geometry();
    ASSERT_NE(g, nullptr);
    ASSERT_EQ(g->points.size(), route.line()->points().size());
    EXPECT_EQ(g->points.size(), 3u) << "the repeated point is dropped once, for both users";
    EXPECT_EQ(g->measure_m, route.line()->measures());
    EXPECT_EQ(g->measure_m.back(), route.lengthM());
    for (std::size_t i = 0; i < g->points.size(); ++i) {
        EXPECT_EQ(g->points[i].x, route.line()->points()[i].x);
        EXPECT_EQ(g->points[i].y, route.line()->points()[i].y);
    }
    EXPECT_NEAR(g->points[1].x, 300.0, 1e-6);
    EXPECT_NEAR(g->points[2].y, 400.0, 1e-6);

    // The estimator matches onto the same line: driven + remaining is the length the daemon
    // reports, and the daemon's remaining distance is the estimator's.
    VehicleStateEstimator estimator(kProjection, nullptr);
    estimator.setRoute(route.line());
    for (int i = 0; i <= 10; ++i) {
        const double y = 40.0 * i;  // driving north on the second leg, 1 s per 40 m
        double lat = 0, lon = 0;
        kProjection.reverse({300.0, y}, lat, lon);
        ipc::VehicleSample u;
        u.set(ipc::VssSignal::Latitude, lat, at(i));
        u.set(ipc::VssSignal::Longitude, lon, at(i));
        u.set(ipc::VssSignal::Heading, 0.0, at(i));
        u.set(ipc::VssSignal::FixType, 5, at(i));
        estimator.addSample(u);
    }
    const EstimatedPose pose = estimator.snapshot()->poseAt(at(10));
    ASSERT_TRUE(pose.valid);
    ASSERT_TRUE(pose.on_route);
    EXPECT_GT(pose.route_driven_m, 300.0) << "matched on the second leg";
    EXPECT_NEAR(pose.route_driven_m + pose.route_remaining_m, route.lengthM(), 1e-9);
    route.track(pose);
    EXPECT_EQ(route.drivenM(), pose.route_driven_m);
    EXPECT_NEAR(route.remainingM(), pose.route_remaining_m, 1e-9);

    // Progress keeps its furthest point; a pose off the route does not move it.
    EstimatedPose back = pose;
    back.route_driven_m = 100.0;
    route.track(back);
    EstimatedPose off;
    off.on_route = false;
    off.route_driven_m = 5000.0;
    route.track(off);
    EXPECT_EQ(route.drivenM(), pose.route_driven_m);
}

TEST(RouteState, ARouteOfOnePointHasNoLineAndNothingToDraw) {
    RouteState route(kProjection);
    ASSERT_TRUE(route.update(controlRoute({{10, 10}}, 1, "dot")));
    EXPECT_EQ(route.id(), "dot");
    EXPECT_EQ(route.line(), nullptr);
    EXPECT_EQ(route.geometry(), nullptr);
    EXPECT_EQ(route.lengthM(), 0.0);
    EXPECT_EQ(route.remainingM(), 0.0);
}

// Where the route runs in a tunnel, found on the road graph: a road north, a 1063 m tunnel that
// bends east, a road north out of it. The route along them has one tunnel, its ends within a
// sample (5 m) of the portals; a route 30 m or more beside the roads has none, nor a RouteState without
// a graph.
TEST(RouteState, MarksWhereTheRouteRunsInATunnel) {
    auto g = std::make_shared<map::RoadGraph>();
    g->nodes = {{0, 0, 1}, {0, 300, 2}, {900, 700, 3}, {900, 1100, 4}};
    g->shape = {{0, 0}, {0, 300}, {0, 300}, {100, 500}, {300, 600}, {600, 600}, {900, 700}, {900, 700}, {900, 1100}};
    g->edges = {{0, 1, 300, 50, map::RoadClass::Primary, 0, 0, 2, 1, 50},
                {1, 2, 1063, 50, map::RoadClass::Primary, map::road_flags::kTunnel, 2, 7, 2, 50},
                {2, 3, 400, 50, map::RoadClass::Primary, 0, 7, 9, 3, 50}};
    map::indexEdges(*g);
    const std::vector<map::PlanarPoint> along = {{0, 0},     {0, 300},   {100, 500}, {300, 600},
                                                 {600, 600}, {900, 700}, {900, 1100}};
    RouteState route(kProjection, RouteState::TunnelGraph{g, kProjection});
    ASSERT_TRUE(route.update(controlRoute(along, 1)));
    ASSERT_NE(route.geometry(), nullptr);
    const auto& tunnels = route.geometry()->tunnels_m;
    ASSERT_EQ(tunnels.size(), 1u);
    EXPECT_NEAR(tunnels[0].first, 300.0, 5.0);
    EXPECT_NEAR(tunnels[0].second, 300.0 + 1063.4, 5.0);
    std::vector<map::PlanarPoint> beside = along;
    for (auto& p : beside) p = {p.x - 30.0, p.y + 30.0};
    ASSERT_TRUE(route.update(controlRoute(beside, 2)));
    EXPECT_TRUE(route.geometry()->tunnels_m.empty());
    RouteState no_graph(kProjection);
    ASSERT_TRUE(no_graph.update(controlRoute(along, 1)));
    EXPECT_TRUE(no_graph.geometry()->tunnels_m.empty());
}
