// SPDX-License-Identifier: Apache-2.0
#pragma once
// The route a simulated car drives: the polyline in the store frame with measures, the legal /
// class speed of every segment, and the maneuvers at junctions (for the control IPC set_route).

#include <cstdint>
#include <string>
#include <vector>

#include "navmap/ipc/net/result.h"
#include "navmap/map/guidance/way_names.h"
#include "navmap/map/road_graph.h"
#include "navmap/map/routing.h"

namespace navmap::sim {

/// A turn instruction at a point of the route polyline.
struct Maneuver {
    std::size_t point = 0;   ///< index into DriveRoute::line
    double measure_m = 0.0;  ///< distance from the route start
    /// Control-protocol name (docs/ipc.md): "depart", "arrive", "straight", "turn_left",
    /// "slight_right", "sharp_left", "u_turn", "roundabout", ...
    std::string type;
    std::string text;           ///< street name (else ref) of the road taken; may be empty
    double turn_deg = 0.0;      ///< signed heading change, positive = right (clockwise)
    int exit = 0;               ///< roundabout exit counted from the entry (1 = first); 0 = none
    std::size_t end_point = 0;  ///< index into DriveRoute::line where it is done (a roundabout's exit)
};

struct DriveRoute {
    std::vector<map::RoutePoint> line;  ///< store frame, at least 2 points
    /// Target (legal or class) speed of segment i = line[i] -> line[i + 1], km/h.
    std::vector<float> segment_speed_kmh;
    std::vector<map::RoadClass> segment_class;
    std::vector<Maneuver> maneuvers;
    double graph_duration_s = 0.0;  ///< A* travel-time estimate at the edges' speeds

    [[nodiscard]] double length() const { return line.empty() ? 0.0 : line.back().measure_m; }
};

/// The DriveRoute of a graph route (map::planRoute): target speed per segment is the edge's
/// maxspeed or class default (RoadGraph::speed_kmh), link ramps capped at 60 km/h; classes and
/// maneuvers from the graph.
DriveRoute driveRouteFromGraph(const map::RoadGraph& graph, const map::GraphRoute& route);

/// The maneuvers of a graph route's polyline (map::guidance::deriveManeuvers, docs/guidance.md),
/// with street names from `names` (may be null).
std::vector<Maneuver> graphManeuvers(const map::RoadGraph& graph, const std::vector<map::RoutePoint>& line,
                                     const map::guidance::WayNames* names = nullptr);

/// A route over a bare polyline with one speed (tests, synthetic drives); no maneuvers except
/// depart/arrive.
DriveRoute driveRouteFromPolyline(const std::vector<map::PlanarPoint>& points, float speed_kmh,
                                  map::RoadClass cls = map::RoadClass::Primary);

}  // namespace navmap::sim
