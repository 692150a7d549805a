#include "navmap/sim/drive_route.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <unordered_map>
#include <unordered_set>

namespace navmap::sim {

namespace {

constexpr double kLinkCapKmh = 60.0;
constexpr double kTurnProbeM = 20.0;  // heading before/after a junction over this distance

double headingBetween(map::PlanarPoint a, map::PlanarPoint b) {
    return std::atan2(b.x - a.x, b.y - a.y) * 180.0 / std::numbers::pi;  // clockwise from north
}

double wrap180(double deg) {
    double d = std::fmod(deg + 180.0, 360.0);
    if (d < 0) d += 360.0;
    return d - 180.0;
}

// Turn angle (positive = right) -> protocol maneuver type.
std::string typeFor(double turn) {
    const double a = std::abs(turn);
    const char* side = turn > 0 ? "right" : "left";
    if (a < 25.0) return "straight";
    if (a < 60.0) return std::string("slight_") + side;
    if (a < 135.0) return std::string("turn_") + side;
    if (a < 170.0) return std::string("sharp_") + side;
    return "u_turn";
}

std::string roundaboutText(double turn) {
    const double a = std::abs(turn);
    if (a < 45.0) return "exit straight on";
    if (a > 150.0) return "exit back";
    return std::string("exit to the ") + (turn > 0 ? "right" : "left");
}

double turnAt(const std::vector<map::RoutePoint>& line, std::size_t i, std::size_t exit) {
    const double m_in = line[i].measure_m;
    const double m_out = line[exit].measure_m;
    const auto before = map::sampleRoute(line, std::max(0.0, m_in - kTurnProbeM)).position;
    const auto after = map::sampleRoute(line, std::min(line.back().measure_m, m_out + kTurnProbeM)).position;
    if (m_in <= 0.0 || m_out >= line.back().measure_m) return 0.0;
    return wrap180(headingBetween(line[exit].position, after) - headingBetween(before, line[i].position));
}

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
        if ((e.flags & map::RoadFlags::Link) != 0) v = std::min(v, kLinkCapKmh);
        r.segment_speed_kmh.push_back(static_cast<float>(v));
        r.segment_class.push_back(e.cls);
    }

    // Junction degree (distinct neighbours) of the nodes the route passes.
    std::unordered_map<std::uint32_t, std::unordered_set<std::uint32_t>> neighbours;
    std::unordered_set<std::uint32_t> wanted;
    for (std::uint32_t ei : groute.edges) wanted.insert(graph.edges[ei].from);
    for (const map::GraphEdge& e : graph.edges) {
        if (wanted.count(e.from) != 0) neighbours[e.from].insert(e.to);
        if (wanted.count(e.to) != 0) neighbours[e.to].insert(e.from);
    }

    for (std::size_t i = 1; i + 1 < r.line.size(); ++i) {
        const std::uint32_t in_edge = r.line[i].edge;
        const std::uint32_t out_edge = r.line[i + 1].edge;
        if (in_edge == out_edge) continue;
        const map::GraphEdge& out = graph.edges[out_edge];
        const bool in_round = (graph.edges[in_edge].flags & map::RoadFlags::Roundabout) != 0;
        const bool out_round = (out.flags & map::RoadFlags::Roundabout) != 0;
        if (in_round) continue;  // exits are part of the roundabout maneuver
        if (out_round) {
            std::size_t exit = i + 1;
            while (exit + 1 < r.line.size() &&
                   (graph.edges[r.line[exit + 1].edge].flags & map::RoadFlags::Roundabout) != 0) {
                ++exit;
            }
            const double turn = turnAt(r.line, i, exit);
            r.maneuvers.push_back({i, r.line[i].measure_m, "roundabout", roundaboutText(turn), turn});
            continue;
        }
        const auto it = neighbours.find(out.from);
        const std::size_t degree = it == neighbours.end() ? 0 : it->second.size();
        const double turn = turnAt(r.line, i, i);
        if (degree >= 3 && std::abs(turn) >= 25.0) {
            r.maneuvers.push_back({i, r.line[i].measure_m, typeFor(turn), "", turn});
        }
    }
    addEnds(r);
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

}  // namespace navmap::sim
