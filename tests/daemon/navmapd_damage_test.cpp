// SPDX-License-Identifier: Apache-2.0
// navmapd on damaged input (docs/tile-store.md "Damage", docs/can-input.md): a store whose road
// graph has a flipped bit still starts and renders, without map matching and without the
// simulator's route, and says so in status; a replay file that is no candump log (/dev/zero) is
// one clear error at start, not gigabytes read into memory.
#include <gtest/gtest.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <thread>

#include <nlohmann/json.hpp>

#include "navmap/ipc/client/stream_client.h"
#include "navmap/ipc/control/control_client.h"
#include "navmap/map/tile_store.h"
#include "navmapd_process.h"
#include "test_paths.h"

namespace {

namespace fs = std::filesystem;
using namespace std::chrono_literals;

/// A copy of the default store with one bit of its road graph flipped.
fs::path storeWithDamagedGraph(const fs::path& dir) {
    const fs::path src = navmap::test::binaryDir() / "andorra.navmap";
    fs::path out = dir / "damaged-graph.navmap";
    fs::copy_file(src, out);
    const auto info = navmap::map::TileStore::open(src)->info();
    std::fstream f(out, std::ios::in | std::ios::out | std::ios::binary);
    const auto at = static_cast<std::streamoff>(info.graph_offset + info.graph_stored_size / 2);
    f.seekg(at);
    char c = 0;
    f.get(c);
    f.seekp(at);
    f.put(static_cast<char>(c ^ 0x01));
    return out;
}

/// get_status's "status" object, once the daemon has published one with `key`.
nlohmann::json statusWith(const fs::path& socket, const char* key) {
    auto control = navmap::ipc::ControlClient::connect(socket.string());
    if (!control) return {};
    for (int i = 0; i < 60; ++i) {
        auto reply = control.value().request(R"({"cmd":"get_status"})");
        if (!reply) return {};
        const auto j = nlohmann::json::parse(reply.value(), nullptr, false);
        if (j.contains("status") && j["status"].contains(key)) return j["status"];
        std::this_thread::sleep_for(100ms);
    }
    return {};
}

std::string daemonArgs(const fs::path& dir, const fs::path& store) {
    return "--store " + store.string() + " --noop --no-labels --profiles hud --http-port 0 --log-level info" +
           " --control-socket " + (dir / "control.sock").string() + " --frame-socket " + (dir / "frames.sock").string();
}

/// Frames keep coming on the hud stream: the map renders.
int framesWithin(const fs::path& frame_socket, std::chrono::milliseconds window) {
    navmap::ipc::StreamRequest request;
    request.profile = *navmap::ipc::defaultStreamProfile("hud");
    auto client = navmap::ipc::StreamClient::connectUnix(frame_socket.string(), request);
    if (!client) return -1;
    navmap::ipc::ReceivedFrame f;
    int frames = 0;
    const auto until = std::chrono::steady_clock::now() + window;
    while (std::chrono::steady_clock::now() < until) {
        auto got = client.value()->next(f, 50ms);
        if (!got) return -1;
        frames += got.value() ? 1 : 0;
    }
    return frames;
}

TEST(NavmapdDamage, ADamagedRoadGraphLeavesTheSimulatedDriveOutAndTheMapRendering) {
    navmap::test::ScratchDir s("navmapd-graph-sim");
    const fs::path store = storeWithDamagedGraph(s.dir);
    navmap::test::NavmapdProcess d(NAVMAPD_PATH, daemonArgs(s.dir, store), s.dir / "navmapd.log",
                                   s.dir / "frames.sock");
    ASSERT_TRUE(fs::exists(s.dir / "frames.sock")) << d.output();

    const auto st = statusWith(s.dir / "control.sock", "road_graph");
    ASSERT_TRUE(st.is_object()) << d.output();
    EXPECT_EQ(st["road_graph"], "unavailable: checksum mismatch");
    EXPECT_EQ(st["input"]["source"], "sim andorra-la-vella -> encamp");
    EXPECT_EQ(st["input"]["error"], "the simulator cannot plan a route: road graph unavailable: checksum mismatch");
    EXPECT_EQ(st["position"]["valid"], false);
    EXPECT_GT(framesWithin(s.dir / "frames.sock", 1500ms), 0) << d.output();

    const std::string out = d.output();
    EXPECT_NE(out.find("<4>navmapd: " + store.string() +
                       ": road graph: checksum mismatch; map matching is off (the pose is the raw fix) and the "
                       "simulator cannot plan a route"),
              std::string::npos)
        << out;
    EXPECT_EQ(d.stop(), 0) << out;
}

TEST(NavmapdDamage, ADamagedRoadGraphTurnsMapMatchingOffForAReplay) {
    navmap::test::ScratchDir s("navmapd-graph-replay");
    const fs::path store = storeWithDamagedGraph(s.dir);
    navmap::test::writeStandingLog(s.dir / "standing.candump");
    navmap::test::NavmapdProcess d(NAVMAPD_PATH,
                                   daemonArgs(s.dir, store) + " --replay " + (s.dir / "standing.candump").string(),
                                   s.dir / "navmapd.log", s.dir / "frames.sock");
    ASSERT_TRUE(fs::exists(s.dir / "frames.sock")) << d.output();
    nlohmann::json st;
    for (int i = 0; i < 30; ++i) {  // the first fixes arrive within a second
        st = statusWith(s.dir / "control.sock", "road_graph");
        if (st.is_object() && st["position"]["valid"] == true) break;
        std::this_thread::sleep_for(200ms);
    }
    ASSERT_TRUE(st.is_object()) << d.output();
    EXPECT_EQ(st["road_graph"], "unavailable: checksum mismatch");
    EXPECT_EQ(st["input"]["error"], "");
    EXPECT_EQ(st["position"]["valid"], true) << st.dump();
    EXPECT_EQ(st["position"]["match_confidence"], 0.0) << "no graph to match: the pose is the raw fix";
    EXPECT_GT(framesWithin(s.dir / "frames.sock", 1000ms), 0) << d.output();
    EXPECT_EQ(d.stop(), 0) << d.output();
}

TEST(NavmapdDamage, ReplayingDevZeroIsOneClearErrorAtStart) {
    navmap::test::ScratchDir s("navmapd-devzero");
    const auto t0 = std::chrono::steady_clock::now();
    const std::string cmd =
        std::string(NAVMAPD_PATH) + " --replay /dev/zero --noop --run-for 5 --http-port 0 --control-socket " +
        (s.dir / "control.sock").string() + " --frame-socket " + (s.dir / "frames.sock").string() + " 2>&1";
    FILE* p = ::popen(cmd.c_str(), "r");
    ASSERT_NE(p, nullptr);
    std::string out;
    char buf[512];
    while (std::fgets(buf, sizeof buf, p)) out += buf;
    const int status = ::pclose(p);
    const auto elapsed = std::chrono::steady_clock::now() - t0;
    EXPECT_EQ(WIFEXITED(status) ? WEXITSTATUS(status) : -1, 1) << out;
    EXPECT_NE(out.find("<3>navmapd: /dev/zero: is a character device, not a regular file (candump log)"),
              std::string::npos)
        << out;
    EXPECT_LT(elapsed, 4s) << "refused at start, not read until --run-for";
}

}  // namespace
