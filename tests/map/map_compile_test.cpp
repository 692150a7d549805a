// SPDX-License-Identifier: Apache-2.0
// navmap-compile on the real Andorra extract + SRTM tile (repo data/), and on bad input.
#include <gtest/gtest.h>

#include <spawn.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <optional>
#include <random>
#include <set>

#include "guidance_test_graph.h"
#include "map_test_util.h"
#include "navmap/map/compile/compiler.h"
#include "navmap/map/compile/shard.h"
#include "navmap/map/dem.h"
#include "navmap/map/guidance/lane_guidance.h"
#include "navmap/map/store_lock.h"
#include "navmap/map/store_set.h"
#include "navmap/map/tile_codec.h"
#include "navmap/map/tile_store.h"

extern char** environ;

using namespace navmap::map;
using navmap::map::test::repoData;
using navmap::map::test::ScratchDir;

namespace {

// Edges of the Andorra graph with turn lanes (AndorraStore.TurnLanesReachTheRoadGraph).
constexpr std::size_t kAndorraLaneEdges = 7;  // each tagged way is one edge of the graph

class AndorraStore : public ::testing::Test {
protected:
    static void SetUpTestSuite() {
        s_dir = new ScratchDir("compile");
        CompileOptions opt;
        opt.osm = repoData("andorra-2021-04-14.osm.pbf");
        opt.dems = {repoData("N42E001.hgt")};
        opt.out = s_dir->path() / "andorra.navmap";
        s_stats = new CompileStats(compileStore(opt));
        s_store = TileStore::open(opt.out);
    }
    static void TearDownTestSuite() {
        s_store.reset();
        delete s_stats;
        delete s_dir;
    }
    /// All tiles of one level.
    static std::vector<std::shared_ptr<const Tile>> level(int l) {
        std::vector<std::shared_ptr<const Tile>> out;
        for (const auto& id : s_store->tileIds()) {
            if (id.level != l) continue;
            auto res = s_store->load(id);
            EXPECT_TRUE(res.tile) << res.error;
            if (res.tile) out.push_back(res.tile);
        }
        return out;
    }
    static inline ScratchDir* s_dir = nullptr;
    static inline CompileStats* s_stats = nullptr;
    static inline std::shared_ptr<TileStore> s_store;
};

}  // namespace

TEST_F(AndorraStore, SummaryCountsMatchTheExtract) {
    const CompileStats& s = *s_stats;
    // SOURCES.md: 4,764 highway ways (a few are areas or non-roads), 4,894 + 12 buildings.
    EXPECT_GT(s.roads, 4600u);
    EXPECT_LE(s.roads, 4764u);
    EXPECT_GT(s.road_vertices, 50000u);
    EXPECT_GE(s.buildings, 4850u);
    EXPECT_GT(s.areas, 300u);
    EXPECT_GE(s.place_labels, 130u);
    EXPECT_GT(s.poi_labels, 700u);
    EXPECT_GT(s.road_labels, 900u);
    EXPECT_GT(s.graph_nodes, 3000u);
    EXPECT_GT(s.graph_edges, s.graph_nodes);
    EXPECT_EQ(s.dem_voids_filled, 7652u);
    EXPECT_EQ(s.tiles, s_store->info().tile_count);
    EXPECT_EQ(s.tiles_per_level.size(), static_cast<std::size_t>(s_store->scheme().levelCount()));
    EXPECT_EQ(s.tiles_per_level[0], 1u);
    EXPECT_GT(s.store_bytes, 100000u);
    // Nodes west of 1.0 E lie outside N42E001: warned about, rendered flat.
    ASSERT_FALSE(s.warnings.empty());
    EXPECT_NE(s.warnings.back().find("flat"), std::string::npos) << s.warnings.back();
    EXPECT_NE(formatSummary(s).find("buildings:  "), std::string::npos);
}

// The extract tags maxspeed on 653 ways; 651 of the graph's ways get a limit on their edges
// (docs/tile-store.md "Speed limits").
TEST_F(AndorraStore, SpeedLimitsReachTheRoadGraph) {
    const RoadGraph g = s_store->loadGraph();
    std::set<std::int64_t> with_limit, ways;
    std::size_t edges_with_limit = 0;
    for (const GraphEdge& e : g.edges) {
        ways.insert(e.way_id);
        if (e.speed_limit_kmh == 0) continue;
        ++edges_with_limit;
        with_limit.insert(e.way_id);
        EXPECT_LE(e.speed_limit_kmh, 130) << "way " << e.way_id;
    }
    std::printf("speed limits: %zu of %zu graph ways, %zu of %zu edges\n", with_limit.size(), ways.size(),
                edges_with_limit, g.edges.size());
    EXPECT_EQ(with_limit.size(), 651u);
    EXPECT_EQ(edges_with_limit, 1852u);
}

// The extract tags turn lanes on 7 ways, all of the CG-2 (a climbing lane that ends: `|merge_to_left`
// and `|merge_to_right`, `none|merge_to_left` on the Port d'Envalira); each reaches the graph on
// the edges of its tagged direction (docs/tile-store.md "Turn lanes").
TEST_F(AndorraStore, TurnLanesReachTheRoadGraph) {
    const RoadGraph g = s_store->loadGraph();
    std::set<std::int64_t> with_lanes;
    std::size_t edges_with_lanes = 0;
    for (const GraphEdge& e : g.edges) {
        const auto lanes = g.lanesOf(e);
        if (lanes.empty()) continue;
        ++edges_with_lanes;
        with_lanes.insert(e.way_id);
        ASSERT_EQ(lanes.size(), 2u) << "way " << e.way_id;
        EXPECT_EQ(lanes[0], 0) << "way " << e.way_id;  // the lane that goes on has no arrows
        EXPECT_TRUE(lanes[1] == lane_arrow::kMergeToLeft || lanes[1] == lane_arrow::kMergeToRight)
            << "way " << e.way_id;
    }
    std::printf("turn lanes: %zu graph ways, %zu of %zu edges, %zu lane values\n", with_lanes.size(), edges_with_lanes,
                g.edges.size(), g.lane_arrows.size());
    EXPECT_EQ(with_lanes,
              (std::set<std::int64_t>{28833924, 181921084, 456350882, 456350884, 456350895, 456350896, 456350897}));
    EXPECT_EQ(edges_with_lanes, kAndorraLaneEdges);
    EXPECT_EQ(s_stats->turn_lane_ways, 7u);
    EXPECT_EQ(s_stats->turn_lane_values_ignored, 0u);
    EXPECT_EQ(s_stats->turn_lane_tags_dropped, 0u);
}

