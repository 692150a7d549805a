// SPDX-License-Identifier: Apache-2.0
#include "guidance_test_graph.h"

#include <algorithm>
#include <cmath>

namespace navmap::map::test {

std::uint32_t TestGraph::node(double x, double y) {
    m_g.nodes.push_back({x, y, static_cast<std::int64_t>(m_g.nodes.size() + 1)});
    return static_cast<std::uint32_t>(m_g.nodes.size() - 1);
}

void TestGraph::way(std::int64_t id, const std::vector<std::uint32_t>& nodes, RoadClass cls, std::uint8_t flags,
                    const std::vector<std::vector<PlanarPoint>>& shape) {
    const bool oneway = (flags & road_flags::kOneway) != 0;
    for (std::size_t k = 0; k + 1 < nodes.size(); ++k) {
        const GraphNode& a = m_g.nodes[nodes[k]];
        const GraphNode& b = m_g.nodes[nodes[k + 1]];
        std::vector<PlanarPoint> pts{{a.x, a.y}};
        if (k < shape.size()) pts.insert(pts.end(), shape[k].begin(), shape[k].end());
        pts.push_back({b.x, b.y});
        const auto begin = static_cast<std::uint32_t>(m_g.shape.size());
        double length = 0.0;
        for (std::size_t i = 0; i < pts.size(); ++i) {
            m_g.shape.push_back({static_cast<float>(pts[i].x), static_cast<float>(pts[i].y)});
            if (i > 0) length += std::hypot(pts[i].x - pts[i - 1].x, pts[i].y - pts[i - 1].y);
        }
        const auto end = static_cast<std::uint32_t>(m_g.shape.size());
        GraphEdge e{nodes[k], nodes[k + 1], static_cast<float>(length), defaultSpeedKmh(cls), cls, flags, begin, end,
                    id};
        m_g.edges.push_back(e);
        if (!oneway) {
            std::swap(e.from, e.to);
            e.flags |= edge_flags::kReversed;
            m_g.edges.push_back(e);
        }
    }
}

RoadGraph TestGraph::build() const {
    RoadGraph g = m_g;
    indexEdges(g);
    return g;
}

std::vector<RoutePoint> routeLine(const RoadGraph& graph, std::uint32_t from, std::uint32_t to) {
    const auto r = fastestRoute(graph, from, to);
    return r ? routePolyline(graph, *r) : std::vector<RoutePoint>{};
}

}  // namespace navmap::map::test
