// SPDX-License-Identifier: Apache-2.0
// Matching onto the active route: same scoring as MapMatcher (distance and heading), plus a
// penalty for jumping along the route away from the previous match, so that loops and
// out-and-back legs are followed in driving order.

#include "navmap/daemon/vehicle/route_line.h"

#include <algorithm>
#include <cmath>
#include <cstddef>

#include "navmap/daemon/vehicle/map_matcher.h"

namespace navmap::daemon {

namespace {
constexpr double kRadToDeg = 57.29577951308232;
// A jump of this far along the route from the previous match costs one sigma of the score.
constexpr double kJumpSigmaM = 100.0;
// Matching looks this far along the route around the previous match first (RouteLine::match).
constexpr double kWindowM = 1000.0;
}  // namespace

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
    std::size_t best_segment = 0;  // ties go to the earlier segment, as in one scan from the start
    // Segments first .. last - 1.
    auto scan = [&](std::size_t first, std::size_t last) {
        for (std::size_t i = first; i < last; ++i) {
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
                const double jump = (measure - *previous_measure) / kJumpSigmaM;
                score += jump * jump;
            }
            if (!best || score < best_score || (score == best_score && i < best_segment)) {
                best_score = score;
                best_segment = i;
                best = RouteMatch{q, h, measure, d, matchConfidence(d, dh, heading_deg.has_value(), cfg)};
            }
        }
    };
    const std::size_t segments = m_points.size() < 2 ? 0 : m_points.size() - 1;
    if (previous_measure && segments > 0) {
        // Near the previous match first: the segments within kWindowM of it along the route. Any
        // segment beyond scores at least (kWindowM / kJumpSigmaM)^2, so a match in the window
        // that scores no more is the best of the whole route: the work per pose is bounded by
        // the window, not by the route's length.
        const auto lo = std::lower_bound(m_measures.begin(), m_measures.end(), *previous_measure - kWindowM);
        const auto hi = std::upper_bound(m_measures.begin(), m_measures.end(), *previous_measure + kWindowM);
        const std::size_t first = static_cast<std::size_t>(std::max<std::ptrdiff_t>(0, lo - m_measures.begin() - 1));
        const std::size_t last = std::min(segments, static_cast<std::size_t>(hi - m_measures.begin()));
        scan(first, last);
        const double bound = (kWindowM / kJumpSigmaM) * (kWindowM / kJumpSigmaM);
        if (!(best && best_score <= bound)) {
            // Not found near: the rest of the route (a jump, or a pose far from the previous one).
            scan(0, first);
            scan(last, segments);
        }
    } else {
        scan(0, segments);
    }
    return best;
}

}  // namespace navmap::daemon
