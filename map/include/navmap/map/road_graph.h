// SPDX-License-Identifier: Apache-2.0
#pragma once
// Directed road graph for routing and map matching, built by navmap-compile from the same
// highway ways as the road layer. Nodes are OSM junctions (nodes shared by two or more ways,
// or way ends); edges run between consecutive junctions along a way.

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "navmap/map/road_class.h"
#include "navmap/map/tile.h"
#include "navmap/map/turn_lanes.h"
#include "navmap/map/world_tiles.h"

namespace navmap::map {

struct GraphNode {
    double x = 0;  ///< store-frame metres (east of the store origin)
    double y = 0;  ///< store-frame metres (north of the store origin)
    std::int64_t osm_id = 0;
};

namespace edge_flags {
/// The edge runs against the order of its shape points (the reverse twin of a two-way road).
inline constexpr std::uint8_t kReversed = 128;
}  // namespace edge_flags

struct GraphEdge {
    std::uint32_t from = 0;
    std::uint32_t to = 0;
    float length_m = 0;   ///< geodesic length on WGS84 (GeographicLib), metres
    float speed_kmh = 0;  ///< maxspeed, else the class default
    RoadClass cls = RoadClass::Path;
    std::uint8_t flags = 0;         ///< road_flags bits, plus edge_flags::kReversed
    std::uint32_t shape_begin = 0;  ///< range in RoadGraph::shape (from the way's point of view)
    std::uint32_t shape_end = 0;
    std::int64_t way_id = 0;
    /// The legal speed limit in this edge's direction of travel (a reversed twin has the way's
    /// backward limit), km/h; 0 unknown (docs/tile-store.md "Speed limits").
    std::uint16_t speed_limit_kmh = 0;
    /// The turn lanes in this edge's direction of travel, left to right: RoadGraph::lane_arrows
    /// [lanes_begin, lanes_begin + lane_count), lane_arrow bits; 0 lanes: none tagged
    /// (docs/tile-store.md "Turn lanes").
    std::uint8_t lane_count = 0;
    std::uint32_t lanes_begin = 0;
};

/// Compressed sparse row graph: edges sorted by `from`; the out-edges of node n are
/// edges[first_edge[n] .. first_edge[n + 1]). Two-way roads give two edges sharing one shape.
struct RoadGraph {
    std::vector<GraphNode> nodes;
    std::vector<GraphEdge> edges;
    std::vector<std::uint32_t> first_edge;   ///< nodes.size() + 1 entries
    std::vector<LocalPoint> shape;           ///< store-frame metres as float (way geometry)
    std::vector<std::uint16_t> lane_arrows;  ///< the edges' turn lanes (GraphEdge::lanes_begin)

    /// The turn lanes of `e` (an edge of this graph), left to right; empty when none are tagged.
    [[nodiscard]] std::span<const std::uint16_t> lanesOf(const GraphEdge& e) const {
        if (e.lane_count == 0 || std::size_t{e.lanes_begin} + e.lane_count > lane_arrows.size()) return {};
        return std::span<const std::uint16_t>(lane_arrows).subspan(e.lanes_begin, e.lane_count);
    }

    [[nodiscard]] std::span<const GraphEdge> outEdges(std::uint32_t node) const {
        return std::span<const GraphEdge>(edges).subspan(first_edge[node], first_edge[node + 1] - first_edge[node]);
    }
};

/// Sorts the edges by their start node (stably: each node's edges keep their order) and fills
/// first_edge, the CSR offsets outEdges() reads.
void indexEdges(RoadGraph& graph);

/// Re-expresses the graph's positions (nodes and shape) in another frame: p' = t.scale * p + offset.
void transformRoadGraph(RoadGraph& graph, const FrameTransform& t);
/// Appends `other` (another store's graph) re-expressed with `t` into `graph`'s frame. The two are
/// not connected; the edge indices of `graph` stay as they were.
void appendRoadGraph(RoadGraph& graph, const RoadGraph& other, const FrameTransform& t);

std::vector<std::uint8_t> encodeRoadGraph(const RoadGraph& graph);
/// Decodes and validates (node indices, shape ranges, CSR offsets); false + error on bad input.
bool decodeRoadGraph(std::span<const std::uint8_t> bytes, RoadGraph& out, std::string& error);

}  // namespace navmap::map
