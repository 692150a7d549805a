// SPDX-License-Identifier: Apache-2.0
// Dead reckoning along the road graph (graph_walk.h; not from the seed: docs/vehicle-state.md
// "Tunnels").

#include "graph_walk.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace navmap::daemon {

namespace {

constexpr double kRadToDeg = 57.29577951308232;
// How far along a candidate edge its distance from the route is measured at a junction, metres.
constexpr double kLookAheadM = 15.0;
// A walk that has passed no tunnel after this many metres ends there (null).
constexpr double kTunnelWithinM = 500.0;
// The most edges one walk passes (a bound on the work whatever the graph).
constexpr int kMaxEdges = 4096;

bool drivable(const map::GraphEdge& e) { return e.cls < map::RoadClass::Pedestrian; }  // as MapMatcher

// The shape of an edge in its direction of travel.
struct Shape {
    const map::RoadGraph& g;
    const map::GraphEdge& e;
    [[nodiscard]] std::uint32_t size() const { return e.shape_end - e.shape_begin; }
    [[nodiscard]] map::PlanarPoint at(std::uint32_t k) const {
        const bool rev = (e.flags & map::edge_flags::kReversed) != 0;
        const map::LocalPoint& p = g.shape[rev ? e.shape_end - 1 - k : e.shape_begin + k];
        return {p.x, p.y};
    }
};

bool validEdge(const map::RoadGraph& g, std::uint32_t edge) {
    if (edge >= g.edges.size()) return false;
    const map::GraphEdge& e = g.edges[edge];
    return e.shape_end <= g.shape.size() && e.shape_end >= e.shape_begin + 2;
}

// The point `along_m` along an edge's shape (its end beyond).
map::PlanarPoint pointAlong(const Shape& s, double along_m) {
    for (std::uint32_t k = 0; k + 1 < s.size(); ++k) {
        const map::PlanarPoint a = s.at(k), b = s.at(k + 1);
        const double len = std::hypot(b.x - a.x, b.y - a.y);
        if (along_m <= len && len > 0.0) return {a.x + (b.x - a.x) * along_m / len, a.y + (b.y - a.y) * along_m / len};
        along_m -= len;
    }
    return s.at(s.size() - 1);
}

double headingDeg(map::PlanarPoint a, map::PlanarPoint b) {
    const double h = std::atan2(b.x - a.x, b.y - a.y) * kRadToDeg;
    return h < 0 ? h + 360.0 : h;
}

double turnDeg(double from, double to) {
    double d = std::fmod(to - from + 540.0, 360.0) - 180.0;
    return std::abs(d);
}

// The edge to go on with from the end of `edge`, or none (a dead end): the one that follows the
// route (the route's match confidence at a point kLookAheadM along it, in its direction) where
// some candidate matches it, else the straightest, preferring the same tunnel-ness and the same
// way.
std::optional<std::uint32_t> nextEdge(const map::RoadGraph& g, std::uint32_t edge, double arrival_heading_deg,
                                      const RouteLine* route, std::optional<double> route_measure,
                                      const VehicleStateConfig& cfg) {
    const map::GraphEdge& e = g.edges[edge];
    const std::uint32_t first = g.first_edge[e.to];
    std::optional<std::uint32_t> by_route, by_road;
    double best_route = std::numeric_limits<double>::infinity(), best_road = best_route;
    for (std::uint32_t i = first; i < first + g.outEdges(e.to).size(); ++i) {
        const map::GraphEdge& c = g.edges[i];
        if (!drivable(c) || !validEdge(g, i)) continue;
        if (c.to == e.from && c.way_id == e.way_id && c.shape_begin == e.shape_begin) continue;  // the U-turn
        const Shape s{g, c};
        const map::PlanarPoint ahead = pointAlong(s, kLookAheadM);
        const double heading = headingDeg(s.at(0), s.at(1));
        const double score = turnDeg(arrival_heading_deg, heading) + (c.way_id == e.way_id ? 0.0 : 30.0) +
                             (((c.flags ^ e.flags) & map::road_flags::kTunnel) != 0 ? 60.0 : 0.0);
        if (route) {
            // The route's confidence there, distance and direction (a road back along the route
            // lies on it too), the straighter one where two agree alike.
            const auto m = route->match(ahead, heading, route_measure, cfg);
            const double agree = m ? m->confidence - 1e-6 * score : 0.0;
            if (m && m->confidence >= cfg.snap_min_confidence && -agree < best_route) {
                best_route = -agree;
                by_route = i;
            }
        }
        if (score < best_road) {
            best_road = score;
            by_road = i;
        }
    }
    return by_route ? by_route : by_road;
}

}  // namespace

