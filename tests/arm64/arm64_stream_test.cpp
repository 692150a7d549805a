// SPDX-License-Identifier: Apache-2.0
// The aarch64 navmapd (cross build, run under qemu-aarch64-static with the arm64 sysroot's Mesa)
// serves frames to this machine's navmap-view over the shared-memory frame socket, as a display
// process beside the daemon on an ECU would receive them. The recorded cluster frame of the
// standing vehicle matches the amd64 daemon's golden (tests/daemon/navmapd_e2e_test.cpp).
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <thread>
#include <vector>

#include "../daemon/navmapd_process.h"
#include "golden.h"
#include "navmap/render/image.h"

namespace {

namespace fs = std::filesystem;
using namespace std::chrono_literals;

// Output and exit status of a shell command.
std::pair<int, std::string> run(const std::string& cmd) {
    std::string out;
    FILE* p = ::popen((cmd + " 2>&1").c_str(), "r");
    if (!p) return {-1, "popen failed"};
    char buf[4096];
    std::size_t n = 0;
    while ((n = std::fread(buf, 1, sizeof buf, p)) > 0) out.append(buf, n);
    const int status = ::pclose(p);
    return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, out};
}

TEST(Arm64Stream, Arm64NavmapdServesTheAmd64ViewerAndTheClusterFrameMatchesItsGolden) {
    const fs::path cross = NAVMAP_ARM64_DIR;
    const fs::path navmapd = cross / "daemon" / "navmapd";
    const fs::path emulator = cross / "arm64-run";
    if (!fs::exists(navmapd) || !fs::exists(emulator)) {
        GTEST_SKIP() << "no arm64 build in " << cross
                     << " (the test arm64_build, scripts/cross-build.sh --daemon, makes it)";
    }
    const fs::path dir = fs::temp_directory_path() / ("navmap-arm64-stream-" + std::to_string(::getpid()));
    fs::remove_all(dir);
    fs::create_directories(dir / "frames");
    // Standing in Andorra la Vella for as long as the emulated start-up may take.
    navmap::test::writeStandingLog(dir / "standing.candump", {{42.50770, 1.52190}}, 600000);
    const fs::path socket = dir / "frames.sock";
    // Under emulation the first map frame (shaders compiled by LLVM inside qemu, tiles loaded) comes
    // well after the 5 s a client waits for it by default.
    std::ofstream(dir / "navmapd.toml") << "[stream]\nhandshake_timeout_s = 240\n";
    // As the amd64 end-to-end test runs it (its golden), labels off (they fade in with wall-clock time).
    navmap::test::NavmapdProcess daemon(emulator.string() + " " + navmapd.string(),
                                        "--config " + (dir / "navmapd.toml").string() + " --replay " +
                                            (dir / "standing.candump").string() + " --control-socket " +
                                            (dir / "control.sock").string() + " --frame-socket " + socket.string() +
                                            " --http-port 0 --profiles cluster --no-labels --log-level info",
                                        dir / "navmapd.log", socket);
    // Under emulation the start takes longer than the 10 s NavmapdProcess waits.
    for (int i = 0; i < 600 && !fs::exists(socket); ++i) std::this_thread::sleep_for(200ms);
    ASSERT_TRUE(fs::exists(socket)) << daemon.output();

    // navmap-view (amd64) records 60 s of cluster frames (the daemon sends them once the map is there).
    const auto [rc, view_out] =
        run(std::string(NAVMAP_VIEW_PATH) + " --unix " + socket.string() + " --profile cluster --duration 120 --save " +
            (dir / "frames").string() + " --json");
    std::printf("navmap-view: %s\n", view_out.c_str());
    EXPECT_EQ(rc, 0) << view_out << "\n" << daemon.output();
    EXPECT_NE(view_out.find("\"frames\":"), std::string::npos) << view_out;

    std::vector<fs::path> frames;
    for (const auto& e : fs::directory_iterator(dir / "frames")) frames.push_back(e.path());
    std::sort(frames.begin(), frames.end());  // frame_<seq>.png, seq zero-padded
    ASSERT_GE(frames.size(), 3u) << "too few frames from the arm64 navmapd\n" << view_out << "\n" << daemon.output();
    std::printf("arm64 navmapd: %zu cluster frames recorded, %s ... %s\n", frames.size(),
                frames.front().filename().c_str(), frames.back().filename().c_str());
    navmap::render::Image last;
    std::string error;
    ASSERT_TRUE(navmap::render::readImage(frames.back(), &last, &error)) << error;
    EXPECT_EQ(last.width, 1280);
    EXPECT_EQ(last.height, 480);
    EXPECT_GOLDEN(last, "daemon/golden/navmapd_cluster_standing.png", (navmap::test::GoldenTolerance{12, 0.02}));
    EXPECT_EQ(daemon.stop(), 0) << daemon.output();
    fs::remove_all(dir);
}

}  // namespace
