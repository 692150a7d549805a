// SPDX-License-Identifier: Apache-2.0
#include "navmap/sim/drive_route.h"

#include <algorithm>
#include <cmath>

#include "navmap/map/guidance/maneuver_derivation.h"

namespace navmap::sim {

namespace {

constexpr double kLinkCapKmh = 60.0;

void addEnds(DriveRoute& r) {
    if (r.line.size() < 2) return;
    r.maneuvers.insert(r.maneuvers.begin(), Maneuver{0, 0.0, "depart", "", 0.0});
    r.maneuvers.push_back(Maneuver{r.line.size() - 1, r.line.back().measure_m, "arrive", "", 0.0});
}

}  // namespace

DriveRoute driveRouteFromGraph(const map::RoadGraph& graph, const map::GraphRoute& groute) {
    DriveRoute r;
    r.line = map::routePolyline(graph, groute);
    r.graph_duration_s = groute.duration_s;
    if (r.line.size() < 2) return r;
    r.segment_speed_kmh.reserve(r.line.size() - 1);
    r.segment_class.reserve(r.line.size() - 1);
    for (std::size_t i = 0; i + 1 < r.line.size(); ++i) {
        // routePolyline drops the duplicate first point of every edge, so segment i belongs to
        // the edge of its end point.
        const map::GraphEdge& e = graph.edges[r.line[i + 1].edge];
        double v = std::max(5.0, static_cast<double>(e.speed_kmh));
        if ((e.flags & map::road_flags::kLink) != 0) v = std::min(v, kLinkCapKmh);
        r.segment_speed_kmh.push_back(static_cast<float>(v));
        r.segment_class.push_back(e.cls);
    }
    r.maneuvers = graphManeuvers(graph, r.line);
    return r;
}

DriveRoute driveRouteFromPolyline(const std::vector<map::PlanarPoint>& points, float speed_kmh, map::RoadClass cls) {
    DriveRoute r;
    for (const map::PlanarPoint& p : points) {
        if (!r.line.empty()) {
            const double d = std::hypot(p.x - r.line.back().position.x, p.y - r.line.back().position.y);
            if (d < 1e-3) continue;
            r.line.push_back({p, r.line.back().measure_m + d, 0});
        } else {
            r.line.push_back({p, 0.0, 0});
        }
    }
    if (r.line.size() < 2) return r;
    r.segment_speed_kmh.assign(r.line.size() - 1, speed_kmh);
    r.segment_class.assign(r.line.size() - 1, cls);
    r.graph_duration_s = r.length() / (std::max(1.0f, speed_kmh) / 3.6);
    addEnds(r);
    return r;
}

std::vector<Maneuver> graphManeuvers(const map::RoadGraph& graph, const std::vector<map::RoutePoint>& line,
                                     const map::guidance::WayNames* names) {
    std::vector<Maneuver> out;
    for (const map::guidance::Maneuver& m : map::guidance::deriveManeuvers(graph, line, names)) {
        out.push_back({m.point, m.measure_m, std::string(map::guidance::maneuverTypeName(m.type)), m.street, m.turn_deg,
                       m.exit, m.end_point});
    }
    return out;
}

}  // namespace navmap::sim
