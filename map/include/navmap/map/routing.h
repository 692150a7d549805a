// SPDX-License-Identifier: Apache-2.0
#pragma once
// Shortest routes on the compiled road graph (A*, travel time), and the geometry of a route:
// the polyline the vehicle follows, with the distance along it at every point.

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "navmap/map/geometry.h"
#include "navmap/map/road_graph.h"

namespace navmap::map {

struct GraphRoute {
    std::vector<std::uint32_t> edges;  ///< indices into RoadGraph::edges, in driving order
    double length_m = 0.0;
    double duration_s = 0.0;  ///< at the edges' speeds
};

/// A point on the route polyline.
struct RoutePoint {
    PlanarPoint position;    ///< store frame
    double measure_m = 0.0;  ///< distance from the route start
    std::uint32_t edge = 0;  ///< graph edge this point belongs to
};

/// Nearest graph node to a store-frame position that has outgoing edges usable by cars
/// (class above Track), or nullopt for an empty graph.
std::optional<std::uint32_t> nearestDrivableNode(const RoadGraph& graph, PlanarPoint p);

/// Fastest route for a car (tracks, paths and pedestrian ways excluded; one-way respected).
std::optional<GraphRoute> fastestRoute(const RoadGraph& graph, std::uint32_t from, std::uint32_t to);

/// A car route between two positions, or why there is none.
struct RoutePlan {
    std::optional<GraphRoute> route;
    /// "the road graph has no drivable road", "start and destination snap to the same junction
    /// (node 12)", "no route for cars from node 12 to node 345"; empty when there is a route.
    std::string problem;
    [[nodiscard]] bool ok() const { return route.has_value(); }
};

/// The route planner of navmapd's simulator, the tools and the tests: the fastest car route
/// (fastestRoute, A* on travel time) between the drivable nodes nearest to two store-frame
/// positions (nearestDrivableNode). Never throws; RoutePlan::problem says why there is none.
[[nodiscard]] RoutePlan planRoute(const RoadGraph& graph, PlanarPoint from, PlanarPoint to);

/// The route's polyline with measures (duplicate joints removed).
std::vector<RoutePoint> routePolyline(const RoadGraph& graph, const GraphRoute& route);

/// Position and heading (degrees clockwise from north) at `measure_m` along a polyline.
struct RouteSample {
    PlanarPoint position;
    double heading_deg = 0.0;
    std::size_t segment = 0;  ///< index of the polyline segment
};
RouteSample sampleRoute(const std::vector<RoutePoint>& line, double measure_m);

}  // namespace navmap::map
