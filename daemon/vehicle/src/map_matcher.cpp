// SPDX-License-Identifier: Apache-2.0
// Map matching onto the road graph (docs/vehicle-state.md "Map matching"): nearest segment with
// heading agreement and hysteresis. The confidence is the product of two Gaussian terms, so it
// falls smoothly with distance and heading difference and the pose can be blended onto the road
// without a visible step.

#include "navmap/daemon/vehicle/map_matcher.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace navmap::daemon {

namespace {

constexpr double kRadToDeg = 57.29577951308232;

double headingOf(map::PlanarPoint a, map::PlanarPoint b) {
    double h = std::atan2(b.x - a.x, b.y - a.y) * kRadToDeg;
    return h < 0 ? h + 360.0 : h;
}

double angleDiff(double a, double b) {
    double d = std::fmod(a - b, 360.0);
    if (d > 180.0) d -= 360.0;
    if (d < -180.0) d += 360.0;
    return d;
}

bool drivable(const map::GraphEdge& e) {
    return e.cls < map::RoadClass::Pedestrian;  // motorway .. service, as routing
}

}  // namespace

double matchConfidence(double distance_m, double heading_diff_deg, bool use_heading, const VehicleStateConfig& cfg) {
    const double zd = distance_m / cfg.match_sigma_m;
    double c = std::exp(-0.5 * zd * zd);
    if (use_heading) {
        const double zh = heading_diff_deg / cfg.match_sigma_heading_deg;
        c *= std::exp(-0.5 * zh * zh);
    }
    return c;
}

MapMatcher::MapMatcher(std::shared_ptr<const map::RoadGraph> graph, double cell_m)
    : m_graph(std::move(graph)), m_cell(cell_m) {
    const auto& g = *m_graph;
    double max_x = -std::numeric_limits<double>::infinity();
    double max_y = max_x;
    m_min_x = m_min_y = std::numeric_limits<double>::infinity();
    for (std::uint32_t e = 0; e < g.edges.size(); ++e) {
        const auto& edge = g.edges[e];
        if (!drivable(edge) || edge.shape_end > g.shape.size() || edge.shape_end < edge.shape_begin + 2) {
            continue;
        }
        const bool rev = (edge.flags & map::edge_flags::kReversed) != 0;
        for (std::uint32_t k = edge.shape_begin; k + 1 < edge.shape_end; ++k) {
            map::PlanarPoint a{g.shape[k].x, g.shape[k].y};
            map::PlanarPoint b{g.shape[k + 1].x, g.shape[k + 1].y};
            if (rev) std::swap(a, b);
            if (a.x == b.x && a.y == b.y) continue;
            m_segments.push_back({a, b, e});
            m_min_x = std::min({m_min_x, a.x, b.x});
            m_min_y = std::min({m_min_y, a.y, b.y});
            max_x = std::max({max_x, a.x, b.x});
            max_y = std::max({max_y, a.y, b.y});
        }
    }
    m_segments.shrink_to_fit();  // kept for the daemon's life: no spare capacity from push_back
    if (m_segments.empty()) {
        return;
    }
    // A graph spanning a continent gets coarser cells, not a grid of billions (decoded graphs
    // have finite coordinates within +-4e7 m).
    constexpr double kMaxCells = 4.0 * 1024 * 1024;
    while (((max_x - m_min_x) / m_cell + 1) * ((max_y - m_min_y) / m_cell + 1) > kMaxCells) m_cell *= 2;
    m_cols = static_cast<int>((max_x - m_min_x) / m_cell) + 1;
    m_rows = static_cast<int>((max_y - m_min_y) / m_cell) + 1;
    const auto cells = static_cast<std::size_t>(m_cols) * static_cast<std::size_t>(m_rows);
    std::vector<std::uint32_t> count(cells + 1, 0);
    const auto for_cells = [&](const Seg& s, auto&& fn) {
        const int c0 = static_cast<int>((std::min(s.a.x, s.b.x) - m_min_x) / m_cell);
        const int c1 = static_cast<int>((std::max(s.a.x, s.b.x) - m_min_x) / m_cell);
        const int r0 = static_cast<int>((std::min(s.a.y, s.b.y) - m_min_y) / m_cell);
        const int r1 = static_cast<int>((std::max(s.a.y, s.b.y) - m_min_y) / m_cell);
        for (int r = r0; r <= r1; ++r)
            for (int c = c0; c <= c1; ++c) fn(static_cast<std::size_t>(r) * m_cols + static_cast<std::size_t>(c));
    };
    for (const auto& s : m_segments) for_cells(s, [&](std::size_t cell) { ++count[cell + 1]; });
    for (std::size_t i = 1; i <= cells; ++i) count[i] += count[i - 1];
    m_cell_start = count;
    m_cell_segs.resize(count[cells]);
    for (std::uint32_t i = 0; i < m_segments.size(); ++i) {
        for_cells(m_segments[i], [&](std::size_t cell) { m_cell_segs[count[cell]++] = i; });
    }
}

