// SPDX-License-Identifier: Apache-2.0
#include "route_state.h"

#include <algorithm>
#include <cmath>
#include <vector>

namespace navmap::daemon {

std::vector<std::pair<double, double>> routeTunnels(const MapMatcher& matcher,
                                                    const std::vector<map::PlanarPoint>& points,
                                                    const std::vector<double>& measures) {
    constexpr double kStepM = 5.0;
    VehicleStateConfig cfg;
    cfg.match_radius_m = 10.0;
    const map::RoadGraph& g = matcher.graph();
    std::vector<std::pair<double, double>> out;
    std::optional<std::uint32_t> previous;
    const double total = measures.empty() ? 0.0 : measures.back();
    for (std::size_t i = 0; i + 1 < points.size() && i + 1 < measures.size(); ++i) {
        const map::PlanarPoint a = points[i], b = points[i + 1];
        const double len = std::hypot(b.x - a.x, b.y - a.y);
        if (!(len > 0.0)) continue;
        double heading = std::atan2(b.x - a.x, b.y - a.y) * 57.29577951308232;
        if (heading < 0.0) heading += 360.0;
        const int n = std::max(1, static_cast<int>(std::ceil(len / kStepM)));
        const double half = 0.5 * (measures[i + 1] - measures[i]) / n;
        for (int j = 0; j < n; ++j) {
            const double f = (j + 0.5) / n;
            const auto m = matcher.match({a.x + f * (b.x - a.x), a.y + f * (b.y - a.y)}, heading, previous, cfg);
            previous = m && m->confidence >= 0.5 ? std::optional<std::uint32_t>(m->edge) : std::nullopt;
            if (!previous || !(g.edges[*previous].flags & map::road_flags::kTunnel)) continue;
            const double at = measures[i] + f * (measures[i + 1] - measures[i]);
            const double from = std::max(0.0, at - half), to = std::min(total, at + half);
            if (!out.empty() && from - out.back().second <= 2.0 * kStepM)
                out.back().second = to;
            else
                out.emplace_back(from, to);
        }
    }
    return out;
}

bool RouteState::update(const std::shared_ptr<const ipc::RouteState>& route) {
    if (!route) {
        // clear_route: nothing to draw or match from now on.
        if (m_id.empty() && !m_line) return false;
        m_version = ~std::uint64_t{0};
        ++m_conversions;
        m_id.clear();
        m_control_points = 0;
        m_driven_m = 0.0;
        m_line = nullptr;
        m_control = nullptr;
        const std::uint64_t geometry_version = m_geometry.version + 1;
        m_geometry = {};
        m_geometry.version = geometry_version;
        return true;
    }
    if (route->version == m_version) return false;
    m_version = route->version;
    ++m_conversions;
    m_id = route->id;
    m_control_points = route->points.size();
    m_driven_m = 0.0;
    m_control = route;
    convert();
    return true;
}

void RouteState::rebase(const map::Projection& frame) {
    m_projection = frame;
    if (m_line) convert();
}

void RouteState::convert() {
    // The points as RouteLine keeps them (finite, repeats dropped), and the same points in the
    // tunnel graph's frame, one for one.
    std::vector<map::PlanarPoint> points, graph_points;
    points.reserve(m_control->points.size());
    for (const auto& p : m_control->points) {
        const map::PlanarPoint q = m_projection.forward(p.lat_deg, p.lon_deg);
        if (!std::isfinite(q.x) || !std::isfinite(q.y)) continue;
        if (!points.empty() && std::hypot(q.x - points.back().x, q.y - points.back().y) < 1e-6) continue;
        points.push_back(q);
        if (m_tunnels) graph_points.push_back(m_tunnels->frame.forward(p.lat_deg, p.lon_deg));
    }
    m_line = points.size() >= 2 ? std::make_shared<const RouteLine>(m_id, points) : nullptr;
    // The renderers re-drape the route when the geometry's version changes.
    const std::uint64_t geometry_version = m_geometry.version + 1;
    m_geometry = {};
    m_geometry.version = geometry_version;
    if (m_line) {
        for (const auto& p : m_line->points()) m_geometry.points.emplace_back(p.x, p.y, 0.0);
        m_geometry.measure_m = m_line->measures();
        if (m_tunnels && m_tunnels->graph && m_line->points().size() == graph_points.size()) {
            if (!m_tunnel_matcher) m_tunnel_matcher = std::make_shared<const MapMatcher>(m_tunnels->graph);
            m_geometry.tunnels_m = routeTunnels(*m_tunnel_matcher, graph_points, m_line->measures());
        }
    }
}

void RouteState::track(const EstimatedPose& pose) {
    if (pose.on_route) m_driven_m = std::max(m_driven_m, pose.route_driven_m);
}

double RouteState::remainingM() const { return std::max(0.0, lengthM() - m_driven_m); }

}  // namespace navmap::daemon
