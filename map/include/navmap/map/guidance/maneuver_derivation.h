// SPDX-License-Identifier: Apache-2.0
#pragma once
// Manoeuvres derived from a route's geometry on the road graph (docs/guidance.md "Manoeuvres"):
// turn classes by the heading change at junctions that offer a choice, forks as keep_left /
// keep_right, a roundabout as one manoeuvre with its exit number, depart and arrive. Pure
// functions, thread-safe.

#include <vector>

#include "navmap/map/guidance/maneuver.h"
#include "navmap/map/guidance/way_names.h"
#include "navmap/map/road_graph.h"
#include "navmap/map/routing.h"

namespace navmap::map::guidance {

struct DeriveOptions {
    TurnThresholds turns;
    /// Headings are measured over this distance before and after a junction (along the route
    /// before it, along each way leaving it), metres.
    double probe_m = 20.0;
    /// Two drivable ways leaving a junction within this angle of straight ahead make a fork:
    /// the route's one is keep_left / keep_right, degrees.
    double fork_deg = 45.0;
};

/// Manoeuvres of `line` (map::routePolyline of a route on `graph`: every point carries the
/// graph edge it belongs to, a junction is where that edge changes), in route order, starting
/// with Depart and ending with Arrive (empty for fewer than 2 points). `names` (may be null)
/// fills Maneuver::street and lets two differently split ways of one named street count as
/// the same road. Edge indices outside the graph are a broken invariant of the caller: such
/// junctions are skipped.
std::vector<Maneuver> deriveManeuvers(const RoadGraph& graph, const std::vector<RoutePoint>& line,
                                      const WayNames* names = nullptr, const DeriveOptions& options = {});

}  // namespace navmap::map::guidance
