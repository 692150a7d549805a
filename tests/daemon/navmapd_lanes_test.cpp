// SPDX-License-Identifier: Apache-2.0
// End to end: lane guidance in navmapd on a real Andorra junction. The CG-2's climbing lane ends
// where way 456350884 (turn:lanes:forward "|merge_to_right") meets the next way of the road; a
// vehicle stands on that way before the junction and a control route leads on along the CG-2
// through it. The cluster's frames carry the two lanes in their metadata (the first to take, the
// second merging away: slight right on the wire) and draw the lane row at the top centre; with
// lane_guidance = false the row is gone and the metadata still has the lanes (docs/guidance.md
// "Lanes", docs/frame-protocol.md "Metadata block").
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "navmap/ipc/client/stream_client.h"
#include "navmap/ipc/control/control_client.h"
#include "navmap/map/road_graph.h"
#include "navmap/map/tile_store.h"
#include "navmapd_process.h"

namespace {

namespace fs = std::filesystem;
using namespace std::chrono_literals;
namespace map = navmap::map;
using json = nlohmann::json;

struct LaneRoute {
    json set_route;
    double stand_lat = 0, stand_lon = 0;
};

// The route: the tagged edge's shape up to the junction, then the edge leaving it closest to
// straight ahead; the vehicle stands on the tagged edge 2/3 of the way along its last piece.
std::optional<LaneRoute> laneRoute(const map::TileStore& store) {
    const map::RoadGraph g = store.loadGraph();
    const map::GraphEdge* tagged = nullptr;
    for (const map::GraphEdge& e : g.edges)
        if (e.way_id == 456350884 && g.nodes[e.to].osm_id == 4525945527 && !g.lanesOf(e).empty()) tagged = &e;
    if (tagged == nullptr) return std::nullopt;
    // Shape points in the direction of travel.
    const auto shapeOf = [&](const map::GraphEdge& e) {
        std::vector<map::LocalPoint> s(g.shape.begin() + e.shape_begin, g.shape.begin() + e.shape_end);
        if ((e.flags & map::edge_flags::kReversed) != 0) std::reverse(s.begin(), s.end());
        return s;
    };
    const auto in = shapeOf(*tagged);
    const double in_heading = std::atan2(in.back().x - in[in.size() - 2].x, in.back().y - in[in.size() - 2].y);
    const map::GraphEdge* out = nullptr;
    double best = 10.0;
    for (const map::GraphEdge& e : g.outEdges(tagged->to)) {
        if (e.to == tagged->from) continue;
        const auto s = shapeOf(e);
        const double d = std::abs(std::remainder(std::atan2(s[1].x - s[0].x, s[1].y - s[0].y) - in_heading, 2 * M_PI));
        if (d < best) {
            best = d;
            out = &e;
        }
    }
    if (out == nullptr) return std::nullopt;
    LaneRoute r;
    json points = json::array();
    const auto add = [&](map::LocalPoint p) {
        double lat = 0, lon = 0;
        store.projection().reverse({p.x, p.y}, lat, lon);
        points.push_back(json::array({lat, lon}));
    };
    for (const auto& p : in) add(p);
    const std::size_t junction = points.size() - 1;
    const auto after = shapeOf(*out);
    for (std::size_t i = 1; i < after.size(); ++i) add(after[i]);
    const map::LocalPoint a = in[in.size() - 2], b = in.back();
    store.projection().reverse({a.x + (b.x - a.x) * 2.0 / 3.0, a.y + (b.y - a.y) * 2.0 / 3.0}, r.stand_lat,
                               r.stand_lon);
    r.set_route = {{"cmd", "set_route"},
                   {"id", "lanes"},
                   {"points", points},
                   {"maneuvers", json::array({{{"index", 0}, {"type", "depart"}},
                                              {{"index", junction}, {"type", "straight"}, {"text", "CG-2"}},
                                              {{"index", points.size() - 1}, {"type", "arrive"}}})}};
    return r;
}

struct LaneFrames {
    int frames = 0, with_meta_lanes = 0, with_row = 0;
    std::vector<std::uint8_t> lanes;  ///< the last metadata lanes
    std::string output;
};

bool near(const std::uint8_t* p, int r, int g, int b) {
    return std::abs(p[0] - r) <= 8 && std::abs(p[1] - g) <= 8 && std::abs(p[2] - b) <= 8;
}

// The cluster's frames with the route set. The lane row of two lanes at 1280 x 480 (layout unit
// 1.6): boxes 54.4 x 64 px, 6.4 px apart, centred, their top 32 px below the top edge; the first
// box blue (the lane to take), the second dark.
LaneFrames clusterFrames(const fs::path& dir, const fs::path& store, const json& route, const std::string& extra) {
    LaneFrames out;
    fs::remove(dir / "frames.sock");
    fs::remove(dir / "control.sock");
    navmap::test::NavmapdProcess daemon(
        NAVMAPD_PATH,
        "--store " + store.string() + " --replay " + (dir / "standing.candump").string() + " --control-socket " +
            (dir / "control.sock").string() + " --frame-socket " + (dir / "frames.sock").string() +
            " --http-port 0 --profiles cluster --no-labels --log-level info" + extra,
        dir / "navmapd.log", dir / "frames.sock");
    auto control = navmap::ipc::ControlClient::connect((dir / "control.sock").string());
    if (!control) {
        out.output = control.error().message + "\n" + daemon.output();
        return out;
    }
    const auto reply = control.value().request(route.dump());
    EXPECT_TRUE(reply && reply.value().find("\"ok\":true") != std::string::npos)
        << (reply ? reply.value() : reply.error().message);
    navmap::ipc::StreamRequest request;
    request.profile = *navmap::ipc::defaultStreamProfile("cluster");
    request.meta = true;
    auto cluster = navmap::ipc::StreamClient::connectUnix((dir / "frames.sock").string(), request);
    if (!cluster) {
        out.output = cluster.error().message + "\n" + daemon.output();
        return out;
    }
    const double box_w = 54.4, gap = 6.4, left = 0.5 * (1280.0 - (2 * box_w + gap)), top = 32.0;
    navmap::ipc::ReceivedFrame f;
    const auto until = std::chrono::steady_clock::now() + 20s;
    while (std::chrono::steady_clock::now() < until && out.frames < 60) {
        auto got = cluster.value()->next(f, 200ms);
        if (!got) break;
        if (!got.value() || f.header.width != 1280u) continue;
        ++out.frames;
        if (f.meta && f.meta->lanes_known) {
            ++out.with_meta_lanes;
            out.lanes = f.meta->lanes;
        }
        const auto px = [&](double x, double y) {
            return &f.pixels[static_cast<std::size_t>(y) * f.header.stride + static_cast<std::size_t>(x) * 4];
        };
        if (near(px(left + 3, top + 3), 56, 107, 191) && near(px(left + box_w + gap + 3, top + 3), 41, 43, 51))
            ++out.with_row;
    }
    out.output = daemon.output();
    EXPECT_EQ(daemon.stop(), 0) << out.output;
    return out;
}

TEST(NavmapdLanes, TheClusterShowsTheLanesBeforeARealJunction) {
    const fs::path store_path = fs::path(NAVMAP_BINARY_DIR) / "andorra.navmap";
    ASSERT_TRUE(fs::exists(store_path)) << store_path << " (target navmap_default_store)";
    const auto route = laneRoute(*map::TileStore::open(store_path));
    ASSERT_TRUE(route) << "way 456350884's edge into node 4525945527 and a way on";
    navmap::test::ScratchDir dir("navmapd-lanes");
    navmap::test::writeStandingLog(dir.dir / "standing.candump", {{route->stand_lat, route->stand_lon}}, 20000);
    const LaneFrames shown = clusterFrames(dir.dir, store_path, route->set_route, "");
    ASSERT_GT(shown.frames, 20) << shown.output;
    std::printf("lanes: %d frames, %d with lanes in the metadata, %d with the row\n", shown.frames,
                shown.with_meta_lanes, shown.with_row);
    EXPECT_GE(shown.with_meta_lanes, 10) << shown.frames << " frames\n" << shown.output;
    EXPECT_EQ(shown.lanes, (std::vector<std::uint8_t>{navmap::ipc::kLaneRecommended, navmap::ipc::kLaneSlightRight}));
    EXPECT_GE(shown.with_row, 10) << shown.frames << " frames; the vehicle stands at " << route->stand_lat << ", "
                                  << route->stand_lon;
    // The profile can switch the row off; the metadata keeps the lanes.
    std::ofstream(dir.dir / "navmapd.toml") << "[[profile]]\nname = \"cluster\"\nlane_guidance = false\n";
    const LaneFrames off =
        clusterFrames(dir.dir, store_path, route->set_route, " --config " + (dir.dir / "navmapd.toml").string());
    ASSERT_GT(off.frames, 20) << off.output;
    EXPECT_EQ(off.with_row, 0);
    EXPECT_GE(off.with_meta_lanes, 10) << off.output;
}

}  // namespace
