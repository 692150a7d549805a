// SPDX-License-Identifier: Apache-2.0
// navmap-compile on hostile OpenStreetMap input (docs/tile-store.md "Limits"), written with
// libosmium's PBF writer: a way of millions of node references (a 4 KB file that took the compile
// to 714 MB) and a relation beyond the member cap stop the compile with an error naming them; a
// multipolygon that lists one way 50,000 times is assembled from it once, in memory and bounded
// (200,000 times took the in-memory assembly 32 s); and the spill folders of killed bounded
// compiles are removed by the next compile in the same place.
#include <gtest/gtest.h>

#include <fcntl.h>
#include <sys/file.h>
#include <sys/wait.h>
#include <unistd.h>

// GCC 12 reports a false -Wstringop-overread inside libosmium's builders (as in compile_read.cpp).
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic ignored "-Wstringop-overread"
#endif

#include <osmium/builder/attr.hpp>
#include <osmium/builder/osm_object_builder.hpp>
#include <osmium/io/pbf_output.hpp>
#include <osmium/io/writer.hpp>

#include <fstream>
#include <string>
#include <vector>

#include "map_test_util.h"
#include "navmap/map/compile/compiler.h"
#include "osm_limits.h"
#include "spill_dir.h"

using namespace navmap::map;
using navmap::map::test::ScratchDir;
using namespace osmium::builder::attr;  // NOLINT: the builder's attribute vocabulary

