// SPDX-License-Identifier: Apache-2.0
#include "navmap/map/road_graph.h"

#include <algorithm>
#include <cmath>
#include <utility>

#include "byte_io.h"
#include "graph_encoder.h"

namespace navmap::map {

using detail::ByteReader;
using detail::ByteWriter;
using detail::kGraphMagic;

void indexEdges(RoadGraph& g) {
    std::stable_sort(g.edges.begin(), g.edges.end(),
                     [](const GraphEdge& a, const GraphEdge& b) { return a.from < b.from; });
    g.first_edge.assign(g.nodes.size() + 1, 0);
    for (const auto& e : g.edges) ++g.first_edge[e.from + 1];
    for (std::size_t i = 1; i < g.first_edge.size(); ++i) g.first_edge[i] += g.first_edge[i - 1];
}

void transformRoadGraph(RoadGraph& g, const FrameTransform& t) {
    if (t.identity()) return;
    for (GraphNode& n : g.nodes) {
        n.x = t.scale * n.x + t.offset_x;
        n.y = t.scale * n.y + t.offset_y;
    }
    for (LocalPoint& p : g.shape) {
        p = {static_cast<float>(t.scale * p.x + t.offset_x), static_cast<float>(t.scale * p.y + t.offset_y)};
    }
}

void appendRoadGraph(RoadGraph& g, const RoadGraph& other, const FrameTransform& t) {
    const auto node_base = static_cast<std::uint32_t>(g.nodes.size());
    const auto shape_base = static_cast<std::uint32_t>(g.shape.size());
    const auto lane_base = static_cast<std::uint32_t>(g.lane_arrows.size());
    RoadGraph moved = other;
    transformRoadGraph(moved, t);
    g.nodes.insert(g.nodes.end(), moved.nodes.begin(), moved.nodes.end());
    g.shape.insert(g.shape.end(), moved.shape.begin(), moved.shape.end());
    g.lane_arrows.insert(g.lane_arrows.end(), moved.lane_arrows.begin(), moved.lane_arrows.end());
    for (GraphEdge e : moved.edges) {
        e.from += node_base;
        e.to += node_base;
        e.shape_begin += shape_base;
        e.shape_end += shape_base;
        e.lanes_begin += lane_base;
        g.edges.push_back(e);
    }
    indexEdges(g);  // stable: the appended nodes come last, so the first graph's edges keep their indices
}

namespace detail {

RoadGraphEncoder::RoadGraphEncoder(ByteSink sink, std::size_t piece_bytes)
    : m_sink(std::move(sink)), m_piece_bytes(piece_bytes) {
    m_w.u32(kGraphMagic);
}

void RoadGraphEncoder::maybeFlush() {
    if (m_w.size() < m_piece_bytes) return;
    m_sink(m_w.bytes());
    m_w.bytes().clear();
}

void RoadGraphEncoder::nodes(std::size_t count) { m_w.varint(count); }

void RoadGraphEncoder::node(const GraphNode& n) {
    m_w.f64(n.x);
    m_w.f64(n.y);
    m_w.svarint(n.osm_id);
    maybeFlush();
}

void RoadGraphEncoder::edges(std::size_t count) { m_w.varint(count); }

void RoadGraphEncoder::edge(const GraphEdge& e) {
    m_w.varint(e.from);
    m_w.varint(e.to);
    m_w.f32(e.length_m);
    m_w.f32(e.speed_kmh);
    m_w.u8(static_cast<std::uint8_t>(e.cls));
    m_w.u8(e.flags);
    m_w.varint(e.shape_begin);
    m_w.varint(e.shape_end - e.shape_begin);
    m_w.svarint(e.way_id);
    m_w.varint(e.speed_limit_kmh);
    m_w.varint(e.lane_count);
    if (e.lane_count > 0) m_w.varint(e.lanes_begin);
    maybeFlush();
}

void RoadGraphEncoder::shape(std::size_t count) { m_w.varint(count); }

void RoadGraphEncoder::point(LocalPoint p) {
    m_w.f32(p.x);
    m_w.f32(p.y);
    maybeFlush();
}

void RoadGraphEncoder::lanes(std::size_t count) { m_w.varint(count); }

void RoadGraphEncoder::lane(std::uint16_t arrows) {
    m_w.varint(arrows);
    maybeFlush();
}

void RoadGraphEncoder::finish() {
    if (m_w.size() > 0) m_sink(m_w.bytes());
    m_w.bytes().clear();
}

void encodeRoadGraph(const RoadGraph& g, const ByteSink& sink) {
    RoadGraphEncoder enc(sink);
    enc.nodes(g.nodes.size());
    for (const auto& n : g.nodes) enc.node(n);
    enc.edges(g.edges.size());
    for (const auto& e : g.edges) enc.edge(e);
    enc.shape(g.shape.size());
    for (const auto& p : g.shape) enc.point(p);
    enc.lanes(g.lane_arrows.size());
    for (const std::uint16_t a : g.lane_arrows) enc.lane(a);
    enc.finish();
}

}  // namespace detail

std::vector<std::uint8_t> encodeRoadGraph(const RoadGraph& g) {
    std::vector<std::uint8_t> out;
    detail::encodeRoadGraph(
        g, [&](std::span<const std::uint8_t> piece) { out.insert(out.end(), piece.begin(), piece.end()); });
    return out;
}

bool decodeRoadGraph(std::span<const std::uint8_t> bytes, RoadGraph& g, std::string& error) {
    ByteReader r(bytes);
    g = RoadGraph{};
    const std::uint32_t magic = r.u32();
    if (magic != kGraphMagic && magic != detail::kGraphMagicV2 && magic != detail::kGraphMagicV1) {
        error = "not a road graph (bad magic)";
        return false;
    }
    const bool has_limits = magic != detail::kGraphMagicV1;  // "GRG1" graphs have no speed limits
    const bool has_lanes = magic == kGraphMagic;             // nor have "GRG2" graphs turn lanes
    g.nodes.resize(r.count(17, "node"));
    for (auto& n : g.nodes) {
        n.x = r.f64();
        n.y = r.f64();
        n.osm_id = r.svarint();
    }
    g.edges.resize(r.count(14, "edge"));
    for (auto& e : g.edges) {
        e.from = static_cast<std::uint32_t>(r.varint());
        e.to = static_cast<std::uint32_t>(r.varint());
        e.length_m = r.f32();
        e.speed_kmh = r.f32();
        const std::uint8_t cls = r.u8();
        if (cls >= kRoadClassCount) r.fail("bad road class");
        e.cls = static_cast<RoadClass>(cls);
        e.flags = r.u8();
        e.shape_begin = static_cast<std::uint32_t>(r.varint());
        e.shape_end = e.shape_begin + static_cast<std::uint32_t>(r.varint());
        e.way_id = r.svarint();
        if (has_limits) {
            const std::uint64_t limit = r.varint();
            if (limit > 0xFFFF) r.fail("bad speed limit");
            e.speed_limit_kmh = static_cast<std::uint16_t>(limit);
        }
        if (has_lanes) {
            const std::uint64_t lanes = r.varint();
            if (lanes > kMaxTurnLanes) r.fail("bad lane count");
            e.lane_count = static_cast<std::uint8_t>(lanes);
            if (lanes > 0) {
                const std::uint64_t begin = r.varint();
                if (begin > 0xFFFFFFFFU) r.fail("bad lane index");
                e.lanes_begin = static_cast<std::uint32_t>(begin);
            }
        }
        if (r.failed()) break;
    }
    g.shape.resize(r.count(8, "shape point"));
    for (auto& p : g.shape) {
        p.x = r.f32();
        p.y = r.f32();
    }
    if (has_lanes) {
        g.lane_arrows.resize(r.count(1, "lane"));
        for (auto& a : g.lane_arrows) {
            const std::uint64_t v = r.varint();
            if ((v & ~std::uint64_t{lane_arrow::kKnown}) != 0) r.fail("unknown lane arrows");
            a = static_cast<std::uint16_t>(v & lane_arrow::kKnown);
            if (r.failed()) break;
        }
    }
    if (!r.failed() && r.remaining() != 0) r.fail("trailing bytes");
    if (r.failed()) {
        error = r.error();
        g = RoadGraph{};
        return false;
    }
    // Coordinates within the planet's store frame and sane costs: routing and the map matcher's
    // grid trust them (a NaN length would poison every route through the edge).
    constexpr double kMaxCoordM = 4e7;
    const auto plausible = [](double v) { return std::isfinite(v) && std::abs(v) <= kMaxCoordM; };
    for (std::size_t i = 0; i < g.nodes.size(); ++i) {
        if (!plausible(g.nodes[i].x) || !plausible(g.nodes[i].y)) {
            error = "node " + std::to_string(i) + " has an implausible position";
            g = RoadGraph{};
            return false;
        }
    }
    for (std::size_t i = 0; i < g.shape.size(); ++i) {
        if (!plausible(g.shape[i].x) || !plausible(g.shape[i].y)) {
            error = "shape point " + std::to_string(i) + " has an implausible position";
            g = RoadGraph{};
            return false;
        }
    }
    // Validate references and build the CSR offsets (edges must be sorted by `from`).
    g.first_edge.assign(g.nodes.size() + 1, 0);
    std::uint32_t prev_from = 0;
    for (const auto& e : g.edges) {
        if (e.from >= g.nodes.size() || e.to >= g.nodes.size() || e.from < prev_from || e.shape_end < e.shape_begin ||
            e.shape_end > g.shape.size() || std::size_t{e.lanes_begin} + e.lane_count > g.lane_arrows.size()) {
            error = "edge references out of range or unsorted";
            g = RoadGraph{};
            return false;
        }
        if (!std::isfinite(e.length_m) || e.length_m < 0 || !std::isfinite(e.speed_kmh) || e.speed_kmh < 0) {
            error = "edge with a negative or non-finite length or speed";
            g = RoadGraph{};
            return false;
        }
        prev_from = e.from;
        ++g.first_edge[e.from + 1];
    }
    for (std::size_t i = 1; i < g.first_edge.size(); ++i) g.first_edge[i] += g.first_edge[i - 1];
    return true;
}

}  // namespace navmap::map
