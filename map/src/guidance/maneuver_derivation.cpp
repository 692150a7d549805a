// SPDX-License-Identifier: Apache-2.0
#include "navmap/map/guidance/maneuver_derivation.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace navmap::map::guidance {

namespace {

// Cars may use motorway .. service (map::fastestRoute's rule); pedestrian ways, tracks and
// paths are no choice for a driver.
bool drivable(const GraphEdge& e) { return e.cls < RoadClass::Pedestrian; }
bool roundabout(const GraphEdge& e) { return (e.flags & road_flags::kRoundabout) != 0; }

double headingOf(PlanarPoint a, PlanarPoint b) {
    return std::atan2(b.x - a.x, b.y - a.y) * 180.0 / std::numbers::pi;  // clockwise from north
}

// The point `probe_m` along an edge from its start (its end when the edge is shorter), in the
// edge's driving direction.
PlanarPoint edgeProbe(const RoadGraph& g, const GraphEdge& e, double probe_m) {
    const PlanarPoint end{g.nodes[e.to].x, g.nodes[e.to].y};
    if (e.shape_end <= e.shape_begin + 1 || e.shape_end > g.shape.size()) return end;
    const bool reversed = (e.flags & edge_flags::kReversed) != 0;
    const std::uint32_t count = e.shape_end - e.shape_begin;
    auto at = [&](std::uint32_t k) {
        const LocalPoint& p = g.shape[reversed ? e.shape_end - 1 - k : e.shape_begin + k];
        return PlanarPoint{p.x, p.y};
    };
    PlanarPoint prev = at(0);
    double walked = 0.0;
    for (std::uint32_t k = 1; k < count; ++k) {
        const PlanarPoint p = at(k);
        const double d = std::hypot(p.x - prev.x, p.y - prev.y);
        if (walked + d >= probe_m && d > 0.0) {
            const double t = (probe_m - walked) / d;
            return {prev.x + (p.x - prev.x) * t, prev.y + (p.y - prev.y) * t};
        }
        walked += d;
        prev = p;
    }
    return prev;
}

struct Candidate {
    std::uint32_t edge = 0;
    double angle = 0.0;  // heading change from the arrival heading, positive = right
};

class Deriver {
public:
    Deriver(const RoadGraph& g, const std::vector<RoutePoint>& line, const WayNames* names, const DeriveOptions& o)
        : m_g(g), m_line(line), m_names(names), m_o(o) {}

    std::vector<Maneuver> run() {
        std::vector<Maneuver> out;
        const std::size_t n = m_line.size();
        if (n < 2) return out;
        const double length = m_line.back().measure_m;
        out.push_back({ManeuverType::Depart, 0, 0, 0.0, 0.0, 0.0, 0, street(m_line[1].edge)});
        for (std::size_t i = 1; i + 1 < n; ++i) {
            const std::uint32_t in_i = m_line[i].edge;
            const std::uint32_t out_i = m_line[i + 1].edge;
            if (in_i == out_i || in_i >= m_g.edges.size() || out_i >= m_g.edges.size()) continue;
            const GraphEdge& in = m_g.edges[in_i];
            const GraphEdge& out_e = m_g.edges[out_i];
            if (roundabout(in)) continue;  // circulating or leaving: part of the roundabout manoeuvre
            if (roundabout(out_e)) {
                if (auto m = roundaboutAt(i)) out.push_back(std::move(*m));
                continue;
            }
            if (auto m = junctionAt(i, in, out_i)) out.push_back(std::move(*m));
        }
        out.push_back({ManeuverType::Arrive, n - 1, n - 1, length, length, 0.0, 0, std::string()});
        return out;
    }

private:
    std::string street(std::uint32_t edge) const {
        if (m_names == nullptr || edge >= m_g.edges.size()) return {};
        return std::string(m_names->lookup(m_g.edges[edge].way_id));
    }

    bool sameRoad(const GraphEdge& a, const GraphEdge& b) const {
        if (a.way_id == b.way_id) return true;
        if (m_names == nullptr) return false;
        const std::string_view na = m_names->lookup(a.way_id);
        return !na.empty() && na == m_names->lookup(b.way_id);
    }

    // Heading of arrival at route point i: over the last probe_m before it.
    double arrivalHeading(std::size_t i) const {
        const double m = m_line[i].measure_m;
        const PlanarPoint before = sampleRoute(m_line, std::max(0.0, m - m_o.probe_m)).position;
        return headingOf(before, m_line[i].position);
    }

    double leaveAngle(double arrival, const GraphEdge& e) const {
        const PlanarPoint node{m_g.nodes[e.from].x, m_g.nodes[e.from].y};
        return headingChange(arrival, headingOf(node, edgeProbe(m_g, e, m_o.probe_m)));
    }

    // Drivable ways leaving `node`, except straight back along the way the route came on.
    std::vector<Candidate> candidates(std::uint32_t node, const GraphEdge* in, double arrival) const {
        std::vector<Candidate> c;
        if (node >= m_g.nodes.size()) return c;
        for (std::uint32_t k = m_g.first_edge[node]; k < m_g.first_edge[node + 1]; ++k) {
            const GraphEdge& e = m_g.edges[k];
            if (!drivable(e) || e.to == node) continue;
            if (in != nullptr && e.to == in->from && e.way_id == in->way_id) continue;  // U-turn on the same way
            c.push_back({k, leaveAngle(arrival, e)});
        }
        return c;
    }

