// SPDX-License-Identifier: Apache-2.0
// End to end: a route does not stop the map. navmapd renders the HUD (Mesa llvmpipe) for a
// vehicle standing in Andorra la Vella; a control client sets a valid route of 20,000 points (the
// most set_route takes) zig-zagging across the drawn area. Frames keep coming at about the rate
// they came without a route, the daemon's resident memory stays bounded, and clear_route gives
// that memory back (docs/rendering.md "Route", docs/ipc.md). The route's work is bounded by the
// tiles drawn, not by its points.
#include <gtest/gtest.h>

#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <sstream>
#include <string>
#include <thread>

#include <nlohmann/json.hpp>

#include "navmap/ipc/client/stream_client.h"
#include "navmap/ipc/control/control_client.h"
#include "navmapd_process.h"

namespace {

namespace fs = std::filesystem;
using namespace std::chrono_literals;
using nlohmann::json;

constexpr double kLat = 42.50770, kLon = 1.52190;  // writeStandingLog's vehicle

// set_route with `points` points zig-zagging east-west across a 2 km square around the vehicle,
// from its south edge to its north one: every segment crosses the drawn area.
std::string zigZagRoute(int points) {
    const double m_per_deg_lat = 111320.0;
    const double m_per_deg_lon = 111320.0 * std::cos(kLat * M_PI / 180.0);
    std::ostringstream out;
    out.precision(9);
    out << R"({"cmd":"set_route","id":"zigzag","points":[)";
    for (int i = 0; i < points; ++i) {
        const double x = i % 2 == 0 ? -1000.0 : 1000.0;
        const double y = -1000.0 + 2000.0 * i / (points - 1);
        out << (i ? "," : "") << "[" << kLat + y / m_per_deg_lat << "," << kLon + x / m_per_deg_lon << "]";
    }
    out << "]}";
    return out.str();
}

class RouteLoad : public ::testing::Test {
protected:
    void SetUp() override {
        m_dir = fs::temp_directory_path() / ("navmapd-route-load-" + std::to_string(::getpid()));
        fs::remove_all(m_dir);
        fs::create_directories(m_dir);
        navmap::test::writeStandingLog(m_dir / "standing.candump");
        m_daemon = std::make_unique<navmap::test::NavmapdProcess>(
            NAVMAPD_PATH,
            "--replay " + (m_dir / "standing.candump").string() + " --control-socket " +
                (m_dir / "control.sock").string() + " --frame-socket " + (m_dir / "frames.sock").string() +
                " --http-port 0 --profiles hud --no-labels --log-level info",
            m_dir / "navmapd.log", m_dir / "frames.sock");
        ASSERT_TRUE(fs::exists(m_dir / "frames.sock")) << m_daemon->output();
    }
    void TearDown() override {
        m_daemon.reset();
        fs::remove_all(m_dir);
    }
    // HUD frames received within `window`.
    int framesWithin(navmap::ipc::StreamClient& client, std::chrono::milliseconds window) {
        navmap::ipc::ReceivedFrame f;
        int n = 0;
        const auto until = std::chrono::steady_clock::now() + window;
        while (std::chrono::steady_clock::now() < until) {
            auto got = client.next(f, 50ms);
            if (!got) {
                ADD_FAILURE() << got.error().message << "\n" << m_daemon->output();
                return n;
            }
            if (got.value()) ++n;
        }
        return n;
    }
    // The daemon's resident memory, bytes, from get_status (published about once a second: asked
    // after a pause so that it is the memory of now).
    std::uint64_t rssBytes(navmap::ipc::ControlClient& control) {
        std::this_thread::sleep_for(1500ms);
        const auto reply = control.request(R"({"cmd":"get_status"})", 5s);
        if (!reply) {
            ADD_FAILURE() << reply.error().message;
            return 0;
        }
        const json st = json::parse(reply.value(), nullptr, false);
        if (!st.is_object() || !st.contains("status") || !st["status"].contains("memory")) {
            ADD_FAILURE() << reply.value().substr(0, 500);
            return 0;
        }
        return st["status"]["memory"]["rss_bytes"].get<std::uint64_t>();
    }

    fs::path m_dir;
    std::unique_ptr<navmap::test::NavmapdProcess> m_daemon;
};

TEST_F(RouteLoad, AZigZagRouteOfTwentyThousandPointsKeepsTheFramesAndClearRouteGivesTheMemoryBack) {
    navmap::ipc::StreamRequest request;
    request.profile = *navmap::ipc::defaultStreamProfile("hud");
    auto hud = navmap::ipc::StreamClient::connectUnix((m_dir / "frames.sock").string(), request);
    ASSERT_TRUE(hud) << hud.error().message;
    auto control = navmap::ipc::ControlClient::connect((m_dir / "control.sock").string());
    ASSERT_TRUE(control) << control.error().message;
    // The map loaded and drawn: frames coming.
    for (int i = 0; i < 60 && framesWithin(*hud.value(), 500ms) < 2; ++i) {}
    const int without = framesWithin(*hud.value(), 8s);
    ASSERT_GT(without, 8) << m_daemon->output();
    const std::uint64_t rss_without = rssBytes(control.value());

    const auto set = control.value().request(zigZagRoute(20000), 10s);
    ASSERT_TRUE(set) << set.error().message;
    ASSERT_NE(set.value().find("\"ok\":true"), std::string::npos) << set.value().substr(0, 300);
    ASSERT_NE(set.value().find("\"points\":20000"), std::string::npos) << set.value().substr(0, 300);
    // The frame that drapes the route onto the drawn tiles, then the rate with the route.
    (void)framesWithin(*hud.value(), 2s);
    const int with = framesWithin(*hud.value(), 8s);
    const std::uint64_t rss_with = rssBytes(control.value());
    EXPECT_GE(with, without / 3) << "frames in 8 s without the route " << without << ", with it " << with << "\n"
                                 << m_daemon->output();
    EXPECT_LT(rss_with, rss_without + (std::uint64_t{192} << 20))
        << "resident " << (rss_without >> 20) << " MiB without the route, " << (rss_with >> 20) << " MiB with it";

    const auto clear = control.value().request(R"({"cmd":"clear_route"})", 5s);
    ASSERT_TRUE(clear) << clear.error().message;
    ASSERT_NE(clear.value().find("\"ok\":true"), std::string::npos) << clear.value();
    const int cleared = framesWithin(*hud.value(), 4s);
    const std::uint64_t rss_cleared = rssBytes(control.value());
    EXPECT_GT(cleared, 2) << m_daemon->output();
    EXPECT_LT(rss_cleared, rss_without + (std::uint64_t{48} << 20))
        << "resident " << (rss_without >> 20) << " MiB before the route, " << (rss_with >> 20) << " MiB with it, "
        << (rss_cleared >> 20) << " MiB after clear_route";
    std::printf(
        "hud frames in 8 s: %d without the route, %d with 20,000 zig-zag points; resident MiB: %llu, %llu, "
        "%llu after clear_route\n",
        without, with, static_cast<unsigned long long>(rss_without >> 20),
        static_cast<unsigned long long>(rss_with >> 20), static_cast<unsigned long long>(rss_cleared >> 20));
}

}  // namespace