// A real junction: the CG-2's climbing lane ends where way 456350884 meets the next way of the
// road (node 4525945527). A route on along the CG-2 gets the way's two lanes before the junction,
// the lane that goes on highlighted, not the one merging away.
TEST_F(AndorraStore, LanesBeforeARealJunction) {
    const RoadGraph g = s_store->loadGraph();
    const GraphEdge* tagged = nullptr;
    for (const GraphEdge& e : g.edges) {
        if (e.way_id == 456350884 && g.nodes[e.to].osm_id == 4525945527 && !g.lanesOf(e).empty()) tagged = &e;
    }
    ASSERT_NE(tagged, nullptr) << "way 456350884's edge into node 4525945527";
    const std::uint32_t junction = tagged->to;
    // On along the road: the way leaving the junction closest to straight ahead (not back).
    const auto heading = [&](std::uint32_t a, std::uint32_t b) {
        return std::atan2(g.nodes[b].x - g.nodes[a].x, g.nodes[b].y - g.nodes[a].y);
    };
    const double in = heading(tagged->from, junction);
    const GraphEdge* out = nullptr;
    double best = 10.0;
    for (const GraphEdge& e : g.outEdges(junction)) {
        if (e.to == tagged->from) continue;
        const double d = std::abs(std::remainder(heading(junction, e.to) - in, 2.0 * M_PI));
        if (d < best) {
            best = d;
            out = &e;
        }
    }
    ASSERT_NE(out, nullptr);
    const auto line = test::routeLine(g, tagged->from, out->to);
    ASSERT_GE(line.size(), 3u);
    std::vector<PlanarPoint> points;
    std::size_t at = 0;
    for (const RoutePoint& p : line) {
        if (std::hypot(p.position.x - g.nodes[junction].x, p.position.y - g.nodes[junction].y) < 0.5)
            at = points.size();
        points.push_back(p.position);
    }
    ASSERT_GT(at, 0u) << "the route passes the junction";
    guidance::Maneuver on;  // as a control route gives it: straight on at the junction
    on.type = guidance::ManeuverType::Straight;
    on.point = on.end_point = at;
    const guidance::LaneFinder finder(g);
    const auto found = finder.find(points, {on});
    ASSERT_EQ(found.size(), 1u);
    ASSERT_TRUE(found[0].has_value());
    EXPECT_EQ(found[0]->way_id, 456350884);
    EXPECT_EQ(found[0]->lanes, (std::vector<std::uint16_t>{0, lane_arrow::kMergeToRight}));
    EXPECT_EQ(found[0]->recommended, 0b01u);
    EXPECT_NEAR(found[0]->before_junction_m, 0.0, 0.01);
}

TEST_F(AndorraStore, LeafTilesKeepNamesRoadsBuildingsAndTerrain) {
    const auto leaves = level(s_store->scheme().leafLevel());
    bool town = false, cg3 = false, levels_height = false, middle_dot = false, path = false;
    for (const auto& t : leaves) {
        for (std::size_t i = 1; i < t->roads.size(); ++i) EXPECT_LE(t->roads[i - 1].cls, t->roads[i].cls);
        for (const auto& r : t->roads) {
            if (r.ref == "CG-3" && r.cls == RoadClass::Primary) cg3 = true;
            if (r.cls == RoadClass::Path) path = true;
            ASSERT_GE(r.points.size(), 2u);
            for (const auto& p : r.points) {
                EXPECT_GE(p.x, -0.01f);
                EXPECT_LE(p.x, t->size_m + 0.01);
            }
        }
        for (const auto& b : t->buildings) {
            EXPECT_GT(b.height_m, 0.0f);
            if (b.height_m != 8.0f && std::fmod(b.height_m, 3.0f) == 0.0f) levels_height = true;
            EXPECT_EQ(b.footprint.indices.size() % 3, 0u);
        }
        for (const auto& l : t->labels) {
            if (l.name.find("l\xC2\xB7l") != std::string::npos) middle_dot = true;  // UTF-8 "l·l"
            if (l.kind == LabelKind::Place && l.name == "Andorra la Vella") {
                town = true;
                EXPECT_EQ(l.subclass, static_cast<std::uint8_t>(PlaceClass::Town));
                // SOURCES.md: SRTM reads about 1024 m at Andorra la Vella.
                const int c = static_cast<int>(std::lround(l.anchor.x / t->dem.spacing_m));
                const int r = static_cast<int>(std::lround(l.anchor.y / t->dem.spacing_m));
                EXPECT_NEAR(t->dem.at(r, c), 1040.0f, 80.0f);
                EXPECT_FLOAT_EQ(t->dem.coverage, 1.0f);
            }
        }
    }
    EXPECT_TRUE(town);
    EXPECT_TRUE(cg3);
    EXPECT_TRUE(levels_height);
    EXPECT_TRUE(middle_dot);
    EXPECT_TRUE(path);
}

TEST_F(AndorraStore, CoarseLevelsAreLighter) {
    const auto root = level(0);
    ASSERT_EQ(root.size(), 1u);
    for (const auto& r : root[0]->roads) EXPECT_LE(r.cls, RoadClass::Primary) << roadClassName(r.cls);
    EXPECT_TRUE(root[0]->buildings.empty());
    std::size_t root_vertices = 0, leaf_vertices = 0;
    for (const auto& r : root[0]->roads) root_vertices += r.points.size();
    for (const auto& t : level(s_store->scheme().leafLevel())) {
        for (const auto& r : t->roads) leaf_vertices += r.points.size();
    }
    EXPECT_GT(root_vertices, 0u);
    EXPECT_LT(root_vertices * 10, leaf_vertices);
}

TEST_F(AndorraStore, RoadGraphLoads) {
    const RoadGraph g = s_store->loadGraph();
    EXPECT_EQ(g.nodes.size(), s_stats->graph_nodes);
    EXPECT_EQ(g.edges.size(), s_stats->graph_edges);
    double total = 0;
    for (std::uint32_t n = 0; n < g.nodes.size(); ++n) {
        for (const auto& e : g.outEdges(n)) {
            EXPECT_EQ(e.from, n);
            EXPECT_GT(e.length_m, 0.0f);
            EXPECT_GE(e.shape_end - e.shape_begin, 2u);
            total += e.length_m;
        }
    }
    EXPECT_GT(total, 1e6);  // > 1000 km of directed road in Andorra
}

