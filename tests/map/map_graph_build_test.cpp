// SPDX-License-Identifier: Apache-2.0
// The road graph of the bounded compile, built on disk: the same graph, encoded to the same bytes,
// as the in-memory build, also when its node ids are sorted in several runs; the store's graph
// block is the same whether the encoding comes whole or in pieces; scratch files are removed and
// a full disk names the file.
#include <gtest/gtest.h>
#include <zlib.h>

#include <algorithm>
#include <fstream>
#include <iterator>
#include <random>

#include "graph_build.h"
#include "map_test_util.h"
#include "navmap/map/compile/spill_file.h"
#include "navmap/map/compile/store_writer.h"
#include "navmap/map/tile_store.h"

using namespace navmap::map;
using namespace navmap::map::detail;
using navmap::map::test::ScratchDir;
using navmap::map::test::withFileSizeLimit;

namespace {

/// A street grid of `n` x `n` crossings 100 m apart, each row and column cut into ways of 3 to
/// 6 blocks with a node every 25 m, every third way one-way, plus dead ends; ids shuffled so
/// that the input order is not the id order.
std::vector<RawGraphWay> streetGrid(int n) {
    std::mt19937 rng(7);
    const double lat0 = 42.5, lon0 = 1.5;
    const double dlat = 100.0 / 111320.0, dlon = 100.0 / (111320.0 * std::cos(lat0 * M_PI / 180.0));
    auto crossing = [&](int i, int j) { return std::int64_t{1000000} + std::int64_t{i} * n + j; };
    std::int64_t next_inner = 5000000, next_way = 1;
    std::vector<RawGraphWay> ways;
    auto street = [&](bool row, int line) {
        int k = 0;
        while (k < n - 1) {
            const int blocks = std::min(n - 1 - k, 3 + static_cast<int>(rng() % 4));
            RawGraphWay w;
            w.id = next_way++;
            w.cls = row ? RoadClass::Secondary : RoadClass::Residential;
            w.speed_kmh = row ? 70.0f : 30.0f;
            w.limit_forward_kmh = row ? 70 : 0;  // the limits travel through both builders too
            w.limit_backward_kmh = static_cast<std::uint16_t>(w.id % 2 == 0 ? 50 : 0);
            // And the turn lanes: some ways with lanes one way, some both.
            if (w.id % 4 == 1) w.lanes_forward = {lane_arrow::kLeft, lane_arrow::kThrough};
            if (w.id % 5 == 2) w.lanes_backward = {0, lane_arrow::kMergeToLeft, lane_arrow::kRight};
            w.oneway = w.id % 3 == 0;
            for (int b = k; b <= k + blocks; ++b) {
                const int i = row ? line : b, j = row ? b : line;
                w.nodes.push_back(crossing(i, j));
                w.points.push_back({lat0 + i * dlat, lon0 + j * dlon});
                if (b == k + blocks) break;
                for (int q = 1; q < 4; ++q) {  // nodes between crossings
                    const double f = q / 4.0;
                    w.nodes.push_back(next_inner++);
                    w.points.push_back({lat0 + (row ? i : i + f) * dlat, lon0 + (row ? j + f : j) * dlon});
                }
            }
            ways.push_back(std::move(w));
            k += blocks;
        }
    };
    for (int line = 0; line < n; ++line) {
        street(true, line);
        street(false, line);
    }
    std::shuffle(ways.begin(), ways.end(), rng);
    return ways;
}

GraphWaySource sourceOf(const std::vector<RawGraphWay>& ways) {
    return [&ways](const std::function<void(const RawGraphWay&)>& f) {
        for (const auto& w : ways) f(w);
    };
}

std::vector<std::uint8_t> encoded(const DiskGraph& graph) {
    std::vector<std::uint8_t> out;
    graph.encode([&](std::span<const std::uint8_t> piece) { out.insert(out.end(), piece.begin(), piece.end()); });
    return out;
}

std::vector<std::uint8_t> fileBytes(const std::filesystem::path& path) {
    std::ifstream in(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

}  // namespace

TEST(GraphBuild, OnDiskInSeveralRunsItIsTheInMemoryGraphByteForByte) {
    const auto ways = streetGrid(60);
    const Projection proj(42.52, 1.53);
    const RoadGraph in_memory = buildGraph(sourceOf(ways), proj);
    // Crossings are junctions and nothing else is (inner nodes appear once and are no way end).
    ASSERT_EQ(in_memory.nodes.size(), std::size_t{60 * 60});
    EXPECT_GT(in_memory.lane_arrows.size(), 0u);
    for (const auto& node : in_memory.nodes) EXPECT_LT(node.osm_id, 5000000);
    ScratchDir dir("graph-build");
    std::vector<std::uint8_t> on_disk;
    {
        // The least memory a run may take: 8192 ids per run (every way node, and each way's
        // ends once more).
        std::size_t ids = 0;
        for (const auto& w : ways) ids += w.nodes.size() + 2;
        const DiskGraph graph(sourceOf(ways), proj, dir.path(), 1);
        EXPECT_EQ(graph.idRuns(), (ids + 8191) / 8192);
        EXPECT_GE(graph.idRuns(), 4u);
        EXPECT_EQ(graph.nodes(), in_memory.nodes.size());
        EXPECT_EQ(graph.edges(), in_memory.edges.size());
        EXPECT_EQ(graph.shapePoints(), in_memory.shape.size());
        on_disk = encoded(graph);
    }
    EXPECT_EQ(on_disk, encodeRoadGraph(in_memory));
    // One run: the same again.
    {
        const DiskGraph graph(sourceOf(ways), proj, dir.path(), std::uint64_t{64} << 20);
        EXPECT_EQ(graph.idRuns(), 1u);
        EXPECT_EQ(encoded(graph), on_disk);
    }
    // Every scratch file is gone with the graph.
    EXPECT_TRUE(std::filesystem::is_empty(dir.path())) << std::filesystem::directory_iterator(dir.path())->path();
    // And it decodes into a graph routing can use: edges sorted by start node, stably.
    RoadGraph decoded;
    std::string error;
    ASSERT_TRUE(decodeRoadGraph(on_disk, decoded, error)) << error;
    EXPECT_TRUE(std::is_sorted(decoded.edges.begin(), decoded.edges.end(),
                               [](const GraphEdge& a, const GraphEdge& b) { return a.from < b.from; }));
}

TEST(GraphBuild, NoWaysGiveTheEmptyGraph) {
    const std::vector<RawGraphWay> none;
    ScratchDir dir("graph-build-empty");
    const Projection proj(42.5, 1.5);
    const DiskGraph graph(sourceOf(none), proj, dir.path(), 1);
    EXPECT_EQ(graph.nodes(), 0u);
    EXPECT_EQ(encoded(graph), encodeRoadGraph(RoadGraph{}));
}

TEST(GraphBuild, TheStoredGraphIsTheSameWhetherItsEncodingComesWholeOrInPieces) {
    const RoadGraph graph = buildGraph(sourceOf(streetGrid(20)), Projection(42.52, 1.53));
    const auto raw = encodeRoadGraph(graph);
    ScratchDir dir("graph-store");
    StoreInfo info;
    {
        StoreWriter whole(dir / "whole.navmap", info);
        whole.setGraph(graph);
        whole.finish();
    }
    {
        StoreWriter pieces(dir / "pieces.navmap", info);
        pieces.writeGraph([&](const StoreWriter::ByteSink& sink) {
            // Pieces of 1 to 13 bytes.
            for (std::size_t pos = 0, n = 1; pos < raw.size(); pos += n, n = n % 13 + 1) {
                sink(std::span<const std::uint8_t>(raw).subspan(pos, std::min(n, raw.size() - pos)));
            }
        });
        pieces.finish();
    }
    const auto whole_bytes = fileBytes(dir / "whole.navmap");
    EXPECT_EQ(fileBytes(dir / "pieces.navmap"), whole_bytes);
    // The block is zlib's compress2() of the encoding (level 6), as stores have always held it.
    uLongf len = compressBound(static_cast<uLong>(raw.size()));
    std::vector<std::uint8_t> compressed(len);
    ASSERT_EQ(compress2(compressed.data(), &len, raw.data(), static_cast<uLong>(raw.size()), 6), Z_OK);
    compressed.resize(len);
    const auto store = TileStore::open(dir / "pieces.navmap");
    EXPECT_EQ(store->info().graph_raw_size, raw.size());
    ASSERT_EQ(store->info().graph_stored_size, compressed.size());
    EXPECT_TRUE(std::equal(compressed.begin(), compressed.end(),
                           whole_bytes.begin() + static_cast<std::ptrdiff_t>(store->info().graph_offset)));
    const auto loaded = store->tryLoadGraph();
    ASSERT_TRUE(loaded.error.empty()) << loaded.error;
    EXPECT_EQ(encodeRoadGraph(loaded.graph), raw);
}

TEST(GraphBuild, AFullDiskIsAnErrorNamingTheScratchFile) {
    // RLIMIT_FSIZE stands in for a full disk (withFileSizeLimit).
    ScratchDir dir("graph-full");
    std::string error;
    ASSERT_TRUE(withFileSizeLimit(4096, [&] {
        try {
            MappedFile file(dir / "graph-nodes.bin", 1 << 20);
        } catch (const SpillError& e) {
            error = e.what();
        }
    }));
    EXPECT_EQ(error, "fallocate(" + (dir / "graph-nodes.bin").string() + ", 1048576 bytes): File too large");
    EXPECT_FALSE(std::filesystem::exists(dir / "graph-nodes.bin"));
}
