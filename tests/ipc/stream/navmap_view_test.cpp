// SPDX-License-Identifier: Apache-2.0
// navmap-view end to end: the test process serves frames, the real navmap-view binary connects
// over the Unix socket (shm) and TCP (zlib), saves PNGs and prints its statistics as JSON, and
// prints the statuses it gets before the first frame, and each frame's validity and metadata.

#include <gtest/gtest.h>

#include <atomic>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <memory>
#include <nlohmann/json.hpp>
#include <thread>

#include "navmap/ipc/client/frame_meta.h"
#include "navmap/ipc/stream/frame_server.h"
#include "navmap/render/image.h"
#include "stream_test_util.h"

using namespace navmap::ipc;
using namespace std::chrono_literals;

namespace {

std::string runCommand(const std::string& cmd, int* status) {
    std::string out;
    FILE* p = popen(cmd.c_str(), "r");
    if (p == nullptr) {
        *status = -1;
        return out;
    }
    char buf[4096];
    std::size_t n = 0;
    while ((n = fread(buf, 1, sizeof(buf), p)) > 0) {
        out.append(buf, n);
    }
    *status = pclose(p);
    return out;
}

}  // namespace

TEST(NavmapView, SavesPngsAndPrintsLatencyAndDrops) {
    FrameServerOptions o;
    o.unix_path = navmap::stream_test::uniqueSocketPath("view-test");
    o.tcp_port = 0;
    FrameServer server(o);
    ASSERT_TRUE(server.start().ok());
    navmap::stream_test::Publisher pub(server, "hud", 800, 240, 60);
    const auto dir = std::filesystem::temp_directory_path() / ("navmap-view-test-" + std::to_string(getpid()));
    std::filesystem::remove_all(dir);
    for (const bool tcp : {false, true}) {
        const std::string target =
            tcp ? "--tcp 127.0.0.1:" + std::to_string(server.tcpPort()) + " --payload zlib" : "--unix " + o.unix_path;
        const std::string cmd = std::string(NAVMAP_VIEW_EXE) + " " + target + " --profile hud --frames 6 --save " +
                                dir.string() + " --save-count 3 --json 2>&1";
        int status = 0;
        const std::string out = runCommand(cmd, &status);
        ASSERT_EQ(status, 0) << out;
        auto j = nlohmann::json::parse(out.substr(out.find('{')), nullptr, false);
        ASSERT_TRUE(j.is_object()) << out;
        EXPECT_EQ(j["frames"], 6);
        EXPECT_EQ(j["saved"], 3);
        EXPECT_GT(j["fps"].get<double>(), 10.0);
        EXPECT_EQ(j["source_latency_ms"]["samples"], 6);
        // The publisher stamps its frames with CAN data 2 ms old.
        EXPECT_GE(j["source_latency_ms"]["p50"].get<double>(), 2.0);
        EXPECT_LT(j["source_latency_ms"]["p99"].get<double>(), 1000.0);
        EXPECT_TRUE(j["dropped"].is_number());
    }
    pub.stop();
    int pngs = 0;
    for (const auto& e : std::filesystem::directory_iterator(dir)) {
        navmap::render::Image img;
        std::string err;
        ASSERT_TRUE(navmap::render::readImage(e.path(), &img, &err)) << err;
        EXPECT_EQ(img.width, 800);
        EXPECT_EQ(img.height, 240);
        // The publisher's frames are uniform (sequencePattern): a saved frame must be too.
        EXPECT_EQ(e.path().filename().string().rfind("frame_", 0), 0U);
        for (int y = 0; y < 240; y += 7) {
            for (int x = 0; x < 800; x += 13) {
                ASSERT_EQ(0, std::memcmp(img.pixel(x, y), img.pixel(0, 0), 4)) << e.path();
            }
        }
        EXPECT_EQ(img.pixel(0, 0)[3], 255);
        ++pngs;
    }
    EXPECT_GE(pngs, 3);  // 3 per run; the two runs may share sequence numbers
    std::filesystem::remove_all(dir);
}

TEST(NavmapView, ReportsConnectionAndUsageErrors) {
    int status = 0;
    std::string out = runCommand(std::string(NAVMAP_VIEW_EXE) + " --unix /nonexistent-navmap/x.sock 2>&1", &status);
    EXPECT_EQ(WEXITSTATUS(status), 1);
    EXPECT_NE(out.find("connect(/nonexistent-navmap/x.sock): No such file or directory"), std::string::npos) << out;
    out = runCommand(std::string(NAVMAP_VIEW_EXE) + " --frames 3 2>&1", &status);
    EXPECT_EQ(WEXITSTATUS(status), 2);
    EXPECT_NE(out.find("give exactly one of"), std::string::npos) << out;
}

