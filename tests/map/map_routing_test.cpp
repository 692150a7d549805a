// SPDX-License-Identifier: Apache-2.0
// map::planRoute, the route planner of the simulator, the tools and the tests: the fastest car
// route between the drivable nodes nearest to two positions, or the problem named.
#include <gtest/gtest.h>

#include <vector>

#include "navmap/map/routing.h"

using namespace navmap::map;

namespace {

// A (0,0) -> B (100,0) one-way, B <-> C (200,0) two-way, both primary; D (300,0) has only a
// footway to C, so it is no place for a car to start or stop.
RoadGraph oneWayLine() {
    RoadGraph g;
    g.nodes = {{0, 0, 1}, {100, 0, 2}, {200, 0, 3}, {300, 0, 4}};
    const GraphEdge ab{0, 1, 100.0F, 50.0F, RoadClass::Primary, 0, 0, 0, 10};
    const GraphEdge bc{1, 2, 100.0F, 50.0F, RoadClass::Primary, 0, 0, 0, 11};
    const GraphEdge cb{2, 1, 100.0F, 50.0F, RoadClass::Primary, 0, 0, 0, 11};
    const GraphEdge dc{3, 2, 100.0F, 5.0F, RoadClass::Path, 0, 0, 0, 12};
    g.edges = {ab, bc, cb, dc};
    g.first_edge = {0, 1, 2, 3, 4};
    return g;
}

}  // namespace

TEST(PlanRoute, FollowsTheOneWayRoadBetweenTheNearestDrivableNodes) {
    const RoadGraph g = oneWayLine();
    const RoutePlan plan = planRoute(g, {-5, 3}, {310, -4});  // D is a footway end: C
    ASSERT_TRUE(plan.ok()) << plan.problem;
    EXPECT_TRUE(plan.problem.empty());
    EXPECT_EQ(plan.route->edges, (std::vector<std::uint32_t>{0, 1}));
    EXPECT_DOUBLE_EQ(plan.route->length_m, 200.0);
}

TEST(PlanRoute, NamesTheProblemWhenThereIsNoRoute) {
    const RoadGraph g = oneWayLine();
    const RoutePlan back = planRoute(g, {210, 0}, {0, 0});  // against the one-way road
    EXPECT_FALSE(back.ok());
    EXPECT_EQ(back.problem, "no route for cars from node 2 to node 0");
    const RoutePlan same = planRoute(g, {1, 1}, {-1, -1});
    EXPECT_FALSE(same.ok());
    EXPECT_EQ(same.problem, "start and destination snap to the same junction (node 0)");
    const RoutePlan empty = planRoute(RoadGraph{}, {0, 0}, {100, 0});
    EXPECT_FALSE(empty.ok());
    EXPECT_EQ(empty.problem, "the road graph has no drivable road");
}