    std::optional<Maneuver> junctionAt(std::size_t i, const GraphEdge& in, std::uint32_t out_i) const {
        const GraphEdge& out_e = m_g.edges[out_i];
        const double arrival = arrivalHeading(i);
        const double a = leaveAngle(arrival, out_e);
        std::vector<Candidate> others;
        for (const Candidate& c : candidates(out_e.from, &in, arrival)) {
            if (c.edge != out_i) others.push_back(c);
        }
        // No choice: the driver follows the road however it bends.
        if (others.empty()) return std::nullopt;
        const bool same_road = sameRoad(in, out_e);
        const bool most_straight = std::all_of(others.begin(), others.end(),
                                               [&](const Candidate& c) { return std::abs(c.angle) > std::abs(a); });
        // Following the road that goes on most straight: nothing to say.
        if (same_road && most_straight) return std::nullopt;
        Maneuver m{ManeuverType::Straight, i, i, m_line[i].measure_m, m_line[i].measure_m, a, 0, street(out_i)};
        if (std::abs(a) < m_o.fork_deg) {
            bool left_of_route = false;  // another near-straight way lies left of the route's
            bool right_of_route = false;
            for (const Candidate& c : others) {
                if (std::abs(c.angle) >= m_o.fork_deg) continue;
                (c.angle < a ? left_of_route : right_of_route) = true;
            }
            if (left_of_route != right_of_route) {
                m.type = left_of_route ? ManeuverType::KeepRight : ManeuverType::KeepLeft;
                return m;
            }
            if (left_of_route && right_of_route) return m;  // the middle branch of three: straight
        }
        if (std::abs(a) < m_o.turns.straight_deg) {
            // Straight on while the road the route was on turns away: say so; straight over a
            // crossing of other roads needs no word.
            const bool road_turns_away = std::any_of(
                others.begin(), others.end(), [&](const Candidate& c) { return sameRoad(in, m_g.edges[c.edge]); });
            return road_turns_away ? std::optional<Maneuver>(m) : std::nullopt;
        }
        m.type = classifyTurn(a, m_o.turns);
        return m;
    }

    // Entry into a roundabout at route point i: one manoeuvre up to the exit, the exit counted
    // among the drivable ways leaving the ring from the entry on.
    std::optional<Maneuver> roundaboutAt(std::size_t i) const {
        const std::size_t n = m_line.size();
        std::size_t k = i + 1;
        while (k + 1 < n && m_line[k + 1].edge < m_g.edges.size() && roundabout(m_g.edges[m_line[k + 1].edge])) ++k;
        if (k + 1 >= n || m_line[k + 1].edge >= m_g.edges.size()) return std::nullopt;  // ends on the ring
        // Circulation: the heading change summed along the ring (negative = counter-clockwise).
        double circulation = 0.0;
        for (std::size_t j = i + 1; j + 1 <= k; ++j) {
            const double h0 = headingOf(m_line[j - 1].position, m_line[j].position);
            const double h1 = headingOf(m_line[j].position, m_line[j + 1].position);
            circulation += headingChange(h0, h1);
        }
        int exits = 0;
        for (std::size_t j = i + 1; j < k; ++j) {
            if (m_line[j].edge == m_line[j + 1].edge) continue;
            const std::uint32_t node = m_g.edges[m_line[j + 1].edge].from;
            for (const Candidate& c : candidates(node, nullptr, 0.0)) exits += roundabout(m_g.edges[c.edge]) ? 0 : 1;
        }
        const std::uint32_t out_i = m_line[k + 1].edge;
        const std::uint32_t exit_node = m_g.edges[out_i].from;
        const double ring_heading = headingOf(m_line[k - 1].position, m_line[k].position);
        const double a = leaveAngle(ring_heading, m_g.edges[out_i]);
        // Several exits at one ring node: on a counter-clockwise ring the one turning off more
        // to the right comes first, on a clockwise ring the one more to the left.
        for (const Candidate& c : candidates(exit_node, nullptr, ring_heading)) {
            if (c.edge == out_i || roundabout(m_g.edges[c.edge])) continue;
            exits += (circulation <= 0.0 ? c.angle > a : c.angle < a) ? 1 : 0;
        }
        const double entry = arrivalHeading(i);
        const PlanarPoint node{m_g.nodes[exit_node].x, m_g.nodes[exit_node].y};
        const double turn = headingChange(entry, headingOf(node, edgeProbe(m_g, m_g.edges[out_i], m_o.probe_m)));
        return Maneuver{ManeuverType::Roundabout, i,    k,         m_line[i].measure_m,
                        m_line[k].measure_m,      turn, exits + 1, street(out_i)};
    }

    const RoadGraph& m_g;
    const std::vector<RoutePoint>& m_line;
    const WayNames* m_names;
    const DeriveOptions& m_o;
};

}  // namespace

std::vector<Maneuver> deriveManeuvers(const RoadGraph& graph, const std::vector<RoutePoint>& line,
                                      const WayNames* names, const DeriveOptions& options) {
    return Deriver(graph, line, names, options).run();
}

}  // namespace navmap::map::guidance
