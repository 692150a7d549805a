// SPDX-License-Identifier: Apache-2.0
#include "graph_build.h"

#include <fcntl.h>
#include <sys/mman.h>
#include <unistd.h>

#include <GeographicLib/Geodesic.hpp>
#include <algorithm>
#include <cerrno>
#include <cstring>
#include <queue>
#include <utility>

#include "navmap/map/compile/spill_file.h"

namespace navmap::map::detail {

namespace {

/// The ids whose junctions are wanted: every way node, and each way's ends once more, so that a
/// node is a junction exactly when its id comes twice or more (in two places, or at an end).
template <class F>
void junctionCandidates(const RawGraphWay& w, F&& emit) {
    for (const std::int64_t id : w.nodes) emit(id);
    emit(w.nodes.front());
    emit(w.nodes.back());
}

/// Calls `junction` with each id that comes at least twice in the sorted ids fed to it.
class JunctionScan {
public:
    template <class F>
    void feed(std::int64_t id, F&& junction) {
        if (m_count > 0 && id == m_last) {
            if (++m_count == 2) junction(id);
            return;
        }
        m_last = id;
        m_count = 1;
    }

private:
    std::int64_t m_last = 0;
    std::size_t m_count = 0;
};

/// The lane values written so far (lane_values), and where one direction's lanes begin.
struct LaneRange {
    std::uint32_t begin = 0;
    std::uint8_t count = 0;
};

/// One way's nodes, edges, shape points and turn lanes, as both builders produce them:
/// `node(index, n)` for each junction it passes (its position is set again each time), `edge(e)`
/// for each edge in way order (the reverse twin right after a two-way edge), `point(p)` for each
/// shape point, `lane(arrows)` for each lane of each direction (once per way: its edges share
/// them). `index_of(id)` is a junction's index or -1; `counts` the shape points and lane values
/// so far.
struct WalkCounts {
    std::uint32_t shape_points = 0;
    std::uint32_t lane_values = 0;
};
template <class IndexOf, class Node, class Edge, class Point, class Lane>
void walkWay(const RawGraphWay& w, const Projection& proj, IndexOf&& index_of, WalkCounts& counts, Node&& node,
             Edge&& edge, Point&& point, Lane&& lane) {
    const GeographicLib::Geodesic& geod = GeographicLib::Geodesic::WGS84();
    std::uint32_t& shape_points = counts.shape_points;
    const auto lanes_of = [&](const std::vector<std::uint16_t>& lanes) {
        LaneRange r{counts.lane_values, 0};
        if (lanes.empty() || lanes.size() > kMaxTurnLanes) return r;
        for (const std::uint16_t a : lanes) lane(static_cast<std::uint16_t>(a & lane_arrow::kKnown));
        counts.lane_values += static_cast<std::uint32_t>(lanes.size());
        r.count = static_cast<std::uint8_t>(lanes.size());
        return r;
    };
    const LaneRange forward_lanes = lanes_of(w.lanes_forward);
    const LaneRange backward_lanes = w.oneway ? LaneRange{} : lanes_of(w.lanes_backward);
    std::size_t start = 0;
    std::uint32_t shape_begin = shape_points;
    double length = 0;
    auto push = [&](std::size_t i) {
        const PlanarPoint p = proj.forward(w.points[i].lat_deg, w.points[i].lon_deg);
        point(LocalPoint{static_cast<float>(p.x), static_cast<float>(p.y)});
        ++shape_points;
        return p;
    };
    const PlanarPoint first = push(0);
    node(static_cast<std::uint32_t>(index_of(w.nodes[0])), GraphNode{first.x, first.y, w.nodes[0]});
    for (std::size_t i = 1; i < w.nodes.size(); ++i) {
        double s12 = 0;
        geod.Inverse(w.points[i - 1].lat_deg, w.points[i - 1].lon_deg, w.points[i].lat_deg, w.points[i].lon_deg, s12);
        length += s12;
        const PlanarPoint p = push(i);
        const auto ni = index_of(w.nodes[i]);
        if (ni < 0) continue;
        node(static_cast<std::uint32_t>(ni), GraphNode{p.x, p.y, w.nodes[i]});
        GraphEdge e{static_cast<std::uint32_t>(index_of(w.nodes[start])),
                    static_cast<std::uint32_t>(ni),
                    static_cast<float>(length),
                    w.speed_kmh,
                    w.cls,
                    w.flags,
                    shape_begin,
                    shape_points,
                    w.id,
                    w.limit_forward_kmh};
        e.lane_count = forward_lanes.count;
        e.lanes_begin = forward_lanes.count > 0 ? forward_lanes.begin : 0;
        edge(e);
        if (!w.oneway) {
            std::swap(e.from, e.to);
            e.flags |= edge_flags::kReversed;
            e.speed_limit_kmh = w.limit_backward_kmh;
            e.lane_count = backward_lanes.count;
            e.lanes_begin = backward_lanes.count > 0 ? backward_lanes.begin : 0;
            edge(e);
        }
        // The next edge starts at this junction and shares its shape point.
        start = i;
        length = 0;
        shape_begin = shape_points - 1;
    }
}

/// The index of `id` in the sorted `junctions`, or -1.
std::int64_t indexIn(std::span<const std::int64_t> junctions, std::int64_t id) {
    const auto it = std::lower_bound(junctions.begin(), junctions.end(), id);
    return (it != junctions.end() && *it == id) ? it - junctions.begin() : -1;
}

// ---- the scratch files' records: batches of fixed-size values, little-endian as in memory ----

constexpr std::size_t kBatch = 8192;  // values per spill record

template <class T>
void putField(std::vector<std::uint8_t>& out, const T& v) {
    const std::size_t at = out.size();
    out.resize(at + sizeof(T));
    std::memcpy(out.data() + at, &v, sizeof(T));
}

template <class T>
T getField(const std::uint8_t*& p) {
    T v;
    std::memcpy(&v, p, sizeof(T));
    p += sizeof(T);
    return v;
}

// An edge's fields without the struct's padding (nothing uninitialised reaches the disk).
constexpr std::size_t kEdgeBytes = 4 + 4 + 4 + 4 + 1 + 1 + 4 + 4 + 8 + 2 + 1 + 4;

void putEdge(std::vector<std::uint8_t>& out, const GraphEdge& e) {
    putField(out, e.from);
    putField(out, e.to);
    putField(out, e.length_m);
    putField(out, e.speed_kmh);
    putField(out, static_cast<std::uint8_t>(e.cls));
    putField(out, e.flags);
    putField(out, e.shape_begin);
    putField(out, e.shape_end);
    putField(out, e.way_id);
    putField(out, e.speed_limit_kmh);
    putField(out, e.lane_count);
    putField(out, e.lanes_begin);
}

GraphEdge getEdge(const std::uint8_t*& p) {
    GraphEdge e;
    e.from = getField<std::uint32_t>(p);
    e.to = getField<std::uint32_t>(p);
    e.length_m = getField<float>(p);
    e.speed_kmh = getField<float>(p);
    e.cls = static_cast<RoadClass>(getField<std::uint8_t>(p));
    e.flags = getField<std::uint8_t>(p);
    e.shape_begin = getField<std::uint32_t>(p);
    e.shape_end = getField<std::uint32_t>(p);
    e.way_id = getField<std::int64_t>(p);
    e.speed_limit_kmh = getField<std::uint16_t>(p);
    e.lane_count = getField<std::uint8_t>(p);
    e.lanes_begin = getField<std::uint32_t>(p);
    return e;
}

/// Reads the records of a spill file of fixed-size values one value at a time.
class ValueReader {
public:
    ValueReader(const std::filesystem::path& path, std::size_t value_bytes) : m_in(path), m_value_bytes(value_bytes) {}

