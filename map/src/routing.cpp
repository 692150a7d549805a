// SPDX-License-Identifier: Apache-2.0
#include "navmap/map/routing.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <queue>
#include <string>

namespace navmap::map {

namespace {

bool drivable(const GraphEdge& e) {
    return e.cls < RoadClass::Pedestrian;  // motorway .. service
}

double edgeSeconds(const GraphEdge& e) {
    const double speed = std::max(5.0, static_cast<double>(e.speed_kmh)) / 3.6;
    return e.length_m / speed;
}

}  // namespace

std::optional<std::uint32_t> nearestDrivableNode(const RoadGraph& graph, PlanarPoint p) {
    std::optional<std::uint32_t> best;
    double best_d = std::numeric_limits<double>::max();
    for (std::uint32_t n = 0; n < graph.nodes.size(); ++n) {
        bool ok = false;
        for (const auto& e : graph.outEdges(n)) ok |= drivable(e);
        if (!ok) continue;
        const double d = std::hypot(graph.nodes[n].x - p.x, graph.nodes[n].y - p.y);
        if (d < best_d) {
            best_d = d;
            best = n;
        }
    }
    return best;
}

std::optional<GraphRoute> fastestRoute(const RoadGraph& graph, std::uint32_t from, std::uint32_t to) {
    const std::size_t n = graph.nodes.size();
    if (from >= n || to >= n) return std::nullopt;
    double vmax = 1.0;
    for (const auto& e : graph.edges) vmax = std::max(vmax, static_cast<double>(e.speed_kmh) / 3.6);
    auto heuristic = [&](std::uint32_t a) {
        return std::hypot(graph.nodes[a].x - graph.nodes[to].x, graph.nodes[a].y - graph.nodes[to].y) / vmax;
    };
    std::vector<double> cost(n, std::numeric_limits<double>::infinity());
    std::vector<std::uint32_t> via(n, std::numeric_limits<std::uint32_t>::max());  // edge index
    using Item = std::pair<double, std::uint32_t>;
    std::priority_queue<Item, std::vector<Item>, std::greater<>> open;
    cost[from] = 0.0;
    open.push({heuristic(from), from});
    while (!open.empty()) {
        const auto [f, u] = open.top();
        open.pop();
        if (u == to) break;
        if (f - heuristic(u) > cost[u] + 1e-9) continue;  // stale entry
        for (std::uint32_t i = graph.first_edge[u]; i < graph.first_edge[u + 1]; ++i) {
            const GraphEdge& e = graph.edges[i];
            if (!drivable(e)) continue;
            const double c = cost[u] + edgeSeconds(e);
            if (c < cost[e.to]) {
                cost[e.to] = c;
                via[e.to] = i;
                open.push({c + heuristic(e.to), e.to});
            }
        }
    }
    if (!std::isfinite(cost[to])) return std::nullopt;
    GraphRoute route;
    for (std::uint32_t v = to; v != from;) {
        const std::uint32_t ei = via[v];
        route.edges.push_back(ei);
        route.length_m += graph.edges[ei].length_m;
        v = graph.edges[ei].from;
    }
    std::reverse(route.edges.begin(), route.edges.end());
    route.duration_s = cost[to];
    return route;
}

RoutePlan planRoute(const RoadGraph& graph, PlanarPoint from, PlanarPoint to) {
    RoutePlan plan;
    const auto a = nearestDrivableNode(graph, from);
    const auto b = nearestDrivableNode(graph, to);
    if (!a || !b) {
        plan.problem = "the road graph has no drivable road";
    } else if (*a == *b) {
        plan.problem = "start and destination snap to the same junction (node " + std::to_string(*a) + ")";
    } else if (auto route = fastestRoute(graph, *a, *b)) {
        plan.route = std::move(route);
    } else {
        plan.problem = "no route for cars from node " + std::to_string(*a) + " to node " + std::to_string(*b);
    }
    return plan;
}

std::vector<RoutePoint> routePolyline(const RoadGraph& graph, const GraphRoute& route) {
    std::vector<RoutePoint> line;
    auto add = [&](PlanarPoint p, std::uint32_t edge) {
        if (!line.empty()) {
            const double d = std::hypot(p.x - line.back().position.x, p.y - line.back().position.y);
            if (d < 1e-3) return;
            line.push_back({p, line.back().measure_m + d, edge});
        } else {
            line.push_back({p, 0.0, edge});
        }
    };
    for (std::uint32_t ei : route.edges) {
        const GraphEdge& e = graph.edges[ei];
        std::vector<PlanarPoint> pts;
        for (std::uint32_t s = e.shape_begin; s < e.shape_end && s < graph.shape.size(); ++s) {
            pts.push_back({graph.shape[s].x, graph.shape[s].y});
        }
        if (e.flags & edge_flags::kReversed) std::reverse(pts.begin(), pts.end());
        if (pts.empty()) {
            pts = {{graph.nodes[e.from].x, graph.nodes[e.from].y}, {graph.nodes[e.to].x, graph.nodes[e.to].y}};
        }
        for (const auto& p : pts) add(p, ei);
    }
    return line;
}

RouteSample sampleRoute(const std::vector<RoutePoint>& line, double measure_m) {
    RouteSample s;
    if (line.empty()) return s;
    if (line.size() == 1) {
        s.position = line[0].position;
        return s;
    }
    const double m = std::clamp(measure_m, 0.0, line.back().measure_m);
    const auto it =
        std::upper_bound(line.begin(), line.end(), m, [](double v, const RoutePoint& p) { return v < p.measure_m; });
    std::size_t i = static_cast<std::size_t>(std::max<std::ptrdiff_t>(1, it - line.begin())) - 1;
    i = std::min(i, line.size() - 2);
    const RoutePoint& a = line[i];
    const RoutePoint& b = line[i + 1];
    const double len = b.measure_m - a.measure_m;
    const double t = len > 0 ? (m - a.measure_m) / len : 0.0;
    s.position = {a.position.x + (b.position.x - a.position.x) * t, a.position.y + (b.position.y - a.position.y) * t};
    s.heading_deg = std::fmod(
        std::atan2(b.position.x - a.position.x, b.position.y - a.position.y) * 180.0 / std::numbers::pi + 360.0, 360.0);
    s.segment = i;
    return s;
}

}  // namespace navmap::map
