// SPDX-License-Identifier: Apache-2.0
#include "navmap/map/guidance/lane_guidance.h"
#include "navmap/map/geometry.h"

#include <algorithm>
#include <cmath>

namespace navmap::map::guidance {

namespace {

namespace la = lane_arrow;

constexpr double kCellM = 64.0;  // the node grid's cell size

std::int64_t cellKey(double x, double y) {
    const auto cx = static_cast<std::int64_t>(std::floor(x / kCellM));
    const auto cy = static_cast<std::int64_t>(std::floor(y / kCellM));
    return cx * 0x100000000LL + (cy & 0xFFFFFFFFLL);
}

/// The arrows that lead along a turn of `type`, and those next to them, for when no lane has the
/// first (seed-free: the rule of docs/guidance.md "Lanes").
struct ArrowMatch {
    std::uint16_t primary = 0;
    std::uint16_t secondary = 0;
    bool unmarked_straight = false;  // lanes without arrows count as straight on
};

ArrowMatch arrowsFor(ManeuverType type, double turn_deg) {
    switch (type) {
        case ManeuverType::Straight: return {la::kThrough, 0, true};
        case ManeuverType::TurnLeft: return {la::kLeft, la::kSharpLeft | la::kSlightLeft};
        case ManeuverType::SharpLeft: return {la::kSharpLeft, la::kLeft};
        case ManeuverType::SlightLeft: return {la::kSlightLeft, la::kLeft};
        case ManeuverType::KeepLeft: return {la::kSlightLeft, la::kLeft | la::kThrough};
        case ManeuverType::TurnRight: return {la::kRight, la::kSharpRight | la::kSlightRight};
        case ManeuverType::SharpRight: return {la::kSharpRight, la::kRight};
        case ManeuverType::SlightRight: return {la::kSlightRight, la::kRight};
        case ManeuverType::KeepRight: return {la::kSlightRight, la::kRight | la::kThrough};
        case ManeuverType::UTurn: return {la::kReverse, la::kLeft | la::kSharpLeft};
        case ManeuverType::Roundabout:
        case ManeuverType::Exit:
        case ManeuverType::Merge: {
            const ManeuverType turn = classifyTurn(turn_deg);
            // classifyTurn never gives these three back: no recursion beyond one level.
            return turn == ManeuverType::Straight && type == ManeuverType::Merge
                       ? ArrowMatch{la::kThrough | la::kMergeToLeft | la::kMergeToRight, 0, true}
                       : arrowsFor(turn, turn_deg);
        }
        case ManeuverType::Depart:
        case ManeuverType::Arrive: break;
    }
    return {};
}

}  // namespace

std::uint32_t recommendedLanes(std::span<const std::uint16_t> lanes, ManeuverType type, double turn_deg) {
    const ArrowMatch match = arrowsFor(type, turn_deg);
    const bool merging_on = (match.primary & (la::kMergeToLeft | la::kMergeToRight)) != 0;
    const auto pick = [&](auto&& takes) {
        std::uint32_t bits = 0;
        for (std::size_t i = 0; i < lanes.size() && i < 32; ++i) {
            // A lane that ends (merges away) is not one to stay in for going on, unless the
            // manoeuvre is the merge itself.
            const bool merges = (lanes[i] & (la::kMergeToLeft | la::kMergeToRight)) != 0;
            if (merges && !merging_on) continue;
            if (takes(lanes[i])) bits |= 1U << i;
        }
        return bits;
    };
    if (match.primary == 0) return 0;
    if (const std::uint32_t b = pick([&](std::uint16_t a) { return (a & match.primary) != 0; })) return b;
    if (match.secondary != 0) {
        if (const std::uint32_t b = pick([&](std::uint16_t a) { return (a & match.secondary) != 0; })) return b;
    }
    if (match.unmarked_straight) return pick([](std::uint16_t a) { return a == 0; });
    return 0;
}

LaneFinder::LaneFinder(const RoadGraph& graph) : m_graph(graph) {
    const std::size_t n = graph.nodes.size();
    m_in_first.assign(n + 1, 0);
    for (const GraphEdge& e : graph.edges)
        if (e.to < n) ++m_in_first[e.to + 1];
    for (std::size_t i = 1; i <= n; ++i) m_in_first[i] += m_in_first[i - 1];
    m_in.assign(m_in_first[n], 0);
    std::vector<std::uint32_t> next(m_in_first.begin(), m_in_first.end() - 1);
    for (std::uint32_t k = 0; k < graph.edges.size(); ++k) {
        const std::uint32_t to = graph.edges[k].to;
        if (to < n) m_in[next[to]++] = k;
    }
    for (std::uint32_t i = 0; i < n; ++i) m_cells[cellKey(graph.nodes[i].x, graph.nodes[i].y)].push_back(i);
}

std::optional<std::uint32_t> LaneFinder::nodeNear(PlanarPoint p, double within_m) const {
    std::optional<std::uint32_t> best;
    double best_d = within_m;
    for (int dx = -1; dx <= 1; ++dx) {
        for (int dy = -1; dy <= 1; ++dy) {
            const auto it = m_cells.find(cellKey(p.x + dx * kCellM, p.y + dy * kCellM));
            if (it == m_cells.end()) continue;
            for (const std::uint32_t i : it->second) {
                const double d = std::hypot(m_graph.nodes[i].x - p.x, m_graph.nodes[i].y - p.y);
                if (d <= best_d) {
                    best_d = d;
                    best = i;
                }
            }
        }
    }
    return best;
}

std::optional<LaneGuidance> LaneFinder::lanesBefore(const std::vector<PlanarPoint>& points,
                                                    const std::vector<double>& measures, const Maneuver& m,
                                                    std::size_t previous_end, const LaneSearchOptions& options,
                                                    std::size_t& tests_left) const {
    auto node = nodeNear(points[m.point], options.match_m);
    if (!node) return std::nullopt;
    std::size_t at = m.point;  // the route point at `node`
    double walked = 0.0;       // along the route from the junction back to `node`
    // The edge into `node` that the route came along: every shape point near the route before
    // `at`, its start node at route point `k` (the nearest segment end).
    // A point-to-segment test while the work bound lasts.
    const auto within = [&](PlanarPoint p, std::size_t j) {
        if (tests_left == 0) return false;
        --tests_left;
        return segmentDistance(p, points[j], points[j + 1]) <= options.match_m;
    };
    const auto follows = [&](const GraphEdge& e, std::size_t& k) {
        const double reach = static_cast<double>(e.length_m) + 2.0 * options.match_m;
        const PlanarPoint from{m_graph.nodes[e.from].x, m_graph.nodes[e.from].y};
        bool found = false;
        for (std::size_t j = at; j > 0 && measures[at] - measures[j] <= reach; --j) {
            if (!within(from, j - 1)) continue;
            const bool nearer_end = std::hypot(from.x - points[j - 1].x, from.y - points[j - 1].y) <
                                    std::hypot(from.x - points[j].x, from.y - points[j].y);
            k = nearer_end ? j - 1 : j;
            found = k < at;
            break;
        }
        if (!found) return false;
        for (std::uint32_t s = e.shape_begin; s < e.shape_end; ++s) {
            const PlanarPoint q{m_graph.shape[s].x, m_graph.shape[s].y};
            bool near = false;
            for (std::size_t j = k; j < at && !near; ++j) near = within(q, j);
            if (!near) return false;
        }
        return true;
    };
    while (walked <= options.distance_m) {
        std::optional<std::uint32_t> taken;
        std::size_t taken_at = at;
        for (std::uint32_t x = m_in_first[*node]; x < m_in_first[*node + 1]; ++x) {
            const GraphEdge& e = m_graph.edges[m_in[x]];
            std::size_t k = at;
            // An edge that starts before the previous manoeuvre is done leads to that one.
            if (e.from == e.to || !follows(e, k) || k < previous_end) continue;
            taken = m_in[x];
            taken_at = k;
            break;
        }
        if (!taken) return std::nullopt;  // the route leaves the graph, or starts here
        const GraphEdge& e = m_graph.edges[*taken];
        const auto lanes = m_graph.lanesOf(e);
        if (!lanes.empty()) {
            LaneGuidance g;
            g.lanes.assign(lanes.begin(), lanes.end());
            g.recommended = recommendedLanes(lanes, m.type, m.turn_deg);
            g.before_junction_m = walked;
            g.way_id = e.way_id;
            return g;
        }
        walked += measures[at] - measures[taken_at];
        node = e.from;
        at = taken_at;
    }
    return std::nullopt;
}

std::vector<std::optional<LaneGuidance>> LaneFinder::find(const std::vector<PlanarPoint>& points,
                                                          const std::vector<Maneuver>& maneuvers,
                                                          const LaneSearchOptions& options) const {
    std::vector<std::optional<LaneGuidance>> out(maneuvers.size());
    std::vector<double> measures(points.size(), 0.0);
    for (std::size_t i = 1; i < points.size(); ++i)
        measures[i] = measures[i - 1] + std::hypot(points[i].x - points[i - 1].x, points[i].y - points[i - 1].y);
    std::size_t previous_end = 0;
    std::size_t tests_left = options.max_tests;
    for (std::size_t k = 0; k < maneuvers.size(); ++k) {
        const Maneuver& m = maneuvers[k];
        if (m.type != ManeuverType::Depart && m.type != ManeuverType::Arrive && m.point < points.size())
            out[k] = lanesBefore(points, measures, m, previous_end, options, tests_left);
        previous_end = std::max(previous_end, m.end_point);
    }
    return out;
}

}  // namespace navmap::map::guidance
