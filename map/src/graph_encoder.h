// SPDX-License-Identifier: Apache-2.0
#pragma once
// The road graph's encoding (encodeRoadGraph's bytes, docs/tile-store.md) written in pieces as
// it is produced, so that a graph held on disk by the bounded compile is never encoded whole in
// memory. Private to navmap_map.

#include <cstddef>
#include <cstdint>
#include <functional>
#include <span>

#include "byte_io.h"
#include "navmap/map/road_graph.h"

namespace navmap::map::detail {

/// The first four bytes of an encoded road graph ("GRG3": edges with their speed limit and turn
/// lanes); the store checks them on the first piece it inflates (docs/tile-store.md "Sizes").
inline constexpr std::uint32_t kGraphMagic = 0x33475247;
/// The graphs of earlier compiles, still read: "GRG2" (speed limits, no turn lanes) and "GRG1"
/// (neither: limits 0).
inline constexpr std::uint32_t kGraphMagicV2 = 0x32475247;
inline constexpr std::uint32_t kGraphMagicV1 = 0x31475247;

/// Takes the encoded bytes in pieces, in order.
using ByteSink = std::function<void(std::span<const std::uint8_t>)>;

/// Call in this order: nodes(n) and n node(), edges(m) and m edge(), shape(k) and k point(),
/// lanes(j) and j lane(), then finish(). Hands `sink` a piece whenever about `piece_bytes` are buffered, and the rest
/// in finish().
class RoadGraphEncoder {
public:
    explicit RoadGraphEncoder(ByteSink sink, std::size_t piece_bytes = std::size_t{1} << 20);

    void nodes(std::size_t count);
    void node(const GraphNode& n);
    void edges(std::size_t count);
    void edge(const GraphEdge& e);
    void shape(std::size_t count);
    void point(LocalPoint p);
    void lanes(std::size_t count);
    void lane(std::uint16_t arrows);
    void finish();

private:
    void maybeFlush();
    ByteSink m_sink;
    std::size_t m_piece_bytes;
    ByteWriter m_w;
};

/// The whole of `graph` through an encoder.
void encodeRoadGraph(const RoadGraph& graph, const ByteSink& sink);

}  // namespace navmap::map::detail