// docs/tile-store.md "Damage" on the compiled store: a flipped bit in the header or the index is
// a fatal error naming it; in a tile (one of each level) only that tile fails; in the road graph
// every tile still loads and the graph reports itself unavailable.
TEST_F(AndorraStore, ABitFlippedInEachSectionDegradesOrFailsAsDocumented) {
    const auto src = s_dir->path() / "andorra.navmap";
    std::ifstream in(src, std::ios::binary);
    const std::vector<char> bytes{std::istreambuf_iterator<char>(in), {}};
    const auto path = s_dir->path() / "damaged.navmap";
    auto with_flip = [&](std::uint64_t at) {
        auto d = bytes;
        d.at(at) = static_cast<char>(d.at(at) ^ 0x10);
        std::ofstream(path, std::ios::binary | std::ios::trunc).write(d.data(), static_cast<std::streamsize>(d.size()));
    };
    auto open_error = [&] {
        try {
            TileStore::open(path);
        } catch (const StoreError& e) {
            return std::string(e.what());
        }
        return std::string();
    };
    auto failing = [](const TileStore& store) {
        std::vector<std::string> bad;
        for (const auto& id : store.tileIds()) {
            if (!store.load(id).tile) bad.push_back(id.toString());
        }
        return bad;
    };
    const StoreInfo& info = s_store->info();
    with_flip(0);
    EXPECT_EQ(open_error(), path.string() + ": not a navmap tile store (bad magic)");
    with_flip(70);
    EXPECT_EQ(open_error(), path.string() + ": header checksum mismatch");
    with_flip(info.index_offset + 100);
    EXPECT_EQ(open_error(), path.string() + ": tile index checksum mismatch");

    for (int level = 0; level < s_store->scheme().levelCount(); ++level) {
        TileId victim{};
        for (const auto& id : s_store->tileIds()) {
            if (id.level == level) victim = id;
        }
        with_flip(s_store->blobOffset(victim) + s_store->storedSize(victim) / 2);
        const auto store = TileStore::open(path);
        EXPECT_EQ(failing(*store), std::vector<std::string>{victim.toString()});
        EXPECT_EQ(store->load(victim).error,
                  path.string() + ": tile " + victim.toString() + ": checksum mismatch (corrupt tile)");
        EXPECT_TRUE(store->tryLoadGraph().ok());
    }

    with_flip(info.graph_offset + info.graph_stored_size / 3);
    const auto store = TileStore::open(path);
    EXPECT_TRUE(failing(*store).empty());
    const auto graph = store->tryLoadGraph();
    EXPECT_EQ(graph.problem, "checksum mismatch");
    EXPECT_EQ(graph.error, path.string() + ": road graph: checksum mismatch");
    std::filesystem::remove(path);
}

TEST(CompileBadInput, TruncatedRandomAndMissingPbf) {
    ScratchDir dir("compile-bad");
    std::ifstream in(repoData("andorra-2021-04-14.osm.pbf"), std::ios::binary);
    std::vector<char> bytes{std::istreambuf_iterator<char>(in), {}};
    const auto trunc = dir / "truncated.osm.pbf";
    std::ofstream(trunc, std::ios::binary).write(bytes.data(), static_cast<std::streamsize>(bytes.size() / 3));
    const auto junk = dir / "random.osm.pbf";
    {
        std::mt19937 rng(7);
        std::ofstream out(junk, std::ios::binary);
        for (int i = 0; i < 100000; ++i) out.put(static_cast<char>(rng()));
    }
    for (const auto& [path, what] :
         {std::pair{trunc, std::string("cannot read OSM data")}, std::pair{junk, std::string("cannot read OSM data")},
          std::pair{dir / "absent.osm.pbf", std::string("No such file or directory (OSM input)")}}) {
        CompileOptions opt;
        opt.osm = path;
        opt.out = dir / "out.navmap";
        try {
            compileStore(opt);
            ADD_FAILURE() << "expected CompileError for " << path;
        } catch (const CompileError& e) {
            const std::string msg = e.what();
            EXPECT_NE(msg.find(path.string()), std::string::npos) << msg;
            EXPECT_NE(msg.find(what), std::string::npos) << msg;
        }
        EXPECT_FALSE(std::filesystem::exists(dir / "out.navmap"));
    }
}

// docs/architecture.md "Untrusted files": an input that is no regular file is named for what it
// is, at once (a FIFO is opened without blocking). --osm /dev/zero used to say "no such file".
TEST(CompileBadInput, InputsThatAreNoRegularFilesSayWhatTheyAre) {
    ScratchDir dir("compile-not-regular");
    const auto fifo = dir / "fifo.osm.pbf";
    ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
    const auto compileError = [&](const CompileOptions& opt) {
        try {
            compileStore(opt);
        } catch (const std::exception& e) {  // CompileError, DemError
            return std::string(e.what());
        }
        return std::string("no error");
    };
    CompileOptions opt;
    opt.out = dir / "out.navmap";
    for (const auto& [osm, what] :
         {std::pair{std::filesystem::path("/dev/zero"), std::string("a character device")},
          std::pair{fifo, std::string("a FIFO")}, std::pair{dir.path(), std::string("a directory")}}) {
        opt.osm = osm;
        EXPECT_EQ(compileError(opt), osm.string() + ": is " + what + ", not a regular file (OSM input)");
        // Sharded: the inputs' fingerprint reads them first; it says the same.
        opt.shard = {0, 2};
        EXPECT_EQ(compileError(opt), osm.string() + ": is " + what + ", not a regular file (OSM input)");
        opt.shard = {};
    }
    EXPECT_FALSE(std::filesystem::exists(opt.out));
    // A DEM, in memory or read when first needed.
    const auto dem_fifo = dir / "N42E001.hgt";
    ASSERT_EQ(::mkfifo(dem_fifo.c_str(), 0600), 0);
    opt.osm = repoData("andorra-2021-04-14.osm.pbf");
    opt.dems = {dem_fifo};
    for (const std::uint64_t limit : {std::uint64_t{0}, std::uint64_t{64}}) {
        opt.memory_limit_mib = limit;
        EXPECT_EQ(compileError(opt), dem_fifo.string() + ": is a FIFO, not a regular file (DEM file)");
    }
}