    /// The next value's bytes, or null at the end of the file.
    const std::uint8_t* next() {
        if (m_pos == m_record.size()) {
            m_pos = 0;
            if (!m_in.next(m_record)) return nullptr;
            if (m_record.size() % m_value_bytes != 0 || m_record.empty()) {
                throw SpillError(m_in.path().string() + ": damaged: a record of " + std::to_string(m_record.size()) +
                                 " bytes does not hold whole values of " + std::to_string(m_value_bytes));
            }
        }
        const std::uint8_t* p = m_record.data() + m_pos;
        m_pos += m_value_bytes;
        return p;
    }

private:
    SpillReader m_in;
    std::size_t m_value_bytes;
    std::vector<std::uint8_t> m_record;
    std::size_t m_pos = 0;
};

/// Appends fixed-size values to a spill file, kBatch values per record.
class ValueWriter {
public:
    explicit ValueWriter(const std::filesystem::path& path) : m_out(path) {}
    std::vector<std::uint8_t>& buffer() { return m_buffer; }
    /// After each value put into buffer().
    void added() {
        if (++m_values == kBatch) flush();
    }
    void close() {
        flush();
        m_out.close();
    }

private:
    void flush() {
        if (m_values == 0) return;
        m_out.append(m_buffer);
        m_buffer.clear();
        m_values = 0;
    }
    SpillWriter m_out;
    std::vector<std::uint8_t> m_buffer;
    std::size_t m_values = 0;
};

}  // namespace

RoadGraph buildGraph(const GraphWaySource& ways, const Projection& proj) {
    std::vector<std::int64_t> ids;
    ways([&](const RawGraphWay& w) { junctionCandidates(w, [&](std::int64_t id) { ids.push_back(id); }); });
    std::sort(ids.begin(), ids.end());
    std::vector<std::int64_t> junctions;
    JunctionScan scan;
    for (const std::int64_t id : ids) scan.feed(id, [&](std::int64_t j) { junctions.push_back(j); });
    ids.clear();
    ids.shrink_to_fit();

    RoadGraph g;
    g.nodes.resize(junctions.size());
    WalkCounts counts;
    ways([&](const RawGraphWay& w) {
        walkWay(
            w, proj, [&](std::int64_t id) { return indexIn(junctions, id); }, counts,
            [&](std::uint32_t i, const GraphNode& n) { g.nodes[i] = n; },
            [&](const GraphEdge& e) { g.edges.push_back(e); }, [&](LocalPoint p) { g.shape.push_back(p); },
            [&](std::uint16_t a) { g.lane_arrows.push_back(a); });
    });
    indexEdges(g);
    return g;
}

// ---- MappedFile ----

MappedFile::MappedFile(std::filesystem::path path, std::uint64_t bytes) : m_path(std::move(path)), m_bytes(bytes) {
    m_fd = ::open(m_path.c_str(), O_RDWR | O_CREAT | O_EXCL | O_CLOEXEC | O_NOFOLLOW, 0600);
    if (m_fd < 0) throw SpillError("open(" + m_path.string() + "): " + std::strerror(errno));
    auto fail = [&](const std::string& what) {
        const std::string message =
            what + "(" + m_path.string() + ", " + std::to_string(bytes) + " bytes): " + std::strerror(errno);
        ::close(m_fd);
        m_fd = -1;
        ::unlink(m_path.c_str());
        throw SpillError(message);
    };
    if (bytes == 0) return;
    // Blocks first (they read as zeros), then the mapping.
    if (::fallocate(m_fd, 0, 0, static_cast<off_t>(bytes)) != 0) {
        if (errno != EOPNOTSUPP) fail("fallocate");
        if (::ftruncate(m_fd, static_cast<off_t>(bytes)) != 0) fail("ftruncate");
    }
    m_data = ::mmap(nullptr, bytes, PROT_READ | PROT_WRITE, MAP_SHARED, m_fd, 0);
    if (m_data == MAP_FAILED) {
        m_data = nullptr;
        fail("mmap");
    }
}

MappedFile::~MappedFile() {
    if (m_data != nullptr) ::munmap(m_data, m_bytes);
    if (m_fd >= 0) {
        ::close(m_fd);
        ::unlink(m_path.c_str());
    }
}

// ---- DiskGraph ----

DiskGraph::DiskGraph(const GraphWaySource& ways, const Projection& proj, const std::filesystem::path& dir,
                     std::uint64_t memory_bytes)
    : m_dir(dir) {
    // 1. Every candidate id, sorted in runs of a bounded size.
    const std::size_t run_ids =
        std::max<std::size_t>(static_cast<std::size_t>(memory_bytes / sizeof(std::int64_t)), kBatch);
    auto run_path = [&](std::size_t k) { return dir / ("graph-ids-" + std::to_string(k) + ".spill"); };
    std::uint64_t candidates = 0;
    {
        std::vector<std::int64_t> run;
        run.reserve(run_ids);
        auto write_run = [&] {
            std::sort(run.begin(), run.end());
            ValueWriter out(run_path(m_id_runs++));
            for (const std::int64_t id : run) {
                putField(out.buffer(), id);
                out.added();
            }
            out.close();
            run.clear();
        };
        ways([&](const RawGraphWay& w) {
            junctionCandidates(w, [&](std::int64_t id) {
                run.push_back(id);
                ++candidates;
                if (run.size() == run_ids) write_run();
            });
        });
        if (!run.empty()) write_run();
    }

    // 2. The runs merged: the junction ids, sorted, in a file (at most half the candidates).
    const auto junction_file =
        std::make_unique<MappedFile>(dir / "graph-junctions.bin", (candidates / 2 + 1) * sizeof(std::int64_t));
    std::span<std::int64_t> junction_ids = junction_file->as<std::int64_t>();
    {
        std::vector<std::unique_ptr<ValueReader>> runs;
        using Head = std::pair<std::int64_t, std::size_t>;  // id, run
        std::priority_queue<Head, std::vector<Head>, std::greater<>> heads;
        for (std::size_t k = 0; k < m_id_runs; ++k) {
            runs.push_back(std::make_unique<ValueReader>(run_path(k), sizeof(std::int64_t)));
            if (const std::uint8_t* p = runs.back()->next()) heads.emplace(getField<std::int64_t>(p), k);
        }
        JunctionScan scan;
        while (!heads.empty()) {
            const auto [id, k] = heads.top();
            heads.pop();
            scan.feed(id, [&](std::int64_t j) { junction_ids[m_nodes++] = j; });
            if (const std::uint8_t* p = runs[k]->next()) heads.emplace(getField<std::int64_t>(p), k);
        }
        for (std::size_t k = 0; k < m_id_runs; ++k) std::filesystem::remove(run_path(k));
    }
    junction_ids = junction_ids.first(m_nodes);

    // 3. The nodes in place, the edges in way order with each start node's count, the shape.
    m_node_file = std::make_unique<MappedFile>(dir / "graph-nodes.bin", m_nodes * sizeof(GraphNode));
    const std::span<GraphNode> nodes = m_node_file->as<GraphNode>();
    const auto start_file =
        std::make_unique<MappedFile>(dir / "graph-edge-starts.bin", m_nodes * sizeof(std::uint64_t));
    const std::span<std::uint64_t> starts = start_file->as<std::uint64_t>();
    {
        ValueWriter edges_out(dir / "graph-edges-in-way-order.spill");
        ValueWriter shape_out(dir / "graph-shape.spill");
        ValueWriter lanes_out(dir / "graph-lanes.spill");
        WalkCounts counts;
        ways([&](const RawGraphWay& w) {
            walkWay(
                w, proj, [&](std::int64_t id) { return indexIn(junction_ids, id); }, counts,
                [&](std::uint32_t i, const GraphNode& n) { nodes[i] = n; },
                [&](const GraphEdge& e) {
                    putEdge(edges_out.buffer(), e);
                    edges_out.added();
                    ++starts[e.from];
                    ++m_edges;
                },
                [&](LocalPoint p) {
                    putField(shape_out.buffer(), p.x);
                    putField(shape_out.buffer(), p.y);
                    shape_out.added();
                },
                [&](std::uint16_t a) {
                    putField(lanes_out.buffer(), a);
                    lanes_out.added();
                });
        });
        edges_out.close();
        shape_out.close();
        lanes_out.close();
        m_shape_points = counts.shape_points;
        m_lane_values = counts.lane_values;
    }

    // 4. The edges sorted by start node, stably (indexEdges()'s order), by counting: each start
    //    node's first slot, then each edge into the next slot of its start node.
    std::uint64_t slot = 0;
    for (std::uint64_t& s : starts) s = std::exchange(slot, slot + s);
    m_edge_file = std::make_unique<MappedFile>(dir / "graph-edges.bin", m_edges * sizeof(GraphEdge));
    const std::span<GraphEdge> edges = m_edge_file->as<GraphEdge>();
    {
        ValueReader in(dir / "graph-edges-in-way-order.spill", kEdgeBytes);
        while (const std::uint8_t* p = in.next()) {
            const GraphEdge e = getEdge(p);
            edges[starts[e.from]++] = e;
        }
    }
    std::filesystem::remove(dir / "graph-edges-in-way-order.spill");
}

DiskGraph::~DiskGraph() {
    std::error_code ec;
    std::filesystem::remove(m_dir / "graph-shape.spill", ec);
    std::filesystem::remove(m_dir / "graph-lanes.spill", ec);
}

void DiskGraph::encode(const ByteSink& sink) const {
    RoadGraphEncoder enc(sink);
    enc.nodes(m_nodes);
    for (const GraphNode& n : m_node_file->as<GraphNode>()) enc.node(n);
    enc.edges(m_edges);
    for (const GraphEdge& e : m_edge_file->as<GraphEdge>()) enc.edge(e);
    enc.shape(m_shape_points);
    ValueReader in(m_dir / "graph-shape.spill", 2 * sizeof(float));
    while (const std::uint8_t* p = in.next()) {
        const auto x = getField<float>(p);
        const auto y = getField<float>(p);
        enc.point(LocalPoint{x, y});
    }
    enc.lanes(m_lane_values);
    ValueReader lanes_in(m_dir / "graph-lanes.spill", sizeof(std::uint16_t));
    while (const std::uint8_t* p = lanes_in.next()) enc.lane(getField<std::uint16_t>(p));
    enc.finish();
}

}  // namespace navmap::map::detail