std::optional<GraphWalk> walkGraph(const map::RoadGraph& g, std::uint32_t edge, map::PlanarPoint start,
                                   double distance_m, const RouteLine* route, std::optional<double> route_measure,
                                   const VehicleStateConfig& cfg) {
    if (!validEdge(g, edge) || !std::isfinite(distance_m)) return std::nullopt;
    // The start: the nearest point of the edge's shape.
    std::uint32_t k = 0;
    double s = 0.0;  // metres from shape point k
    {
        const Shape shape{g, g.edges[edge]};
        double best = std::numeric_limits<double>::infinity();
        for (std::uint32_t i = 0; i + 1 < shape.size(); ++i) {
            const map::PlanarPoint a = shape.at(i), b = shape.at(i + 1);
            const double dx = b.x - a.x, dy = b.y - a.y, len2 = dx * dx + dy * dy;
            const double t =
                len2 > 0.0 ? std::clamp(((start.x - a.x) * dx + (start.y - a.y) * dy) / len2, 0.0, 1.0) : 0.0;
            const double d = std::hypot(start.x - (a.x + t * dx), start.y - (a.y + t * dy));
            if (d < best) {
                best = d;
                k = i;
                s = t * std::sqrt(len2);
            }
        }
    }
    GraphWalk w;
    double left = std::max(0.0, distance_m);
    for (int edges = 0; edges < kMaxEdges; ++edges) {
        const map::GraphEdge& e = g.edges[edge];
        const bool tunnel = (e.flags & map::road_flags::kTunnel) != 0;
        w.tunnel = w.tunnel || tunnel;
        if (tunnel) w.beyond_tunnel_m = 0.0;
        const Shape shape{g, e};
        double heading = 0.0;
        for (; k + 1 < shape.size(); ++k, s = 0.0) {
            const map::PlanarPoint a = shape.at(k), b = shape.at(k + 1);
            const double len = std::hypot(b.x - a.x, b.y - a.y);
            if (len <= 0.0) continue;
            heading = headingDeg(a, b);
            const double rest = std::max(0.0, len - s);
            if (left <= rest) {
                const double at = (s + left) / len;
                w.edge = edge;
                w.point = {a.x + (b.x - a.x) * at, a.y + (b.y - a.y) * at};
                w.heading_rad = heading / kRadToDeg;
                w.in_tunnel = tunnel;
                if (w.tunnel && !tunnel) w.beyond_tunnel_m += left;
                return w;
            }
            left -= rest;
            if (w.tunnel && !tunnel) w.beyond_tunnel_m += rest;
        }
        // No tunnel this far: the walk would not be used (the work stays bounded when GNSS is
        // lost on open roads).
        if (!w.tunnel && distance_m - left > kTunnelWithinM) return std::nullopt;
        const auto next = nextEdge(g, edge, heading, route, route_measure, cfg);
        if (!next) {
            w.edge = edge;
            w.point = shape.at(shape.size() - 1);
            w.heading_rad = heading / kRadToDeg;
            w.in_tunnel = tunnel;  // a dead end: it stops at the node
            return w;
        }
        edge = *next;
        k = 0;
        s = 0.0;
    }
    return std::nullopt;  // beyond kMaxEdges: not followed
}

}  // namespace navmap::daemon