// A DEM whose every sample is a void says so; it used to be reported as tiles outside the DEM.
TEST(CompileBadInput, AnAllVoidDemIsSaidToBeAllVoids) {
    ScratchDir dir("compile-void-dem");
    {
        std::ofstream osm(dir / "road.osm");
        osm << R"(<?xml version="1.0" encoding="UTF-8"?>
<osm version="0.6" generator="test">
 <node id="1" version="1" lat="43.020" lon="7.020"/>
 <node id="2" version="1" lat="43.030" lon="7.040"/>
 <way id="100" version="1"><nd ref="1"/><nd ref="2"/><tag k="highway" v="primary"/></way>
</osm>
)";
        std::ofstream hgt(dir / "N43E007.hgt", std::ios::binary);
        const char void_sample[2] = {static_cast<char>(0x80), 0};  // -32768, big-endian
        for (int i = 0; i < 1201 * 1201; ++i) hgt.write(void_sample, 2);
    }
    for (const std::uint64_t limit : {std::uint64_t{0}, std::uint64_t{64}}) {
        CompileOptions opt;
        opt.osm = dir / "road.osm";
        opt.dems = {dir / "N43E007.hgt"};
        opt.out = dir / "road.navmap";
        opt.leaf_tile_m = 1000;
        opt.memory_limit_mib = limit;
        const CompileStats stats = compileStore(opt);
        ASSERT_GE(stats.warnings.size(), 2u) << "limit " << limit;
        EXPECT_NE(
            std::find(stats.warnings.begin(), stats.warnings.end(),
                      "DEM N43E007.hgt: all 1442401 samples are voids: it gives no heights, its area is flat (0 m)"),
            stats.warnings.end())
            << "limit " << limit;
        EXPECT_EQ(stats.warnings.back(),
                  std::to_string(stats.tiles_without_dem) + " of " + std::to_string(stats.tiles_per_level.back()) +
                      " leaf tiles have no heights: the DEM is all voids (N43E007.hgt); terrain is flat (0 m)")
            << "limit " << limit;
        EXPECT_EQ(stats.tiles_without_dem, stats.tiles_per_level.back());
    }
}

TEST(CompileBadInput, DemOfWrongSizeNamesTheFile) {
    ScratchDir dir("compile-dem");
    const auto bad = dir / "N42E001.hgt";
    std::ofstream(bad, std::ios::binary).write("\0\0\0\0", 4);
    CompileOptions opt;
    opt.osm = repoData("andorra-2021-04-14.osm.pbf");
    opt.dems = {bad};
    opt.out = dir / "out.navmap";
    try {
        compileStore(opt);
        FAIL() << "expected DemError";
    } catch (const DemError& e) {
        EXPECT_NE(std::string(e.what()).find(bad.string() + ": 4 bytes is not an SRTM tile"), std::string::npos)
            << e.what();
    }
}

namespace {

namespace fs = std::filesystem;

/// navmap-compile as a child process, stdout and stderr into `log`; `shell` runs before it
/// (limits, traps).
struct CompileProcess {
    pid_t pid = -1;
    fs::path log;
    CompileProcess(const std::string& args, fs::path log_path, const std::string& shell = "")
        : log(std::move(log_path)) {
        const std::string cmd =
            shell + std::string("exec ") + NAVMAP_COMPILE_PATH + " " + args + " > " + log.string() + " 2>&1";
        const char* argv[] = {"/bin/sh", "-c", cmd.c_str(), nullptr};
        if (posix_spawn(&pid, "/bin/sh", nullptr, nullptr, const_cast<char**>(argv), environ) != 0) pid = -1;
    }
    /// Exit status (-1 when it did not exit normally).
    int wait() {
        int status = 0;
        if (pid <= 0 || ::waitpid(pid, &status, 0) != pid) return -1;
        return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    }
    [[nodiscard]] std::string output() const {
        std::ifstream in(log);
        return {std::istreambuf_iterator<char>(in), {}};
    }
};

std::string andorraArgs(const fs::path& out) {
    return "-q --osm " + repoData("andorra-2021-04-14.osm.pbf").string() + " --dem " +
           repoData("N42E001.hgt").string() + " --out " + out.string();
}

std::vector<std::string> namesIn(const fs::path& d) {
    std::vector<std::string> names;
    for (const auto& e : fs::directory_iterator(d)) names.push_back(e.path().filename().string());
    std::sort(names.begin(), names.end());
    return names;
}

/// Every tile of the store decodes and the graph loads: what a half-written or interleaved store fails.
void expectWholeStore(const fs::path& path) {
    const auto store = TileStore::open(path);
    std::size_t loaded = 0;
    for (const auto& id : store->tileIds()) {
        const auto res = store->load(id);
        EXPECT_TRUE(res.tile) << res.error;
        loaded += res.tile ? 1 : 0;
    }
    EXPECT_GT(loaded, 100u);
    EXPECT_GT(store->loadGraph().edges.size(), 10000u);
}

}  // namespace

TEST(CompileCli, TwoCompilesToOneStoreNeverPublishAHalfWrittenOne) {
    ScratchDir dir("compile-race");
    const fs::path out = dir / "s.navmap";
    for (int round = 0; round < 2; ++round) {
        CompileProcess a(andorraArgs(out), dir / "a.log");
        CompileProcess b(andorraArgs(out), dir / "b.log");
        const int sa = a.wait(), sb = b.wait();
        // The second to start is refused at once, naming the first; one that finds the store
        // free (the other already done) writes it whole again.
        EXPECT_TRUE(sa == 0 || sb == 0) << a.output() << b.output();
        for (const auto* p : {&a, &b}) {
            const int status = p == &a ? sa : sb;
            const int other = p == &a ? b.pid : a.pid;
            if (status == 0) continue;
            EXPECT_EQ(status, 1);
            EXPECT_EQ(p->output(), "navmap-compile: " + out.string() + " is being written by another process (pid " +
                                       std::to_string(other) + ")\n");
        }
        expectWholeStore(out);
        EXPECT_EQ(namesIn(dir.path()), (std::vector<std::string>{"a.log", "b.log", "s.navmap"}));
    }
}

TEST(CompileCli, AStoreBeingWrittenIsRefusedWithTheWritersPid) {
    ScratchDir dir("compile-locked");
    const fs::path out = dir / "s.navmap";
    std::optional<StoreLock> held(std::in_place, out);
    CompileProcess p(andorraArgs(out), dir / "p.log");
    EXPECT_EQ(p.wait(), 1);
    EXPECT_EQ(p.output(), "navmap-compile: " + out.string() + " is being written by another process (pid " +
                              std::to_string(::getpid()) + ")\n");
    EXPECT_FALSE(fs::exists(out));
    held.reset();
    EXPECT_EQ(namesIn(dir.path()), std::vector<std::string>{"p.log"});
}