std::optional<RoadMatch> MapMatcher::match(map::PlanarPoint p, std::optional<double> heading_deg,
                                           std::optional<std::uint32_t> previous_edge,
                                           const VehicleStateConfig& cfg) const {
    if (m_segments.empty() || !std::isfinite(p.x) || !std::isfinite(p.y)) {
        return std::nullopt;
    }
    const auto& g = *m_graph;
    const double r = cfg.match_radius_m;
    const int c0 = std::max(0, static_cast<int>(std::floor((p.x - r - m_min_x) / m_cell)));
    const int c1 = std::min(m_cols - 1, static_cast<int>(std::floor((p.x + r - m_min_x) / m_cell)));
    const int r0 = std::max(0, static_cast<int>(std::floor((p.y - r - m_min_y) / m_cell)));
    const int r1 = std::min(m_rows - 1, static_cast<int>(std::floor((p.y + r - m_min_y) / m_cell)));
    std::optional<RoadMatch> best;
    const map::GraphEdge* prev = previous_edge && *previous_edge < g.edges.size() ? &g.edges[*previous_edge] : nullptr;
    for (int row = r0; row <= r1; ++row) {
        for (int col = c0; col <= c1; ++col) {
            const auto cell = static_cast<std::size_t>(row) * m_cols + static_cast<std::size_t>(col);
            for (auto k = m_cell_start[cell]; k < m_cell_start[cell + 1]; ++k) {
                const Seg& s = m_segments[m_cell_segs[k]];
                const double dx = s.b.x - s.a.x, dy = s.b.y - s.a.y;
                const double len2 = dx * dx + dy * dy;
                const double t = std::clamp(((p.x - s.a.x) * dx + (p.y - s.a.y) * dy) / len2, 0.0, 1.0);
                const map::PlanarPoint q{s.a.x + t * dx, s.a.y + t * dy};
                const double d = std::hypot(p.x - q.x, p.y - q.y);
                if (d > r) continue;
                const double seg_heading = headingOf(s.a, s.b);
                const double dh = heading_deg ? angleDiff(*heading_deg, seg_heading) : 0.0;
                const double zd = d / cfg.match_sigma_m;
                const double zh = dh / cfg.match_sigma_heading_deg;
                double score = zd * zd + (heading_deg ? zh * zh : 0.0);
                if (prev != nullptr) {
                    const auto& e = g.edges[s.edge];
                    if (s.edge == *previous_edge) {
                        score -= cfg.hysteresis_bonus;
                    } else if (e.from == prev->to || e.way_id == prev->way_id) {
                        score -= cfg.connected_bonus;
                    }
                }
                if (!best || score < best->score) {
                    best = RoadMatch{s.edge, q, seg_heading, d, matchConfidence(d, dh, heading_deg.has_value(), cfg),
                                     score};
                }
            }
        }
    }
    return best;
}

}  // namespace navmap::daemon
