// SPDX-License-Identifier: Apache-2.0
// navmap-sim as a program: writes a candump log identical to the library's frames, prints a
// summary, writes the set_route line, and fails with one clear line on bad input.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "navmap/ipc/control/control_protocol.h"
#include "navmap/sim/candump_writer.h"
#include "navmap/sim/drive_simulator.h"
#include "test_paths.h"

namespace navmap::sim {
namespace {

struct ProgramRun {
    int status = -1;
    std::string out;
};

ProgramRun run(const std::string& args) {
    const std::string cmd = std::string(NAVMAP_SIM_PATH) + " " + args + " 2>&1";
    ProgramRun r;
    FILE* p = ::popen(cmd.c_str(), "r");
    if (p == nullptr) return r;
    std::array<char, 4096> buf{};
    std::size_t n = 0;
    while ((n = std::fread(buf.data(), 1, buf.size(), p)) > 0) r.out.append(buf.data(), n);
    const int st = ::pclose(p);
    r.status = WIFEXITED(st) ? WEXITSTATUS(st) : -1;
    return r;
}

std::string slurp(const std::filesystem::path& p) {
    std::ifstream f(p);
    std::stringstream ss;
    ss << f.rdbuf();
    return ss.str();
}

class NavmapSimCli : public ::testing::Test {
protected:
    void SetUp() override {
        m_store = navmap::test::binaryDir() / "andorra.navmap";
        if (!std::filesystem::exists(m_store)) GTEST_SKIP() << "no compiled store at " << m_store;
        m_dir = std::filesystem::temp_directory_path() / ("navmap_sim_cli_" + std::to_string(::getpid()));
        std::filesystem::create_directories(m_dir);
    }
    void TearDown() override {
        std::error_code ec;
        if (!m_dir.empty()) std::filesystem::remove_all(m_dir, ec);
    }
    std::filesystem::path m_store, m_dir;
};

TEST_F(NavmapSimCli, WritesTheLibrarysFramesAndASummary) {
    const auto log = m_dir / "d.candump";
    const auto route = m_dir / "route.json";
    const ProgramRun r = run(
        "-q --store " + m_store.string() + " --from 'Andorra la Vella' --to 42.5097,1.5390 --out " + log.string() +
        " --noise-m 2 --dropouts 1 --bad-frames 2 --seed 7 --duration 60 --iface vcan0 --route-out " + route.string());
    ASSERT_EQ(r.status, 0) << r.out;
    EXPECT_NE(r.out.find("route: "), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("NAV_Motion 3001"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("bad: wrong DLC"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("log: " + log.string()), std::string::npos) << r.out;

    DriveRequest req;
    req.store = m_store;
    req.dbc = NAVMAP_IPC_DEFAULT_DBC;
    req.from = "Andorra la Vella";
    req.to = "42.5097,1.5390";
    req.frames.noise_m = 2;
    req.frames.dropouts = 1;
    req.frames.bad_bursts = 2;
    req.frames.seed = 7;
    req.frames.max_duration_s = 60;
    const DriveSimulator sim = DriveSimulator::create(req);
    std::string expected;
    for (const auto& f : sim.frames()) expected += formatCandumpLine(f, "vcan0") + "\n";
    EXPECT_EQ(slurp(log), expected);

    std::string line = slurp(route);
    ASSERT_FALSE(line.empty());
    EXPECT_EQ(line.back(), '\n');
    line.pop_back();
    const auto parsed = ipc::parseControlLine(line);
    EXPECT_TRUE(parsed.command.has_value()) << parsed.error;
}

TEST_F(NavmapSimCli, BadInputFailsWithOneClearLine) {
    ProgramRun r = run("--store " + m_store.string() + " --from Atlantis --to Encamp");
    EXPECT_EQ(r.status, 1);
    EXPECT_EQ(r.out.rfind("navmap-sim: --from: unknown place 'Atlantis'", 0), 0U) << r.out;
    r = run("--store " + m_store.string() + " --from Encamp --to Ordino --out /nonexistent-dir/x.candump");
    EXPECT_EQ(r.status, 1);
    EXPECT_NE(r.out.find("navmap-sim: fopen(/nonexistent-dir/x.candump.tmp): No such file or directory"),
              std::string::npos)
        << r.out;
    r = run("--store " + m_store.string() + " --from Encamp --to Ordino --control " + (m_dir / "no.sock").string());
    EXPECT_EQ(r.status, 1);
    EXPECT_NE(r.out.find("connect(" + (m_dir / "no.sock").string() + ")"), std::string::npos) << r.out;
    // Numbers out of range are usage errors (exit 2) naming the range, before anything runs.
    r = run("--store " + m_store.string() + " --from Encamp --to Ordino --position-hz 0");
    EXPECT_EQ(r.status, 2);
    EXPECT_NE(r.out.find("--position-hz: '0' is not a finite number in [1, 50]"), std::string::npos) << r.out;
    r = run("--from Encamp");
    EXPECT_EQ(r.status, 2) << r.out;
    EXPECT_NE(r.out.find("--to is required"), std::string::npos) << r.out;
}

}  // namespace
}  // namespace navmap::sim
