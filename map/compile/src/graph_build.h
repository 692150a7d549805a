// SPDX-License-Identifier: Apache-2.0
#pragma once
// Building the road graph (road_graph.h) from the graph ways navmap-compile read: in memory for
// the default compile, or on disk for the bounded one (docs/tile-store.md "Bounded memory"),
// where the node ids are sorted in runs of a fixed size and merged, and the nodes, edges and
// shape points live in scratch files until they are encoded into the store. Both give the same
// graph, encoded to the same bytes. Private to navmap_map.

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <span>
#include <type_traits>
#include <vector>

#include "graph_encoder.h"
#include "navmap/map/projection.h"
#include "navmap/map/road_graph.h"
#include "osm_handlers.h"

namespace navmap::map::detail {

/// Calls its argument with every graph way, in input order (from memory or from a spill file).
/// The builders call it more than once and rely on the same ways in the same order each time.
using GraphWaySource = std::function<void(const std::function<void(const RawGraphWay&)>&)>;

/// Nodes are the ways' junctions (node ids in two or more places, and way ends); edges run
/// between consecutive junctions along a way, both ways for a two-way road; shape points are
/// the store-frame positions of every way node, in input order.
RoadGraph buildGraph(const GraphWaySource& ways, const Projection& proj);

/// A new scratch file of `bytes` zero bytes mapped into memory (MAP_SHARED): its pages are the
/// kernel's to write back and drop, as the node index's. The blocks are allocated up front, so a
/// full disk is a SpillError naming the file, not a SIGBUS on a later write. The file is removed
/// with the object. as<T>() views it as an array of a trivially copyable T.
class MappedFile {
public:
    MappedFile(std::filesystem::path path, std::uint64_t bytes);
    ~MappedFile();
    MappedFile(const MappedFile&) = delete;
    MappedFile& operator=(const MappedFile&) = delete;

    template <class T>
    [[nodiscard]] std::span<T> as() const {
        static_assert(std::is_trivially_copyable_v<T>);
        return {static_cast<T*>(m_data), static_cast<std::size_t>(m_bytes / sizeof(T))};
    }

private:
    std::filesystem::path m_path;
    int m_fd = -1;
    void* m_data = nullptr;
    std::uint64_t m_bytes = 0;
};

/// The bounded compile's road graph, the same as buildGraph()'s, held in scratch files in `dir`
/// (node ids in sorted runs of `memory_bytes` / 8 ids each, then the junction ids, nodes, edges
/// and shape points) and encoded from there. Reads the ways twice. Throws SpillError naming the
/// file when a scratch file cannot be written or read back.
class DiskGraph {
public:
    DiskGraph(const GraphWaySource& ways, const Projection& proj, const std::filesystem::path& dir,
              std::uint64_t memory_bytes);
    ~DiskGraph();
    DiskGraph(const DiskGraph&) = delete;
    DiskGraph& operator=(const DiskGraph&) = delete;

    [[nodiscard]] std::size_t nodes() const { return m_nodes; }
    [[nodiscard]] std::size_t edges() const { return m_edges; }
    [[nodiscard]] std::size_t shapePoints() const { return m_shape_points; }
    /// Sorted runs the node ids were split into.
    [[nodiscard]] std::size_t idRuns() const { return m_id_runs; }
    /// The graph's encoding (encodeRoadGraph's bytes), in pieces.
    void encode(const ByteSink& sink) const;

private:
    std::filesystem::path m_dir;
    std::size_t m_nodes = 0, m_edges = 0, m_shape_points = 0, m_lane_values = 0, m_id_runs = 0;
    std::unique_ptr<MappedFile> m_node_file, m_edge_file;
};

}  // namespace navmap::map::detail
