// SPDX-License-Identifier: Apache-2.0
// Matching onto the active route: same scoring as MapMatcher (distance and heading), plus a
// penalty for jumping along the route away from the previous match, so that loops and
// out-and-back legs are followed in driving order.

#include "navmap/daemon/vehicle/route_line.h"

#include <algorithm>
#include <cmath>

#include "navmap/daemon/vehicle/map_matcher.h"

namespace navmap::daemon {

namespace {
constexpr double kRadToDeg = 57.29577951308232;
}

RouteLine::RouteLine(std::string id, const std::vector<map::PlanarPoint>& points) : m_id(std::move(id)) {
    for (const auto& p : points) {
        if (!std::isfinite(p.x) || !std::isfinite(p.y)) continue;
        if (!m_points.empty() && std::hypot(p.x - m_points.back().x, p.y - m_points.back().y) < 1e-6) continue;
        m_measures.push_back(
            m_points.empty() ? 0.0 : m_measures.back() + std::hypot(p.x - m_points.back().x, p.y - m_points.back().y));
        m_points.push_back(p);
    }
}

std::optional<RouteMatch> RouteLine::match(map::PlanarPoint p, std::optional<double> heading_deg,
                                           std::optional<double> previous_measure,
                                           const VehicleStateConfig& cfg) const {
    std::optional<RouteMatch> best;
    double best_score = 0.0;
    for (std::size_t i = 0; i + 1 < m_points.size(); ++i) {
        const auto& a = m_points[i];
        const auto& b = m_points[i + 1];
        const double dx = b.x - a.x, dy = b.y - a.y;
        const double len2 = dx * dx + dy * dy;
        const double t = std::clamp(((p.x - a.x) * dx + (p.y - a.y) * dy) / len2, 0.0, 1.0);
        const map::PlanarPoint q{a.x + t * dx, a.y + t * dy};
        const double d = std::hypot(p.x - q.x, p.y - q.y);
        if (d > cfg.match_radius_m) continue;
        double h = std::atan2(dx, dy) * kRadToDeg;
        if (h < 0) h += 360.0;
        double dh = 0.0;
        if (heading_deg) {
            dh = std::fmod(*heading_deg - h, 360.0);
            if (dh > 180.0) dh -= 360.0;
            if (dh < -180.0) dh += 360.0;
        }
        const double measure = m_measures[i] + t * std::sqrt(len2);
        const double zd = d / cfg.match_sigma_m;
        const double zh = dh / cfg.match_sigma_heading_deg;
        double score = zd * zd + (heading_deg ? zh * zh : 0.0);
        if (previous_measure) {
            // Far along the route from the previous match: unlikely (100 m ~ one sigma).
            const double jump = (measure - *previous_measure) / 100.0;
            score += jump * jump;
        }
        if (!best || score < best_score) {
            best_score = score;
            best = RouteMatch{q, h, measure, d, matchConfidence(d, dh, heading_deg.has_value(), cfg)};
        }
    }
    return best;
}

}  // namespace navmap::daemon
