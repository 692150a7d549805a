// SPDX-License-Identifier: Apache-2.0
// navmapd on files that lie or block (docs/architecture.md "Untrusted files", docs/tile-store.md
// "Sizes"): a store whose index or header claims sizes its bytes cannot hold, a replay log that is
// a FIFO, a config or a DBC that is /dev/zero. Each is one clear error (or, for the road graph, a
// warning and a running map), at once and with bounded memory, never a hang, a start-up that
// zero-fills gigabytes, or a read without end.
#include <gtest/gtest.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <unistd.h>
#include <zlib.h>

#include <chrono>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <string>
#include <thread>
#include <vector>

#include "navmap/map/tile_store.h"
#include "navmapd_process.h"
#include "test_paths.h"

namespace {

namespace fs = std::filesystem;
using namespace std::chrono_literals;

struct DaemonRun {
    int exit_code = -1;  ///< -1: killed at the deadline (it hung) or did not exit normally
    std::string output;
    long peak_mib = -1;  ///< the process's peak resident memory
};

/// navmapd with `args`, output into `log`; killed if still running after `deadline` (a guard
/// against a hang, not a measurement).
DaemonRun runNavmapd(const std::string& args, const fs::path& log, std::chrono::seconds deadline) {
    DaemonRun r;
    const std::string cmd = std::string("exec ") + NAVMAPD_PATH + " " + args + " > " + log.string() + " 2>&1";
    const char* argv[] = {"/bin/sh", "-c", cmd.c_str(), nullptr};
    pid_t pid = -1;
    if (posix_spawn(&pid, "/bin/sh", nullptr, nullptr, const_cast<char**>(argv), environ) != 0) return r;
    int status = 0;
    struct rusage ru {};
    const auto until = std::chrono::steady_clock::now() + deadline;
    pid_t done = 0;
    while ((done = ::wait4(pid, &status, WNOHANG, &ru)) == 0 && std::chrono::steady_clock::now() < until)
        std::this_thread::sleep_for(20ms);
    if (done == 0) {
        ::kill(pid, SIGKILL);
        ::wait4(pid, &status, 0, &ru);
    } else if (WIFEXITED(status)) {
        r.exit_code = WEXITSTATUS(status);
    }
    r.peak_mib = ru.ru_maxrss / 1024;
    std::ifstream in(log);
    r.output.assign(std::istreambuf_iterator<char>(in), {});
    return r;
}

std::string commonArgs(const fs::path& dir) {
    return "--noop --no-labels --profiles hud --http-port 0 --control-socket " + (dir / "control.sock").string() +
           " --frame-socket " + (dir / "frames.sock").string();
}

std::uint32_t crc32Of(const std::vector<char>& bytes, std::size_t at, std::size_t n) {
    return static_cast<std::uint32_t>(
        ::crc32(::crc32(0L, Z_NULL, 0), reinterpret_cast<const Bytef*>(bytes.data() + at), static_cast<uInt>(n)));
}

template <typename T>
void put(std::vector<char>& bytes, std::size_t at, T value) {
    std::memcpy(bytes.data() + at, &value, sizeof value);  // the store is little-endian, as this host
}

/// A copy of the default store with `edit` applied to its bytes, then the index and header
/// checksums made valid again (header layout: docs/tile-store.md "File format").
fs::path editedStore(const fs::path& dir, const std::string& name,
                     const std::function<void(std::vector<char>&, const navmap::map::StoreInfo&)>& edit) {
    const fs::path src = navmap::test::binaryDir() / "andorra.navmap";
    const auto info = navmap::map::TileStore::open(src)->info();
    std::ifstream in(src, std::ios::binary);
    std::vector<char> bytes{std::istreambuf_iterator<char>(in), {}};
    edit(bytes, info);
    put(bytes, 108, crc32Of(bytes, info.index_offset, std::size_t{info.tile_count} * 29));  // index CRC
    put(bytes, 140, crc32Of(bytes, 0, 140));                                                // header CRC
    const fs::path out = dir / name;
    std::ofstream(out, std::ios::binary).write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    return out;
}

}  // namespace