TEST(CompileCli, AMissingOutputFolderIsAnErrorNamingIt) {
    ScratchDir dir("compile-folder");
    const fs::path out = dir / "missing/sub/x.navmap";
    CompileProcess p(andorraArgs(out), dir / "p.log");
    EXPECT_EQ(p.wait(), 1);
    EXPECT_EQ(p.output(), "navmap-compile: " + out.string() + ": directory " + (dir / "missing/sub").string() +
                              " does not exist\n");
    EXPECT_FALSE(fs::exists(dir / "missing"));
}

TEST(CompileCli, NumericOptionsMustBeFiniteAndInRange) {
    ScratchDir dir("compile-usage");
    const fs::path out = dir / "x.navmap";
    const std::pair<std::string, std::string> cases[] = {
        {"--default-building-height nan", "--default-building-height: 'nan' is not a finite number in [0, 1000]"},
        {"--default-building-height inf", "--default-building-height: 'inf' is not a finite number in [0, 1000]"},
        {"--default-building-height -3", "--default-building-height: '-3' is not a finite number in [0, 1000]"},
        {"--leaf-size nan", "--leaf-size: 'nan' is not a finite number in [10, 1e+06]"},
        {"--leaf-size 5", "--leaf-size: '5' is not a finite number in [10, 1e+06]"},
        {"--leaf-size 2000x", "--leaf-size: '2000x' is not a finite number in [10, 1e+06]"},
        {"--dem-samples 1", "--dem-samples: '1' is not 0 (no DEM grid) or an integer in [2, 1025]"},
        {"--dem-samples nan", "--dem-samples: 'nan' is not 0 (no DEM grid) or an integer in [2, 1025]"},
    };
    for (const auto& [option, message] : cases) {
        CompileProcess p(andorraArgs(out) + " " + option, dir / "p.log");
        EXPECT_EQ(p.wait(), 2) << option;  // a usage error, as documented
        EXPECT_NE(p.output().find(message), std::string::npos) << option << ": " << p.output();
        EXPECT_FALSE(fs::exists(out)) << option;
    }
    // Other usage errors exit 2 as well; the library refuses NaN on its own too.
    CompileProcess missing("--out " + out.string(), dir / "p.log");
    EXPECT_EQ(missing.wait(), 2);
    EXPECT_NE(missing.output().find("--osm is required"), std::string::npos) << missing.output();
    CompileOptions opt;
    opt.osm = repoData("andorra-2021-04-14.osm.pbf");
    opt.out = out;
    opt.default_building_height_m = std::nanf("");
    EXPECT_THROW(compileStore(opt), CompileError);
    EXPECT_EQ(namesIn(dir.path()), std::vector<std::string>{"p.log"});
}

namespace {

/// Does a point (tile-local) lie in one of the polygon's triangles?
bool inPolygon(const Polygon& poly, LocalPoint p) {
    for (std::size_t i = 0; i + 2 < poly.indices.size(); i += 3) {
        const LocalPoint a = poly.vertices[poly.indices[i]], b = poly.vertices[poly.indices[i + 1]],
                         c = poly.vertices[poly.indices[i + 2]];
        auto side = [&](LocalPoint u, LocalPoint v) { return (v.x - u.x) * (p.y - u.y) - (v.y - u.y) * (p.x - u.x); };
        const float s0 = side(a, b), s1 = side(b, c), s2 = side(c, a);
        if ((s0 >= 0 && s1 >= 0 && s2 >= 0) || (s0 <= 0 && s1 <= 0 && s2 <= 0)) return true;
    }
    return false;
}

}  // namespace

// A synthetic coast (Andorra has none): an island in the sea, a named road across the water's
// bounds and a named road tunnel, with an SRTM3 tile that is 100 m everywhere (as void filling
// makes of a sea that SRTM left void).
TEST(CompileCoast, AnIslandIsLandInASeaAtZeroMetresAndTunnelsGetNoLabel) {
    ScratchDir dir("coast");
    {
        std::ofstream osm(dir / "coast.osm");
        osm << R"(<?xml version="1.0" encoding="UTF-8"?>
<osm version="0.6" generator="test">
 <node id="1" version="1" lat="43.030" lon="7.030"/>
 <node id="2" version="1" lat="43.030" lon="7.050"/>
 <node id="3" version="1" lat="43.045" lon="7.050"/>
 <node id="4" version="1" lat="43.045" lon="7.030"/>
 <node id="10" version="1" lat="43.000" lon="7.000"/>
 <node id="11" version="1" lat="43.060" lon="7.100"/>
 <node id="20" version="1" lat="43.035" lon="7.035"/>
 <node id="21" version="1" lat="43.040" lon="7.045"/>
 <way id="100" version="1"><nd ref="1"/><nd ref="2"/><nd ref="3"/><nd ref="4"/><nd ref="1"/>
  <tag k="natural" v="coastline"/></way>
 <way id="200" version="1"><nd ref="10"/><nd ref="11"/><tag k="highway" v="primary"/><tag k="name" v="Sea Road"/></way>
 <way id="300" version="1"><nd ref="20"/><nd ref="21"/><tag k="highway" v="primary"/>
  <tag k="tunnel" v="yes"/><tag k="layer" v="-1"/><tag k="name" v="Tunnel Road"/></way>
</osm>
)";
    }
    {
        std::ofstream hgt(dir / "N43E007.hgt", std::ios::binary);
        const char sample[2] = {0, 100};  // big-endian 100 m
        for (int i = 0; i < 1201 * 1201; ++i) hgt.write(sample, 2);
    }
    CompileOptions opt;
    opt.osm = dir / "coast.osm";
    opt.dems = {dir / "N43E007.hgt"};
    opt.out = dir / "coast.navmap";
    opt.leaf_tile_m = 1000;
    const CompileStats stats = compileStore(opt);
    EXPECT_EQ(stats.coast_ways, 1u);
    EXPECT_EQ(stats.sea_rings, 1u);
    EXPECT_EQ(stats.islands, 1u);
    EXPECT_EQ(stats.road_labels, 1u);  // "Sea Road"; the tunnel has none
    EXPECT_NE(formatSummary(stats).find("coast:      1 coastline ways, 1 sea rings, 1 islands"), std::string::npos)
        << formatSummary(stats);

    const auto store = TileStore::open(opt.out);
    const Projection proj = store->projection();
    const int leaf = store->scheme().leafLevel();
    struct Probe {
        double lat, lon;
        bool sea;
    };
    for (const Probe& probe : {Probe{43.005, 7.090, true}, Probe{43.055, 7.010, true}, Probe{43.020, 7.040, true},
                               Probe{43.0375, 7.040, false}, Probe{43.032, 7.048, false}}) {
        const PlanarPoint p = proj.forward(probe.lat, probe.lon);
        const auto id = store->scheme().tileAt(leaf, p);
        ASSERT_TRUE(id);
        const auto res = store->load(*id);
        ASSERT_TRUE(res.tile) << res.error;
        const Tile& t = *res.tile;
        const LocalPoint local{static_cast<float>(p.x - t.origin_x), static_cast<float>(p.y - t.origin_y)};
        bool wet = false;
        for (const Area& a : t.areas) wet = wet || (a.cls == AreaClass::Sea && inPolygon(a.polygon, local));
        EXPECT_EQ(wet, probe.sea) << probe.lat << ", " << probe.lon;
        // The DEM sample nearest the probe: 0 m in the sea, the DEM's 100 m on the island.
        ASSERT_GE(t.dem.size, 2);
        const int c = static_cast<int>(std::lround(local.x / t.dem.spacing_m));
        const int r = static_cast<int>(std::lround(local.y / t.dem.spacing_m));
        EXPECT_FLOAT_EQ(t.dem.at(r, c), probe.sea ? 0.0f : 100.0f) << probe.lat << ", " << probe.lon;
    }
    for (const auto& id : store->tileIds()) {
        const auto res = store->load(id);
        ASSERT_TRUE(res.tile) << res.error;
        for (const Label& l : res.tile->labels) EXPECT_NE(l.name, "Tunnel Road") << id.toString();
    }
}