namespace {

namespace fs = std::filesystem;

struct Osm {
    osmium::memory::Buffer nodes{1 << 16, osmium::memory::Buffer::auto_grow::yes};
    osmium::memory::Buffer ways{1 << 16, osmium::memory::Buffer::auto_grow::yes};
    osmium::memory::Buffer relations{1 << 16, osmium::memory::Buffer::auto_grow::yes};
};

// A square of about 800 m (nodes 1-4) and a named village in it: something to compile.
Osm baseMap() {
    Osm osm;
    osmium::builder::add_node(osm.nodes, _id(1), _location(1.500, 42.500));
    osmium::builder::add_node(osm.nodes, _id(2), _location(1.510, 42.500));
    osmium::builder::add_node(osm.nodes, _id(3), _location(1.510, 42.507));
    osmium::builder::add_node(osm.nodes, _id(4), _location(1.500, 42.507));
    osmium::builder::add_node(osm.nodes, _id(5), _location(1.505, 42.503), _tag("place", "village"),
                              _tag("name", "Limits"));
    return osm;
}

// Way `id` of `n` node references, 1, 2, 1, 2, ...
void addLongWay(osmium::memory::Buffer& buffer, osmium::object_id_type id, std::size_t n) {
    {
        osmium::builder::WayBuilder way{buffer};
        way.set_id(id);
        osmium::builder::WayNodeListBuilder refs{way};
        for (std::size_t i = 0; i < n; ++i)
            refs.add_node_ref(osmium::NodeRef{static_cast<osmium::object_id_type>(1 + i % 2)});
    }
    buffer.commit();
}

// Relation `id`: a forest multipolygon listing way `way` `times` times, or `times` ways from
// `way` on when `distinct`.
void addForest(osmium::memory::Buffer& buffer, osmium::object_id_type id, osmium::object_id_type way, std::size_t times,
               bool distinct = false) {
    {
        osmium::builder::RelationBuilder relation{buffer};
        relation.set_id(id);
        relation.add_tags({{"type", "multipolygon"}, {"landuse", "forest"}});
        osmium::builder::RelationMemberListBuilder members{relation};
        for (std::size_t i = 0; i < times; ++i) {
            members.add_member(osmium::item_type::way, way + (distinct ? static_cast<osmium::object_id_type>(i) : 0),
                               "outer");
        }
    }
    buffer.commit();
}

fs::path writePbf(const fs::path& path, Osm&& osm) {
    osmium::io::Header header;
    osmium::io::Writer writer{path.string(), header, osmium::io::overwrite::allow};
    writer(std::move(osm.nodes));
    writer(std::move(osm.ways));
    writer(std::move(osm.relations));
    writer.close();
    return path;
}

struct Compiled {
    std::optional<CompileStats> stats;
    std::string error;
    std::vector<std::string> log;
};

Compiled compile(const fs::path& osm, const fs::path& out, std::uint64_t memory_limit_mib = 0) {
    Compiled run;
    CompileOptions opt;
    opt.osm = osm;
    opt.out = out;
    opt.memory_limit_mib = memory_limit_mib;
    opt.log = [&run](const std::string& line) { run.log.push_back(line); };
    try {
        run.stats = compileStore(opt);
    } catch (const CompileError& e) {
        run.error = e.what();
    }
    return run;
}

std::string wayError(const fs::path& osm, std::size_t n) {
    return osm.string() + ": way 7 has " + std::to_string(n) +
           " node references, more than 100000 (OpenStreetMap allows 2000 per way)";
}

TEST(CompileLimits, AWayBeyondTheNodeCapStopsTheCompileNamingIt) {
    ScratchDir dir("compile-huge-way");
    for (const std::size_t n : {navmap::map::detail::kMaxWayNodes + 1, std::size_t{4000000}}) {
        Osm osm = baseMap();
        addLongWay(osm.ways, 7, n);
        const fs::path pbf = writePbf(dir / ("way-" + std::to_string(n) + ".osm.pbf"), std::move(osm));
        for (const std::uint64_t limit : {0, 64}) {
            const Compiled run = compile(pbf, dir / "x.navmap", limit);
            EXPECT_FALSE(run.stats) << n << " refs, limit " << limit;
            EXPECT_EQ(run.error, wayError(pbf, n)) << "limit " << limit;
            EXPECT_FALSE(fs::exists(dir / "x.navmap"));
        }
    }
    // At the cap: compiled (the way is untagged, the village is the map).
    Osm osm = baseMap();
    addLongWay(osm.ways, 7, navmap::map::detail::kMaxWayNodes);
    const fs::path pbf = writePbf(dir / "way-at-cap.osm.pbf", std::move(osm));
    const Compiled run = compile(pbf, dir / "x.navmap");
    ASSERT_TRUE(run.stats) << run.error;
    EXPECT_EQ(run.stats->place_labels, 1u);
}

TEST(CompileLimits, ARelationBeyondTheMemberCapStopsTheCompileNamingIt) {
    ScratchDir dir("compile-huge-relation");
    Osm osm = baseMap();
    addForest(osm.relations, 9, 1000, navmap::map::detail::kMaxRelationMembers + 1, true);
    const fs::path pbf = writePbf(dir / "relation.osm.pbf", std::move(osm));
    for (const std::uint64_t limit : {0, 64}) {
        const Compiled run = compile(pbf, dir / "x.navmap", limit);
        EXPECT_FALSE(run.stats);
        EXPECT_EQ(run.error, pbf.string() +
                                 ": relation 9 has 100001 members, more than 100000 (OpenStreetMap allows "
                                 "32000 per relation)")
            << "limit " << limit;
    }
}

// One closed way listed 50,000 times as the outer ring of a forest: the assembly sees it once,
// so the forest is one area, the same in memory and bounded, and the repeats are counted.
TEST(CompileLimits, RepeatedMembersReachTheMultipolygonAssemblyOnce) {
    ScratchDir dir("compile-repeated-members");
    Osm osm = baseMap();
    osmium::builder::add_way(osm.ways, _id(10), _nodes({1, 2, 3, 4, 1}));
    addForest(osm.relations, 20, 10, 50000);
    const fs::path pbf = writePbf(dir / "repeats.osm.pbf", std::move(osm));
    for (const std::uint64_t limit : {0, 64}) {
        const Compiled run = compile(pbf, dir / ("forest-" + std::to_string(limit) + ".navmap"), limit);
        ASSERT_TRUE(run.stats) << run.error;
        EXPECT_EQ(run.stats->areas, 1u) << "limit " << limit;
        EXPECT_EQ(run.stats->repeated_members, 49999u) << "limit " << limit;
        EXPECT_EQ(run.stats->warnings.back(),
                  "1 relation(s) listed members more than once (relation 20 first): 49999 repeats left out");
    }
    const auto bytes = [&](const char* name) {
        std::ifstream in(dir / name, std::ios::binary);
        return std::string{std::istreambuf_iterator<char>(in), {}};
    };
    EXPECT_EQ(bytes("forest-0.navmap"), bytes("forest-64.navmap"));
}

// ---- spill folders of killed compiles ----

pid_t deadPid() {
    const pid_t child = ::fork();
    if (child == 0) ::_exit(0);
    int status = 0;
    ::waitpid(child, &status, 0);
    return child;
}

void makeFolder(const fs::path& dir, const std::string& owner, std::size_t scratch_bytes = 0) {
    fs::create_directories(dir);
    if (!owner.empty()) std::ofstream(dir / "owner") << owner;
    if (scratch_bytes > 0) std::ofstream(dir / "features.spill") << std::string(scratch_bytes, 'x');
}

TEST(CompileSpill, FoldersOfGoneOwnersAreRemovedByTheNextBoundedCompile) {
    ScratchDir dir("compile-stale-spill");
    const fs::path spill = dir / "spill";
    const navmap::map::detail::SpillOwner self = navmap::map::detail::SpillOwner::self();
    ASSERT_GT(self.start_ticks, 0u) << "/proc/self/stat unreadable";
    ASSERT_FALSE(self.boot_id.empty()) << "/proc/sys/kernel/random/boot_id unreadable";
    const pid_t dead = deadPid();
    const std::string boot = self.boot_id;
    // Gone: a dead pid; this pid with another start time (reused); a previous boot.
    makeFolder(spill / "navmap-spill-dead01", std::to_string(dead) + " 12345 " + boot + "\n", 1 << 20);
    makeFolder(spill / "navmap-spill-reuse1",
               std::to_string(::getpid()) + " " + std::to_string(self.start_ticks + 1) + " " + boot + "\n");
    makeFolder(spill / "navmap-spill-oldbt1",
               std::to_string(::getpid()) + " " + std::to_string(self.start_ticks) + " another-boot\n");
    // Kept: a live owner; no owner file (being made); an owner that holds its lock (a process of
    // another pid namespace); another name; an owner file that is not one.
    makeFolder(spill / "navmap-spill-alive1", self.text());
    makeFolder(spill / "navmap-spill-noown1", "");
    makeFolder(spill / "navmap-spill-lockd1", std::to_string(dead) + " 1 " + boot + "\n");
    const int lock_fd = ::open((spill / "navmap-spill-lockd1" / "owner").c_str(), O_RDONLY | O_CLOEXEC);
    ASSERT_GE(lock_fd, 0);
    ASSERT_EQ(::flock(lock_fd, LOCK_EX), 0);
    makeFolder(spill / "other-dead01", std::to_string(dead) + " 1 " + boot + "\n");
    makeFolder(spill / "navmap-spill-junk01", "not an owner\n");

    Osm osm = baseMap();
    const fs::path pbf = writePbf(dir / "village.osm.pbf", std::move(osm));
    CompileOptions opt;
    opt.osm = pbf;
    opt.out = dir / "village.navmap";
    opt.memory_limit_mib = 16;
    opt.spill_dir = spill;
    std::vector<std::string> removed;
    opt.log = [&removed](const std::string& line) {
        if (line.find("removed the spill folder") != std::string::npos) removed.push_back(line);
    };
    const CompileStats stats = compileStore(opt);
    EXPECT_EQ(stats.place_labels, 1u);
    ::close(lock_fd);

    std::vector<std::string> left;
    for (const auto& e : fs::directory_iterator(spill)) left.push_back(e.path().filename().string());
    std::sort(left.begin(), left.end());
    EXPECT_EQ(left, (std::vector<std::string>{"navmap-spill-alive1", "navmap-spill-junk01", "navmap-spill-lockd1",
                                              "navmap-spill-noown1", "other-dead01"}));
    ASSERT_EQ(removed.size(), 3u);
    const std::string dead_line = "removed the spill folder " + (spill / "navmap-spill-dead01").string() +
                                  " of process " + std::to_string(dead) + ", which is gone (" +
                                  std::to_string((1 << 20) + std::to_string(dead).size() + 8 + boot.size()) + " bytes)";
    EXPECT_EQ(std::count_if(removed.begin(), removed.end(),
                            [&](const std::string& l) {
                                return l.size() >= dead_line.size() &&
                                       l.compare(l.size() - dead_line.size(), dead_line.size(), dead_line) == 0;
                            }),
              1)
        << removed[0] << "\n"
        << removed[1] << "\n"
        << removed[2];
}

// A live compile's folder: its owner file names this process and is locked, so another compile's
// clean-up leaves it; once it is gone, nothing is left.
TEST(CompileSpill, ALiveFolderIsKeptAndItsOwnerFileNamesItsProcess) {
    ScratchDir dir("compile-live-spill");
    fs::path made;
    {
        navmap::map::detail::SpillDir live(dir.path(), {});
        made = live.path();
        std::ifstream in(made / "owner");
        const std::string text{std::istreambuf_iterator<char>(in), {}};
        EXPECT_EQ(text, navmap::map::detail::SpillOwner::self().text());
        const auto owner = navmap::map::detail::SpillOwner::parse(text);
        ASSERT_TRUE(owner);
        EXPECT_EQ(owner->pid, ::getpid());
        EXPECT_TRUE(owner->mayBeAlive());
        EXPECT_EQ(navmap::map::detail::SpillDir::removeStale(dir.path(), {}), 0u);
        EXPECT_TRUE(fs::exists(made / "owner"));
    }
    EXPECT_FALSE(fs::exists(made));
    EXPECT_TRUE(fs::is_empty(dir.path()));
}

}  // namespace