// Every index entry claims 256 MiB: start-up used to zero-fill 256 MiB per tile (135 s, SIGINT
// ignored, nothing logged). Now the index is refused as it is read.
TEST(NavmapdFiles, AStoreIndexClaimingMoreThanItsTilesCanHoldIsRefusedAtOnce) {
    navmap::test::ScratchDir s("navmapd-lying-index");
    const fs::path store =
        editedStore(s.dir, "index.navmap", [](std::vector<char>& b, const navmap::map::StoreInfo& i) {
            for (std::uint32_t k = 0; k < i.tile_count; ++k)
                put(b, i.index_offset + k * 29u + 21, std::uint32_t{256} << 20);
        });
    const DaemonRun r =
        runNavmapd("--store " + store.string() + " --run-for 5 " + commonArgs(s.dir), s.dir / "log", 120s);
    EXPECT_EQ(r.exit_code, 1) << r.output;
    EXPECT_NE(
        r.output.find("<3>navmapd: " + store.string() + ": index entry 0 (tile 0/0/0) declares 268435456 bytes from "),
        std::string::npos)
        << r.output;
    EXPECT_NE(r.output.find(" compressed, more than zlib's 1032:1 allows"), std::string::npos) << r.output;
    EXPECT_LT(r.peak_mib, 256) << r.output;
}

// The header claims a 4 GiB road graph: navmapd used to allocate it (4.1 GiB peak). Now the graph
// is refused on its sizes, said once, and the map renders without map matching.
TEST(NavmapdFiles, AGraphClaimingFourGibibytesIsRefusedWithoutAllocatingThem) {
    navmap::test::ScratchDir s("navmapd-lying-graph");
    std::uint64_t stored = 0;
    const fs::path store =
        editedStore(s.dir, "graph.navmap", [&](std::vector<char>& b, const navmap::map::StoreInfo& i) {
            stored = i.graph_stored_size;
            put(b, 128, std::uint64_t{4} << 30);
        });
    const DaemonRun r =
        runNavmapd("--store " + store.string() + " --run-for 2 " + commonArgs(s.dir), s.dir / "log", 120s);
    EXPECT_EQ(r.exit_code, 0) << r.output;
    EXPECT_NE(
        r.output.find("<4>navmapd: " + store.string() + ": road graph: declares 4294967296 bytes from " +
                      std::to_string(stored) + " compressed, more than zlib's 1032:1 allows; map matching is off"),
        std::string::npos)
        << r.output;
    EXPECT_LT(r.peak_mib, 1024) << r.output;
}

// A FIFO as the replay log used to block start-up until a writer came (SIGTERM ignored meanwhile);
// /dev/zero as the config hung --check-config; /dev/zero as a DBC was read to 2 GB.
TEST(NavmapdFiles, FilesThatAreNoRegularFilesAreOneClearErrorAtStart) {
    navmap::test::ScratchDir s("navmapd-not-regular");
    const fs::path fifo = s.dir / "drive.candump";
    ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
    DaemonRun r =
        runNavmapd("--replay " + fifo.string() + " --run-for 5 " + commonArgs(s.dir), s.dir / "replay.log", 60s);
    EXPECT_EQ(r.exit_code, 1) << r.output;
    EXPECT_NE(r.output.find("<3>navmapd: " + fifo.string() + ": is a FIFO, not a regular file (candump log)"),
              std::string::npos)
        << r.output;

    r = runNavmapd("--check-config --config /dev/zero", s.dir / "config.log", 60s);
    EXPECT_EQ(r.exit_code, 1) << r.output;
    EXPECT_EQ(r.output, "<3>navmapd: /dev/zero: is a character device, not a regular file (config file)\n");
    EXPECT_LT(r.peak_mib, 256);
    const fs::path config_fifo = s.dir / "navmapd.toml";
    ASSERT_EQ(::mkfifo(config_fifo.c_str(), 0600), 0);
    r = runNavmapd("--check-config --config " + config_fifo.string(), s.dir / "config-fifo.log", 60s);
    EXPECT_EQ(r.exit_code, 1) << r.output;
    EXPECT_EQ(r.output, "<3>navmapd: " + config_fifo.string() + ": is a FIFO, not a regular file (config file)\n");
    const fs::path huge = s.dir / "huge.toml";
    std::ofstream(huge).close();
    ASSERT_EQ(::truncate(huge.c_str(), off_t{2} << 30), 0);  // sparse: no disk
    r = runNavmapd("--check-config --config " + huge.string(), s.dir / "config-huge.log", 60s);
    EXPECT_EQ(r.exit_code, 1) << r.output;
    EXPECT_EQ(r.output, "<3>navmapd: " + huge.string() + ": 2147483648 bytes, over the limit of 4 MiB (config file)\n");
    EXPECT_LT(r.peak_mib, 256);

    const fs::path config = s.dir / "dbc.toml";
    std::ofstream(config) << "[input]\ndbc = [\"/dev/zero\"]\n";
    r = runNavmapd("--config " + config.string() + " --run-for 5 " + commonArgs(s.dir), s.dir / "dbc.log", 60s);
    EXPECT_GT(r.exit_code, 0) << r.output;
    EXPECT_NE(r.output.find("/dev/zero: is a character device, not a regular file (DBC file)"), std::string::npos)
        << r.output;
    EXPECT_LT(r.peak_mib, 256) << r.output;
}