// ---- sharded compile (shard.h, docs/sharded-compile.md) ----

TEST(Shards, EveryTileHasExactlyOneShardAndEachShardIsOneBandOfColumns) {
    // The data covers leaf columns 1000..1630 of a 12-level scheme (the root square is wider).
    const ShardGrid grid{11, 1000, 1630};
    for (const int n : {1, 2, 3, 7, 64}) {
        for (int level = 0; level <= 12; ++level) {
            const std::uint32_t columns = 1u << level;
            int previous = 0;
            for (std::uint32_t x = 0; x < columns; ++x) {
                const int k = tileShard({static_cast<std::uint8_t>(level), x, 0}, n, grid);
                ASSERT_GE(k, 0);
                ASSERT_LT(k, n);
                EXPECT_GE(k, previous) << "bands run west to east";
                previous = k;
                // Its shard's columns hold it, and no other shard's do.
                for (int j = 0; j < n; ++j) {
                    const auto [x0, x1] = shardColumns(level, {j, n}, grid);
                    EXPECT_EQ(x >= x0 && x <= x1, j == k) << "N " << n << " level " << level << " x " << x;
                }
            }
            // Equal bands of the data's columns: at the leaf level no shard has more than one
            // column of the data over its share.
            if (level == grid.leaf_level) {
                const std::uint32_t data = grid.last + 1 - grid.first;
                for (int j = 0; j < n; ++j) {
                    const auto [x0, x1] = shardColumns(level, {j, n}, grid);
                    const std::uint32_t inside = std::min(x1, grid.last) >= std::max(x0, grid.first)
                                                     ? std::min(x1, grid.last) - std::max(x0, grid.first) + 1
                                                     : 0;
                    EXPECT_LE(inside, data / static_cast<std::uint32_t>(n) + 1) << "N " << n << " shard " << j;
                    EXPECT_GE(inside + 1, data / static_cast<std::uint32_t>(n)) << "N " << n << " shard " << j;
                }
            }
        }
    }
    EXPECT_EQ(parseShardSpec("0/1").count, 1);
    EXPECT_EQ(parseShardSpec("3/4").index, 3);
    for (const std::string bad : {"4/4", "1", "/4", "1/", "-1/4", "1/0", "a/b", "1/4097", "1/4/5", "01x/4"}) {
        try {
            (void)parseShardSpec(bad);
            ADD_FAILURE() << bad << " parsed";
        } catch (const CompileError& e) {
            EXPECT_EQ(std::string(e.what()), "--shard: '" + bad + "' is not K/N with 1 <= N <= 4096 and 0 <= K < N");
        }
    }
}

namespace {

// Andorra compiled whole and in three shards, once for the suite.
class ShardedAndorra : public ::testing::Test {
protected:
    static void SetUpTestSuite() {
        s_dir = new ScratchDir("shards");
        std::vector<CompileProcess> jobs;
        jobs.emplace_back(andorraArgs(*s_dir / "single.navmap"), *s_dir / "single.log");
        for (int k = 0; k < 3; ++k) {
            jobs.emplace_back(andorraArgs(part(k)) + " --shard " + std::to_string(k) + "/3",
                              *s_dir / ("part-" + std::to_string(k) + ".log"));
        }
        // In bounded memory: 1 MiB forces many bands (Andorra spills 3.4 MiB of features).
        s_spill = new ScratchDir("shards-spill");
        // Not quiet: the test reads the progress lines.
        jobs.emplace_back(andorraArgs(*s_dir / "bounded.navmap").substr(3) + " --memory-limit 1 --spill-dir " +
                              s_spill->path().string(),
                          *s_dir / "bounded.log");
        jobs.emplace_back(andorraArgs(*s_dir / "bounded-part-1.navmap") + " --memory-limit 1 --shard 1/3",
                          *s_dir / "bounded-part-1.log");
        for (auto& j : jobs) EXPECT_EQ(j.wait(), 0) << j.output();
    }
    static void TearDownTestSuite() {
        delete s_spill;
        delete s_dir;
    }
    static fs::path part(int k) { return *s_dir / ("part-" + std::to_string(k) + ".navmap"); }
    static std::string parts(std::initializer_list<int> ks) {
        std::string s;
        for (const int k : ks) s += " " + part(k).string();
        return s;
    }
    static std::string bytes(const fs::path& p) {
        std::ifstream in(p, std::ios::binary);
        return {std::istreambuf_iterator<char>(in), {}};
    }
    static inline ScratchDir* s_dir = nullptr;
    static inline ScratchDir* s_spill = nullptr;
};

}  // namespace

