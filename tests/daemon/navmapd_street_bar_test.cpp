// SPDX-License-Identifier: Apache-2.0
// End to end: the current street's bar in navmapd's cluster frames. A vehicle stands on an
// Andorra road whose way has a name and a ref; once the certain match has held that street for
// 2 s, the cluster profile's frames show the bar at the bottom centre: the dark panel with white
// text in it. street_bar = false leaves every frame without it (docs/navmapd.md "Street bar").
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <optional>
#include <string>

#include "navmap/ipc/client/stream_client.h"
#include "navmap/map/road_graph.h"
#include "navmap/map/tile_store.h"
#include "navmap/render/renderer.h"
#include "navmapd_process.h"

namespace {

namespace fs = std::filesystem;
using namespace std::chrono_literals;
namespace map = navmap::map;

struct StreetPoint {
    double lat = 0, lon = 0;
    std::string name, ref;
};

// The middle of a long first segment of a primary or secondary road, neither tunnel nor bridge,
// whose way has a name of 8 bytes or more and a ref, with no point of a road of another name
// within 30 m (a match there is certain).
std::optional<StreetPoint> namedRoad(const map::TileStore& store) {
    const map::RoadGraph g = store.loadGraph();
    const map::TileScheme& scheme = store.scheme();
    for (const map::GraphEdge& e : g.edges) {
        if (e.shape_end - e.shape_begin < 2 || (e.cls != map::RoadClass::Primary && e.cls != map::RoadClass::Secondary))
            continue;
        const map::LocalPoint a = g.shape[e.shape_begin], b = g.shape[e.shape_begin + 1];
        if (std::hypot(b.x - a.x, b.y - a.y) < 120.0) continue;
        const map::PlanarPoint mid{0.5 * (a.x + b.x), 0.5 * (a.y + b.y)};
        const auto id = scheme.tileAt(scheme.leafLevel(), mid);
        if (!id || !store.contains(*id)) continue;
        map::TileStore::LoadResult r;
        const auto tile = store.loadAlone(*id, r);
        if (!tile) continue;
        std::optional<StreetPoint> found;
        bool crowded = false;
        for (const map::Road& road : tile->roads) {
            const bool level = (road.flags & (map::road_flags::kTunnel | map::road_flags::kBridge)) == 0;
            if (road.osm_id == e.way_id && road.name.size() >= 8 && !road.ref.empty() && level)
                found = StreetPoint{0, 0, road.name, road.ref};
        }
        for (const map::Road& road : tile->roads) {
            if (!found || road.osm_id == e.way_id || road.name == found->name) continue;
            for (const map::LocalPoint& p : road.points) {
                const double dx = tile->origin_x + p.x - mid.x, dy = tile->origin_y + p.y - mid.y;
                crowded |= std::hypot(dx, dy) < 30.0;
            }
        }
        if (!found || crowded) continue;
        store.projection().reverse(mid, found->lat, found->lon);
        return found;
    }
    return std::nullopt;
}

struct BarFrames {
    int frames = 0, with_bar = 0;
    int first_bar_frame = -1;
    int text_bright = 0;                 ///< white text pixels in the bar of the last frame with it
    int map_bright = 0;                  ///< most pixels above the panel's darkness in its rows, in a frame without it
    std::string street = "no metadata";  ///< the current street of the last frame with the bar and metadata
    std::string output;
};

// Runs navmapd standing on the replayed log in `dir` with the cluster profile for `frames` frames
// (or 20 s), or until 30 frames had the bar. The bar of a 1280 x 480 frame (the layout's unit 1.6): its panel from
// about y 404 to 464, its text's line box from about 413 to 454, at least 160 px wide about x 640 for a text of 8 bytes
// or more. A frame has it when the panel's rows above and below the text are dark (every pixel of x 600..680 in rows
// 405..410 and 457..462: the panel at alpha 0.72 over the map is at most 92) and its text rows hold 100 white pixels or
// more.
BarFrames clusterFrames(const fs::path& dir, const fs::path& store, const std::string& extra_args, int frames) {
    BarFrames out;
    fs::remove(dir / "frames.sock");
    navmap::test::NavmapdProcess daemon(
        NAVMAPD_PATH,
        "--store " + store.string() + " --replay " + (dir / "standing.candump").string() + " --control-socket " +
            (dir / "control.sock").string() + " --frame-socket " + (dir / "frames.sock").string() +
            " --http-port 0 --profiles cluster --no-labels --log-level info" + extra_args,
        dir / "navmapd.log", dir / "frames.sock");
    navmap::ipc::StreamRequest request;
    request.profile = *navmap::ipc::defaultStreamProfile("cluster");
    request.meta = true;
    auto cluster = navmap::ipc::StreamClient::connectUnix((dir / "frames.sock").string(), request);
    if (!cluster) {
        out.output = cluster.error().message + "\n" + daemon.output();
        return out;
    }
    navmap::ipc::ReceivedFrame f;
    navmap::render::Image last(1280, 480);
    auto px = [&](int x, int y) { return &f.pixels[std::size_t(y) * f.header.stride + std::size_t(x) * 4]; };
    const auto until = std::chrono::steady_clock::now() + 20s;
    while (std::chrono::steady_clock::now() < until && out.frames < frames && out.with_bar < 30) {
        auto got = cluster.value()->next(f, 200ms);
        if (!got) break;
        if (!got.value() || f.header.width != 1280u || f.header.height != 480u) continue;
        ++out.frames;
        int not_dark = 0;
        for (const int y0 : {405, 457})
            for (int y = y0; y <= y0 + 5; ++y)
                for (int x = 600; x <= 680; ++x) {
                    const std::uint8_t* p = px(x, y);
                    not_dark += std::max({p[0], p[1], p[2]}) > 92;
                }
        int text_bright = 0;
        for (int y = 414; y <= 454; ++y)
            for (int x = 600; x <= 680; ++x) {
                const std::uint8_t* p = px(x, y);
                text_bright += std::min({p[0], p[1], p[2]}) >= 235;
            }
        out.map_bright = std::max(out.map_bright, not_dark);
        if (not_dark > 0 || text_bright < 100) continue;
        ++out.with_bar;
        if (out.first_bar_frame < 0) out.first_bar_frame = out.frames;
        out.text_bright = text_bright;
        // A frame taken from the ring after the notified one was overwritten has no metadata.
        if (f.meta) out.street = f.meta->current_street;
        for (int y = 0; y < 480; ++y) std::memcpy(&last.rgba[std::size_t(y) * 1280 * 4], px(0, y), 1280 * 4);
    }
    // NAVMAP_STREET_BAR_DUMP=<file.png> writes the last frame with the bar.
    if (const char* dump = std::getenv("NAVMAP_STREET_BAR_DUMP"); dump && out.with_bar > 0) {
        std::string error;
        if (!navmap::render::writePng(dump, last, &error)) ADD_FAILURE() << dump << ": " << error;
    }
    out.output = daemon.output();
    EXPECT_EQ(daemon.stop(), 0) << out.output;
    return out;
}

TEST(NavmapdStreetBar, TheClusterNamesTheStreetTheVehicleStandsOn) {
    const fs::path store_path = fs::path(NAVMAP_BINARY_DIR) / "andorra.navmap";
    ASSERT_TRUE(fs::exists(store_path)) << store_path << " (target navmap_default_store)";
    const auto street = namedRoad(*map::TileStore::open(store_path));
    ASSERT_TRUE(street) << "no named primary or secondary road with a ref in the store";
    navmap::test::ScratchDir dir("navmapd-street-bar");
    navmap::test::writeStandingLog(dir.dir / "standing.candump", {{street->lat, street->lon}}, 20000);
    const std::string where = "the vehicle stands at " + std::to_string(street->lat) + ", " +
                              std::to_string(street->lon) + " on " + street->name + " (" + street->ref + ")\n";
    const BarFrames shown = clusterFrames(dir.dir, store_path, "", 300);
    EXPECT_EQ(shown.with_bar, 30) << shown.frames << " frames, the first with the bar: " << shown.first_bar_frame
                                  << "; " << where << shown.output;
    EXPECT_GE(shown.text_bright, 100) << "white text in the bar; " << where;
    EXPECT_EQ(shown.street, street->name) << "the frames name the road the vehicle stands on";
    // The profile can switch it off: then the bottom of the frame is the map's.
    std::ofstream(dir.dir / "navmapd.toml") << "[[profile]]\nname = \"cluster\"\nstreet_bar = false\n";
    const BarFrames off = clusterFrames(dir.dir, store_path, " --config " + (dir.dir / "navmapd.toml").string(), 120);
    EXPECT_EQ(off.frames, 120) << off.output;
    EXPECT_EQ(off.with_bar, 0) << where << off.output;
    EXPECT_GT(off.map_bright, 100) << "the map there is not as dark as the panel: " << where;
}

}  // namespace
