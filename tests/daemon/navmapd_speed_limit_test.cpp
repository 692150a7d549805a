// SPDX-License-Identifier: Apache-2.0
// End to end: the speed limit sign in navmapd's cluster frames. A vehicle stands on an Andorra
// road whose limit the compiled store knows (the same in both directions, so it holds without a
// heading); the cluster profile's frames show the sign top right (docs/navmapd.md
// `speed_limit_sign`, docs/rendering.md "Speed limit sign").
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <optional>
#include <string>

#include "navmap/ipc/client/stream_client.h"
#include "navmap/map/road_graph.h"
#include "navmap/map/tile_store.h"
#include "navmapd_process.h"

namespace {

namespace fs = std::filesystem;
using namespace std::chrono_literals;
namespace map = navmap::map;

struct RoadPoint {
    double lat = 0, lon = 0;
    int limit_kmh = 0;
};

// The middle of a long first segment of a two-way primary or secondary road with one limit in
// both directions.
std::optional<RoadPoint> roadWithALimit(const map::TileStore& store) {
    const map::RoadGraph g = store.loadGraph();
    for (const map::GraphEdge& e : g.edges) {
        if (e.speed_limit_kmh == 0 || (e.flags & map::edge_flags::kReversed) != 0 || e.shape_end - e.shape_begin < 2 ||
            (e.cls != map::RoadClass::Primary && e.cls != map::RoadClass::Secondary))
            continue;
        bool twin = false;
        for (const map::GraphEdge& t : g.outEdges(e.to))
            twin |= t.to == e.from && t.way_id == e.way_id && t.speed_limit_kmh == e.speed_limit_kmh;
        const map::LocalPoint a = g.shape[e.shape_begin], b = g.shape[e.shape_begin + 1];
        if (!twin || std::hypot(b.x - a.x, b.y - a.y) < 120.0) continue;
        RoadPoint p;
        store.projection().reverse({0.5 * (a.x + b.x), 0.5 * (a.y + b.y)}, p.lat, p.lon);
        p.limit_kmh = e.speed_limit_kmh;
        return p;
    }
    return std::nullopt;
}

bool red(const navmap::ipc::ReceivedFrame& f, double x, double y) {
    const std::uint8_t* p = &f.pixels[static_cast<std::size_t>(y) * f.header.stride + static_cast<std::size_t>(x) * 4];
    return p[0] >= 170 && p[1] <= 60 && p[2] <= 60;
}

struct SignFrames {
    int frames = 0, with_sign = 0, partial = 0;
    int digits_dark = 0;  ///< dark pixels in the middle of the last frame with the sign
    std::string output;
};

// Runs navmapd standing on the replayed log in `dir` with the cluster profile and counts its
// frames with the sign. The sign of a 1280 x 480 frame (the layout's unit 1.6): 115 px across,
// its centre 80 px from the top and the right edge, the ring between radii 38 and 58 px.
SignFrames clusterFrames(const fs::path& dir, const fs::path& store, const std::string& extra_args) {
    SignFrames out;
    fs::remove(dir / "frames.sock");
    navmap::test::NavmapdProcess daemon(
        NAVMAPD_PATH,
        "--store " + store.string() + " --replay " + (dir / "standing.candump").string() + " --control-socket " +
            (dir / "control.sock").string() + " --frame-socket " + (dir / "frames.sock").string() +
            " --http-port 0 --profiles cluster --no-labels --log-level info" + extra_args,
        dir / "navmapd.log", dir / "frames.sock");
    navmap::ipc::StreamRequest request;
    request.profile = *navmap::ipc::defaultStreamProfile("cluster");
    auto cluster = navmap::ipc::StreamClient::connectUnix((dir / "frames.sock").string(), request);
    if (!cluster) {
        out.output = cluster.error().message + "\n" + daemon.output();
        return out;
    }
    const double cx = 1280.0 - 80.0, cy = 80.0, ring = 48.0;
    navmap::ipc::ReceivedFrame f;
    const auto until = std::chrono::steady_clock::now() + 20s;
    while (std::chrono::steady_clock::now() < until && out.with_sign < 3 && out.frames < 90) {
        auto got = cluster.value()->next(f, 200ms);
        if (!got) break;
        if (!got.value() || f.header.width != 1280u) continue;
        ++out.frames;
        int ring_red = 0;
        for (int k = 0; k < 48; ++k) {
            const double a = 6.283185307 * k / 48;
            ring_red += red(f, cx + ring * std::cos(a), cy + ring * std::sin(a));
        }
        if (ring_red == 0) continue;
        if (ring_red < 48) {
            ++out.partial;
            continue;
        }
        ++out.with_sign;
        out.digits_dark = 0;
        for (int y = -20; y <= 20; ++y)
            for (int x = -20; x <= 20; ++x) {
                const std::uint8_t* p = &f.pixels[static_cast<std::size_t>(cy + y) * f.header.stride +
                                                  static_cast<std::size_t>(cx + x) * 4];
                out.digits_dark += p[0] <= 60 && p[1] <= 60 && p[2] <= 60;
            }
    }
    out.output = daemon.output();
    EXPECT_EQ(daemon.stop(), 0) << out.output;
    return out;
}

TEST(NavmapdSpeedLimit, TheClusterShowsTheLimitOfTheRoadTheVehicleStandsOn) {
    const fs::path store_path = fs::path(NAVMAP_BINARY_DIR) / "andorra.navmap";
    ASSERT_TRUE(fs::exists(store_path)) << store_path << " (target navmap_default_store)";
    const auto road = roadWithALimit(*map::TileStore::open(store_path));
    ASSERT_TRUE(road) << "no two-way road with one limit in the store";
    navmap::test::ScratchDir dir("navmapd-speed-limit");
    navmap::test::writeStandingLog(dir.dir / "standing.candump", {{road->lat, road->lon}}, 20000);
    const SignFrames shown = clusterFrames(dir.dir, store_path, "");
    EXPECT_EQ(shown.partial, 0) << "a frame has the whole sign or none of it";
    EXPECT_GE(shown.with_sign, 3) << shown.frames << " frames; the vehicle stands at " << road->lat << ", " << road->lon
                                  << " (" << road->limit_kmh << " km/h)\n"
                                  << shown.output;
    EXPECT_GE(shown.digits_dark, 100) << "the " << road->limit_kmh << " in black";
    // The profile can switch it off.
    std::ofstream(dir.dir / "navmapd.toml") << "[[profile]]\nname = \"cluster\"\nspeed_limit_sign = \"off\"\n";
    const SignFrames off = clusterFrames(dir.dir, store_path, " --config " + (dir.dir / "navmapd.toml").string());
    EXPECT_EQ(off.frames, 90) << off.output;
    EXPECT_EQ(off.with_sign + off.partial, 0) << off.output;
}

}  // namespace