TEST_F(ShardedAndorra, TheMergedShardsEqualTheSingleCompileByteForByte) {
    const auto single = TileStore::open(*s_dir / "single.navmap");
    std::size_t tiles = 0;
    for (int k = 0; k < 3; ++k) {
        // Each shard holds its band's tiles only, and only shard 0 the road graph.
        const auto store = TileStore::open(part(k));
        const auto manifest = readShardManifest(shardManifestPath(part(k)));
        EXPECT_EQ(manifest.shard.index, k);
        EXPECT_EQ(manifest.shard.count, 3);
        EXPECT_EQ(manifest.graph, k == 0);
        EXPECT_EQ(manifest.tiles, store->tileIds().size());
        for (const TileId id : store->tileIds()) EXPECT_EQ(tileShard(id, 3, shardGridOf(store->info())), k);
        EXPECT_EQ(store->tryLoadGraph().ok(), k == 0) << store->tryLoadGraph().problem;
        EXPECT_GT(store->tileIds().size(), 0u);
        tiles += store->tileIds().size();
    }
    EXPECT_EQ(tiles, single->tileIds().size());
    // Shards in any order on the command line.
    CompileProcess merge("--merge" + parts({2, 0, 1}) + " --out " + (*s_dir / "merged.navmap").string(),
                         *s_dir / "merge.log");
    ASSERT_EQ(merge.wait(), 0) << merge.output();
    EXPECT_NE(merge.output().find("merged 3 shards: " + std::to_string(tiles) + " tiles"), std::string::npos)
        << merge.output();
    const std::string merged = bytes(*s_dir / "merged.navmap");
    ASSERT_FALSE(merged.empty());
    EXPECT_TRUE(merged == bytes(*s_dir / "single.navmap")) << "merged and single stores differ";
    // Tile for tile as well (what a byte difference would be traced to).
    const auto m = TileStore::open(*s_dir / "merged.navmap");
    for (const TileId id : single->tileIds()) {
        const auto a = single->load(id), b = m->load(id);
        ASSERT_TRUE(a.tile && b.tile) << a.error << b.error;
        EXPECT_EQ(encodeTile(*a.tile), encodeTile(*b.tile)) << int(id.level) << "/" << id.x << "/" << id.y;
    }
}

TEST_F(ShardedAndorra, TheShardsMountedTogetherAreTheSingleStoreTileForTile) {
    // Region packages: the shards' stores mounted side by side draw what the single store draws,
    // across the borders of their bands, without a merge.
    const auto single = TileStore::open(*s_dir / "single.navmap");
    std::vector<std::shared_ptr<const TileStore>> shards;
    for (const int k : {2, 0, 1}) shards.push_back(TileStore::open(part(k)));
    const auto set = StoreSet::mount(shards, single->projection());
    EXPECT_EQ(set->scheme().worldRoot(), single->scheme().worldRoot());
    EXPECT_EQ(set->scheme().levelCount(), single->scheme().levelCount());
    EXPECT_EQ(set->roots(), std::vector<TileId>{TileId{}});
    for (const TileId id : single->tileIds()) {
        ASSERT_TRUE(set->contains(id));
        const std::size_t k = *set->storeOf(id);
        EXPECT_EQ(tileShard(id, 3, shardGridOf(single->info())), k == 0 ? 2 : k == 1 ? 0 : 1);
        const auto a = single->load(id), b = set->load(id);
        ASSERT_TRUE(a.tile && b.tile) << a.error << b.error;
        EXPECT_EQ(encodeTile(*a.tile), encodeTile(*b.tile)) << id.toString();
    }
}

TEST_F(ShardedAndorra, TheBoundedCompileEqualsTheInMemoryOneByteForByte) {
    // With a 1 MiB limit the features went through spill files in many bands ...
    std::ifstream log(*s_dir / "bounded.log");
    const std::string out{std::istreambuf_iterator<char>(log), {}};
    // (a band takes at most a tenth of the limit in spilled features: a half for the band, at 5
    // bytes of memory per spilled byte)
    const std::string spilled = "features (3.4 MiB), at most 0.1 MiB per band; ";
    const auto at = out.find(spilled);
    ASSERT_NE(at, std::string::npos) << out;
    const int bands = std::stoi(out.substr(at + spilled.size()));
    EXPECT_GE(bands, 20) << out;
    EXPECT_NE(out.find("band " + std::to_string(bands) + "/" + std::to_string(bands) + ": "), std::string::npos) << out;
    // ... the same progress lines as the in-memory compile for the levels, and the same summary ...
    {
        const auto single = TileStore::open(*s_dir / "single.navmap");
        const TileScheme& scheme = single->scheme();
        std::vector<std::size_t> per_level(static_cast<std::size_t>(scheme.levelCount()), 0);
        for (const TileId id : single->tileIds()) ++per_level[id.level];
        std::string levels;
        for (const std::size_t n : per_level) levels += " " + std::to_string(n);
        const int leaf = scheme.leafLevel();
        EXPECT_NE(
            out.find("level " + std::to_string(leaf) + " (" + std::to_string(static_cast<long>(scheme.tileSize(leaf))) +
                     " m tiles): " + std::to_string(per_level.back()) + " tiles, store "),
            std::string::npos)
            << out;
        EXPECT_NE(out.find("tiles:      " + std::to_string(single->tileIds().size()) + " (per level:" + levels + ")"),
                  std::string::npos)
            << out;
        // The bands divide the data's columns: every band has features (the data fills the grid).
        EXPECT_EQ(out.find(": 0 features"), std::string::npos) << out;
    }
    EXPECT_NE(out.find("buildings:  4906\n"), std::string::npos) << out;
    // ... the scratch folder is gone ...
    EXPECT_TRUE(fs::is_empty(s_spill->path()));
    // ... and the store is the in-memory compile's, byte for byte and tile for tile.
    EXPECT_TRUE(bytes(*s_dir / "bounded.navmap") == bytes(*s_dir / "single.navmap")) << "bounded and single differ";
    const auto single = TileStore::open(*s_dir / "single.navmap");
    const auto bounded = TileStore::open(*s_dir / "bounded.navmap");
    ASSERT_EQ(bounded->tileIds().size(), single->tileIds().size());
    for (const TileId id : single->tileIds()) {
        const auto a = single->load(id), b = bounded->load(id);
        ASSERT_TRUE(a.tile && b.tile) << a.error << b.error;
        EXPECT_EQ(encodeTile(*a.tile), encodeTile(*b.tile)) << int(id.level) << "/" << id.x << "/" << id.y;
    }
    EXPECT_EQ(bounded->loadGraph().edges.size(), single->loadGraph().edges.size());
    // A shard compiled in bounded memory is the same shard (its manifest too).
    EXPECT_TRUE(bytes(*s_dir / "bounded-part-1.navmap") == bytes(part(1))) << "bounded shard 1/3 differs";
    EXPECT_EQ(bytes(shardManifestPath(*s_dir / "bounded-part-1.navmap")), bytes(shardManifestPath(part(1))));
    // Its scratch folder went next to its store, and is gone too.
    for (const auto& name : namesIn(s_dir->path())) EXPECT_EQ(name.find("navmap-spill-"), std::string::npos) << name;
}