TEST(NavmapView, PrintsEachStatusBeforeTheFrames) {
    FrameServerOptions o;
    o.unix_path = navmap::stream_test::uniqueSocketPath("view-status-test");
    FrameServer server(o);
    ASSERT_TRUE(server.start().ok());
    const std::string loading = R"({"state":"loading","view":"hud","tiles_wanted":7,"held_back":4,"waited_ms":300})";
    // The "daemon": once navmap-view has its stream, two statuses, then frames.
    std::atomic<bool> run{true};
    std::thread daemon([&] {
        const auto until = std::chrono::steady_clock::now() + 10s;
        while (run && server.stats().clients == 0 && std::chrono::steady_clock::now() < until) {
            std::this_thread::sleep_for(5ms);
        }
        for (int i = 0; i < 2 && run; ++i) {
            ASSERT_TRUE(server.publishStatus("hud", 800, 240, loading).ok());
            while (run && server.stats().statuses_sent < static_cast<std::uint64_t>(i + 1) &&
                   std::chrono::steady_clock::now() < until) {
                std::this_thread::sleep_for(5ms);
            }
        }
        const auto px = navmap::stream_test::sequencePattern(800, 240, 1);
        for (std::uint64_t seq = 1; run && std::chrono::steady_clock::now() < until; ++seq) {
            FrameView f;
            f.pixels = px.data();
            f.width = 800;
            f.height = 240;
            server.publish("hud", f);
            std::this_thread::sleep_for(20ms);
        }
    });
    int status = 0;
    const std::string out =
        runCommand(std::string(NAVMAP_VIEW_EXE) + " --unix " + o.unix_path + " --profile hud --frames 2", &status);
    run = false;
    daemon.join();
    ASSERT_EQ(status, 0) << out;
    const std::string line = "status: " + loading + "\n";
    const auto first = out.find(line);
    ASSERT_NE(first, std::string::npos) << out;
    EXPECT_NE(out.find(line, first + line.size()), std::string::npos) << "two statuses: " << out;
    EXPECT_GT(out.find("frames 2 "), first) << out;
}

TEST(NavmapView, PrintsEachFramesMetadataAndCountsValidity) {
    FrameServerOptions o;
    o.unix_path = navmap::stream_test::uniqueSocketPath("view-meta-test");
    o.tcp_port = 0;
    FrameServer server(o);
    ASSERT_TRUE(server.start().ok());
    // The "daemon": frames alternately fresh and stale+off route, each with its block.
    FrameMeta m;
    m.has_pose = true;
    m.lat_deg = 42.5;
    m.lon_deg = 1.5;
    m.heading_deg = 90.0;
    m.pose_time_ns = 1764691200000000000LL;
    m.has_next = true;
    m.next_type = 3;  // turn_left
    m.next_distance_m = 120.0;
    m.next_street = "Carrer Major";
    m.has_remaining = true;
    m.remaining_m = 2500.0;
    m.remaining_s = 300.0;
    m.current_street = "Avinguda Meritxell";
    const auto block = std::make_shared<const std::vector<std::uint8_t>>(encodeFrameMeta(m));
    std::atomic<bool> run{true};
    std::thread daemon([&] {
        const auto px = navmap::stream_test::sequencePattern(800, 240, 1);
        for (std::uint64_t seq = 1; run; ++seq) {
            FrameView f;
            f.pixels = px.data();
            f.width = 800;
            f.height = 240;
            f.validity.version = kFrameValidityVersion;
            f.validity.pose_age_ms = seq % 2 == 0 ? 40 : 1800;
            f.validity.flags = seq % 2 == 0 ? 0 : kValidityStalePose | kValidityOffRoute;
            f.meta = block;
            server.publish("hud", f);
            std::this_thread::sleep_for(10ms);
        }
    });
    for (const bool tcp : {false, true}) {
        const std::string target =
            tcp ? "--tcp 127.0.0.1:" + std::to_string(server.tcpPort()) : "--unix " + o.unix_path;
        int status = 0;
        const std::string out = runCommand(
            std::string(NAVMAP_VIEW_EXE) + " " + target + " --profile hud --fps 0 --frames 6 --meta --json 2>&1",
            &status);
        ASSERT_EQ(status, 0) << out;
        int lines = 0;
        long fresh = 0, stale = 0;
        for (std::size_t at = out.find("meta: "); at != std::string::npos; at = out.find("meta: ", at + 1)) {
            auto j = nlohmann::json::parse(out.substr(at + 6, out.find('\n', at) - at - 6), nullptr, false);
            ASSERT_TRUE(j.is_object()) << out;
            ++lines;
            const bool is_fresh = j["validity"] == "fresh";
            (is_fresh ? fresh : stale)++;
            EXPECT_EQ(j["pose_age_ms"], is_fresh ? 40 : 1800) << j.dump();
            EXPECT_EQ(j["validity"], is_fresh ? "fresh" : "stale_pose+off_route");
            EXPECT_EQ(j["pose"]["lat"], 42.5);
            EXPECT_EQ(j["pose"]["lon"], 1.5);
            EXPECT_EQ(j["pose"]["heading"], 90.0);
            EXPECT_EQ(j["pose"]["time_ns"], 1764691200000000000LL);
            EXPECT_EQ(j["next"]["type"], "turn_left");
            EXPECT_EQ(j["next"]["distance_m"], 120.0);
            EXPECT_EQ(j["next"]["street"], "Carrer Major");
            EXPECT_EQ(j["next"]["lanes"], "unknown");
            EXPECT_EQ(j["remaining"]["m"], 2500.0);
            EXPECT_EQ(j["remaining"]["s"], 300.0);
            EXPECT_EQ(j["street"], "Avinguda Meritxell");
            EXPECT_EQ(j["speed_limit_kmh"], "unknown");
        }
        EXPECT_EQ(lines, 6) << out;
        // The summary counts the same frames by validity.
        auto summary = nlohmann::json::parse(out.substr(out.rfind("\n{") + 1), nullptr, false);
        ASSERT_TRUE(summary.is_object()) << out;
        EXPECT_EQ(summary["validity"]["fresh"], fresh);
        EXPECT_EQ(summary["validity"]["stale_pose"], stale);
        EXPECT_EQ(summary["validity"]["off_route"], stale);
        EXPECT_EQ(summary["validity"]["degraded"], 0);
        EXPECT_EQ(summary["validity"]["unknown"], 0);
    }
    run = false;
    daemon.join();
}
