// SPDX-License-Identifier: Apache-2.0
#pragma once
// Dead reckoning along the road graph (docs/vehicle-state.md "Tunnels"): from a point on a
// matched edge, a distance driven is walked along the edges' shapes, through junctions onto the
// edge that follows the route (where one is set and near) or else the road ahead. Private to
// navmap_vehicle_state.

#include <cstdint>
#include <optional>

#include "navmap/daemon/vehicle/route_line.h"
#include "navmap/daemon/vehicle/vehicle_state_config.h"
#include "navmap/map/projection.h"
#include "navmap/map/road_graph.h"

namespace navmap::daemon {

struct GraphWalk {
    std::uint32_t edge = 0;        ///< the edge the walk ends on
    map::PlanarPoint point;        ///< where it ends
    double heading_rad = 0.0;      ///< the edge's direction there, clockwise from north
    bool tunnel = false;           ///< some edge walked (the first included) is in a tunnel
    bool in_tunnel = false;        ///< the edge it ends on is
    double beyond_tunnel_m = 0.0;  ///< walked since the last tunnel edge ended (0 inside one)
};

/// Walks `distance_m` (>= 0) from the point of `edge` nearest `start`. `route` (may be null) and
/// `route_measure` (the previous route match) choose the way at junctions. Null when `edge` is
/// not an edge of `graph` or has no shape, and when the walk passes no tunnel edge within its
/// first 500 m (it would not be used, GraphWalk::tunnel).
std::optional<GraphWalk> walkGraph(const map::RoadGraph& graph, std::uint32_t edge, map::PlanarPoint start,
                                   double distance_m, const RouteLine* route, std::optional<double> route_measure,
                                   const VehicleStateConfig& cfg);

}  // namespace navmap::daemon