TEST(CompileCli, BoundedCompileErrorsNameTheSpillPathAndLeaveNothingBehind) {
    ScratchDir dir("compile-spill-errors");
    const fs::path out = dir / "x.navmap";
    // A spill folder that cannot be made.
    CompileProcess missing(andorraArgs(out) + " --memory-limit 1 --spill-dir " + (dir / "absent").string(),
                           dir / "missing.log");
    EXPECT_EQ(missing.wait(), 1);
    EXPECT_EQ(missing.output(), "navmap-compile: mkdtemp(" + (dir / "absent" / "navmap-spill-XXXXXX").string() +
                                    "): No such file or directory\n");
    // A disk that fills up (a file size limit stands in for it): the failed call and the file.
    const fs::path spill = dir / "spill";
    fs::create_directory(spill);
    CompileProcess full(andorraArgs(out) + " --memory-limit 1 --spill-dir " + spill.string(), dir / "full.log",
                        "trap '' XFSZ; ulimit -f 2048; ");
    EXPECT_EQ(full.wait(), 1);
    const std::string error = full.output();
    EXPECT_EQ(error.rfind("navmap-compile: ", 0), 0u) << error;
    EXPECT_NE(error.find(spill.string() + "/navmap-spill-"), std::string::npos) << error;
    EXPECT_NE(error.find(": File too large\n"), std::string::npos) << error;
    EXPECT_TRUE(fs::is_empty(spill));
    EXPECT_FALSE(fs::exists(out));
    EXPECT_EQ(namesIn(dir.path()), (std::vector<std::string>{"full.log", "missing.log", "spill"}));
    // Usage: a limit that is not a number of MiB.
    CompileProcess usage(andorraArgs(out) + " --memory-limit -5", dir / "usage.log");
    EXPECT_EQ(usage.wait(), 2);
    EXPECT_NE(usage.output().find("--memory-limit: '-5' is not an integer in [0, 1073741824]"), std::string::npos)
        << usage.output();
}

TEST_F(ShardedAndorra, AMergeRefusesAnythingButOneWholeCompileNamingTheProblem) {
    const fs::path out = *s_dir / "refused.navmap";
    auto refused = [&](const std::string& args) {
        CompileProcess p("--merge" + args + " --out " + out.string(), *s_dir / "refused.log");
        EXPECT_EQ(p.wait(), 1) << args;
        EXPECT_FALSE(fs::exists(out)) << args;
        return p.output();
    };
    EXPECT_EQ(refused(parts({0, 2})), "navmap-compile: merge: shard(s) 1 of 3 missing\n");
    EXPECT_EQ(refused(parts({0, 1, 2, 1})),
              "navmap-compile: merge: shard 1/3 given twice (" + part(1).string() + ", " + part(1).string() + ")\n");
    // A shard of another compile: other options, hence another fingerprint.
    const fs::path other = *s_dir / "other.navmap";
    CompileProcess o(andorraArgs(other) + " --leaf-size 1000 --shard 1/3", *s_dir / "other.log");
    ASSERT_EQ(o.wait(), 0) << o.output();
    const std::string mixed = refused(" " + part(0).string() + " " + other.string() + " " + part(2).string());
    EXPECT_EQ(mixed.rfind("navmap-compile: " + other.string() + ": compiled from other input or options than " +
                              part(0).string() + " (",
                          0),
              0u)
        << mixed;
    EXPECT_NE(mixed.find("leaf 1000 m"), std::string::npos) << mixed;
    // A store without its manifest, and a manifest that is not one.
    const fs::path lone = *s_dir / "lone.navmap";
    fs::copy_file(part(1), lone);
    EXPECT_EQ(refused(" " + part(0).string() + " " + lone.string() + " " + part(2).string()),
              "navmap-compile: " + lone.string() +
                  ".shard.json: no such file (each shard store has its manifest beside it)\n");
    std::ofstream(shardManifestPath(lone)) << "{\"format\": \"navmap-shard-1\", \"shard\": -1}";
    EXPECT_EQ(refused(" " + part(0).string() + " " + lone.string() + " " + part(2).string()),
              "navmap-compile: " + lone.string() + ".shard.json: not a shard manifest: \"shard\" is not a count\n");
    // A manifest that lies about its shard: the tiles are in the wrong band.
    ShardManifest lie = readShardManifest(shardManifestPath(part(2)));
    lie.shard.index = 1;
    writeShardManifest(shardManifestPath(lone), lie);
    fs::copy_file(part(2), lone, fs::copy_options::overwrite_existing);
    const std::string wrong = refused(" " + part(0).string() + " " + lone.string() + " " + part(2).string());
    EXPECT_EQ(wrong.rfind("navmap-compile: ", 0), 0u) << wrong;
    EXPECT_NE(wrong.find("belongs to shard 2, not 1/3"), std::string::npos) << wrong;
}

TEST(CompileCli, ShardAndMergeUsageErrorsExitTwo) {
    ScratchDir dir("compile-shard-usage");
    const fs::path out = dir / "x.navmap";
    for (const std::string bad : {"3/3", "x", "1/0"}) {
        CompileProcess p(andorraArgs(out) + " --shard " + bad, dir / "p.log");
        EXPECT_EQ(p.wait(), 2) << bad;
        EXPECT_NE(p.output().find("--shard: '" + bad + "' is not K/N with 1 <= N <= 4096 and 0 <= K < N"),
                  std::string::npos)
            << p.output();
    }
    CompileProcess both(andorraArgs(out) + " --merge " + out.string(), dir / "p.log");
    EXPECT_EQ(both.wait(), 2);
    EXPECT_NE(both.output().find("excludes"), std::string::npos) << both.output();
    EXPECT_FALSE(fs::exists(out));
}
