// SPDX-License-Identifier: Apache-2.0
#include "navmap/map/guidance/route_progress_tracker.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace navmap::map::guidance {

namespace {

constexpr double kBackPenalty = 0.1;

}  // namespace

RouteProgressTracker::RouteProgressTracker(std::shared_ptr<const GuidanceRoute> route, ProgressConfig config)
    : m_route(std::move(route)), m_config(config) {
    if (!m_route) throw std::runtime_error("RouteProgressTracker: no route");
    reset();
}

void RouteProgressTracker::reset() {
    m_started = false;
    m_progress = RouteProgress{};
    const auto& pts = m_route->points();
    if (!pts.empty()) m_progress.on_route = pts.front();
    fill(0.0, Match{0.0, 0.0, m_progress.on_route});
}

std::optional<RouteProgressTracker::Match> RouteProgressTracker::nearest(PlanarPoint p, double from_m,
                                                                         double to_m) const {
    const auto& pts = m_route->points();
    const auto& ms = m_route->measures();
    if (pts.empty()) return std::nullopt;
    if (pts.size() == 1) return Match{0.0, std::hypot(p.x - pts[0].x, p.y - pts[0].y), pts[0]};
    // Segments overlapping [from_m, to_m]: the first whose end reaches from_m to the last whose
    // start lies before to_m.
    const std::size_t first = static_cast<std::size_t>(
        std::max<std::ptrdiff_t>(1, std::lower_bound(ms.begin(), ms.end(), from_m) - ms.begin()) - 1);
    const std::size_t last = std::min<std::size_t>(
        pts.size() - 1, static_cast<std::size_t>(std::upper_bound(ms.begin(), ms.end(), to_m) - ms.begin()));
    std::optional<Match> best;
    double best_score = 0.0;
    for (std::size_t i = first; i < last; ++i) {
        const PlanarPoint a = pts[i];
        const PlanarPoint b = pts[i + 1];
        const double dx = b.x - a.x;
        const double dy = b.y - a.y;
        const double len2 = dx * dx + dy * dy;
        double t = len2 > 0.0 ? ((p.x - a.x) * dx + (p.y - a.y) * dy) / len2 : 0.0;
        // Keep the match inside the window also within a segment that straddles its edge.
        const double seg = ms[i + 1] - ms[i];
        if (seg > 0.0) t = std::clamp(t, (from_m - ms[i]) / seg, (to_m - ms[i]) / seg);
        t = std::clamp(t, 0.0, 1.0);
        const PlanarPoint q{a.x + dx * t, a.y + dy * t};
        const double d = std::hypot(p.x - q.x, p.y - q.y);
        const double measure = ms[i] + seg * t;
        // Where the route passes a place twice (or comes back along the same road) two matches
        // lie equally close: going back costs kBackPenalty metres per metre behind the progress,
        // so the pass ahead wins; at an exact tie without progress the earlier pass does.
        const double score = d + (m_started ? kBackPenalty * std::max(0.0, m_progress.measure_m - measure) : 0.0);
        if (!best || score < best_score) {
            best = Match{measure, d, q};
            best_score = score;
        }
    }
    return best;
}

const RouteProgress& RouteProgressTracker::update(PlanarPoint pose) {
    if (!std::isfinite(pose.x) || !std::isfinite(pose.y)) {
        ++m_ignored;
        return m_progress;
    }
    const double length = m_route->lengthM();
    std::optional<Match> m;
    if (!m_started) {
        m = nearest(pose, 0.0, length);
    } else {
        const double from = std::max(0.0, m_progress.measure_m - m_config.back_window_m);
        m = nearest(pose, from, m_progress.measure_m + m_config.forward_window_m);
        if (m && m->distance > m_config.reacquire_m) {
            // Lost in the window: take the nearest point of the route ahead, never behind it.
            const auto ahead = nearest(pose, from, length);
            if (ahead && ahead->distance < m->distance) {
                m = ahead;
                ++m_reacquired;
            }
        }
    }
    if (!m) return m_progress;
    m_started = true;
    fill(m->measure, *m);
    return m_progress;
}

void RouteProgressTracker::fill(double match_measure, const Match& m) {
    RouteProgress& p = m_progress;
    const double length = m_route->lengthM();
    p.match_measure_m = match_measure;
    p.measure_m = std::max(p.measure_m, match_measure);
    p.on_route = m.point;
    p.offset_m = m.distance;
    p.remaining_m = std::max(0.0, length - p.measure_m);
    p.remaining_s = std::max(0.0, m_route->durationS() - m_route->secondsAt(p.measure_m));
    p.arrived = m_started && p.remaining_m <= m_config.arrive_radius_m;
    const auto& man = m_route->maneuvers();
    // A manoeuvre is passed once the progress is beyond its end (a roundabout's exit), so a
    // roundabout stays the next manoeuvre from its entry to its exit.
    while (p.passed < man.size() && p.measure_m >= man[p.passed].end_measure_m + m_config.pass_after_m &&
           man[p.passed].type != ManeuverType::Arrive) {
        ++p.passed;
    }
    p.next.reset();
    for (std::size_t k = p.passed; k < man.size(); ++k) {
        if (man[k].type == ManeuverType::Depart) continue;
        p.next = k;
        break;
    }
    p.to_next_m = p.next ? std::max(0.0, man[*p.next].measure_m - p.measure_m) : 0.0;
}

}  // namespace navmap::map::guidance
