// SPDX-License-Identifier: Apache-2.0
#pragma once
// A road graph built by hand for the guidance tests, the way navmap-compile builds one: ways
// of junction nodes with shape points, two edges per two-way segment sharing one shape (the
// reverse one flagged edge_flags::kReversed), CSR order.

#include <cstdint>
#include <vector>

#include "navmap/map/road_graph.h"
#include "navmap/map/routing.h"

namespace navmap::map::test {

class TestGraph {
public:
    /// A junction node at store-frame metres (x east, y north); returns its index.
    std::uint32_t node(double x, double y);
    /// A way through `nodes` (straight segments between them) with an optional `shape` of
    /// intermediate points per segment (shape[k] lies between nodes[k] and nodes[k + 1]).
    void way(std::int64_t id, const std::vector<std::uint32_t>& nodes, RoadClass cls = RoadClass::Residential,
             std::uint8_t flags = 0, const std::vector<std::vector<PlanarPoint>>& shape = {});
    /// The graph in CSR form.
    [[nodiscard]] RoadGraph build() const;

private:
    RoadGraph m_g;
};

/// The polyline of the fastest car route between two nodes of `graph` (empty when none).
std::vector<RoutePoint> routeLine(const RoadGraph& graph, std::uint32_t from, std::uint32_t to);

}  // namespace navmap::map::test
