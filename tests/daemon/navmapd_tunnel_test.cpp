// SPDX-License-Identifier: Apache-2.0
// End to end: a drive through an Andorra road tunnel with GNSS dropped (docs/navmapd.md
// "Tunnels"). The test finds a tunnel in the compiled store's road graph, writes a candump log
// that drives along the road into it at 20 m/s with positions until 30 m before the portal and
// speed only after, and a route along the same road. navmapd replays it; the cluster stream's
// frames show the marker moving on along the tunnel's shape (the pose in each frame's
// metadata), not stale, the view dimmed to the night style, and the route drawn on the surface
// above; get_status gives the reason "tunnel".
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
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

// The road driven: the edge into a tunnel, the tunnel, the edge out of it (store frame).
struct TunnelDrive {
    std::vector<map::PlanarPoint> points;
    std::vector<double> measures;
    double tunnel_from = 0.0, tunnel_to = 0.0;
    std::int64_t way_id = 0;
};

std::vector<map::PlanarPoint> edgeShape(const map::RoadGraph& g, const map::GraphEdge& e) {
    std::vector<map::PlanarPoint> out;
    for (std::uint32_t k = e.shape_begin; k < e.shape_end; ++k) out.push_back({g.shape[k].x, g.shape[k].y});
    if (e.flags & map::edge_flags::kReversed) std::reverse(out.begin(), out.end());
    return out;
}

double shapeLength(const std::vector<map::PlanarPoint>& s) {
    double m = 0.0;
    for (std::size_t i = 1; i < s.size(); ++i) m += std::hypot(s[i].x - s[i - 1].x, s[i].y - s[i - 1].y);
    return m;
}

bool drivable(const map::GraphEdge& e) { return e.cls < map::RoadClass::Pedestrian; }
bool uTurn(const map::GraphEdge& a, const map::GraphEdge& b) {
    return a.to == b.from && b.to == a.from && a.way_id == b.way_id;
}

// The edges before `edge` back to `metres` or more: each time the longest drivable road (not a
// tunnel) into the node that is not the U-turn of the edge after it. Empty when there is none.
std::vector<const map::GraphEdge*> roadIn(const map::RoadGraph& g, const map::GraphEdge& edge, double metres) {
    std::vector<const map::GraphEdge*> out;
    const map::GraphEdge* next = &edge;
    for (double m = 0.0; m < metres && out.size() < 20;) {
        const map::GraphEdge* best = nullptr;
        for (const map::GraphEdge& p : g.edges) {
            if (p.to != next->from || !drivable(p) || (p.flags & map::road_flags::kTunnel) || uTurn(p, *next)) continue;
            if (!best || shapeLength(edgeShape(g, p)) > shapeLength(edgeShape(g, *best))) best = &p;
        }
        if (!best) return {};
        out.insert(out.begin(), best);
        m += shapeLength(edgeShape(g, *best));
        next = best;
    }
    return out;
}

// The edges after `edge` on to `metres` or more, as roadIn.
std::vector<const map::GraphEdge*> roadOut(const map::RoadGraph& g, const map::GraphEdge& edge, double metres) {
    std::vector<const map::GraphEdge*> out;
    const map::GraphEdge* prev = &edge;
    for (double m = 0.0; m < metres && out.size() < 20;) {
        const map::GraphEdge* best = nullptr;
        for (const map::GraphEdge& s : g.outEdges(prev->to)) {
            if (!drivable(s) || (s.flags & map::road_flags::kTunnel) || uTurn(*prev, s)) continue;
            if (!best || shapeLength(edgeShape(g, s)) > shapeLength(edgeShape(g, *best))) best = &s;
        }
        if (!best) return {};
        out.push_back(best);
        m += shapeLength(edgeShape(g, *best));
        prev = best;
    }
    return out;
}

// The longest tunnel edge of 400..1300 m on a drivable road with roads of 200 m or more (no
// tunnels) into it and out of it, the last 100 m before it one edge of the graph.
std::optional<TunnelDrive> findTunnel(const map::RoadGraph& g) {
    std::optional<TunnelDrive> best;
    for (const map::GraphEdge& t : g.edges) {
        if (!(t.flags & map::road_flags::kTunnel) || !drivable(t) || t.shape_end < t.shape_begin + 2) continue;
        const double len = shapeLength(edgeShape(g, t));
        if (len < 400.0 || len > 1300.0 || (best && len <= best->tunnel_to - best->tunnel_from)) continue;
        std::vector<const map::GraphEdge*> edges = roadIn(g, t, 200.0);
        const std::vector<const map::GraphEdge*> after = roadOut(g, t, 200.0);
        // The last fix (30 m before the portal) on a road that leads straight into the tunnel.
        if (edges.empty() || after.empty() || shapeLength(edgeShape(g, *edges.back())) < 100.0) continue;
        const std::size_t tunnel_index = edges.size();
        edges.push_back(&t);
        edges.insert(edges.end(), after.begin(), after.end());
        TunnelDrive d;
        d.way_id = t.way_id;
        for (std::size_t i = 0; i < edges.size(); ++i) {
            if (i == tunnel_index) d.tunnel_from = d.measures.empty() ? 0.0 : d.measures.back();
            for (const auto& p : edgeShape(g, *edges[i])) {
                if (!d.points.empty() && std::hypot(p.x - d.points.back().x, p.y - d.points.back().y) < 1e-3) continue;
                d.measures.push_back(d.points.empty() ? 0.0
                                                      : d.measures.back() + std::hypot(p.x - d.points.back().x,
                                                                                       p.y - d.points.back().y));
                d.points.push_back(p);
            }
            if (i == tunnel_index) d.tunnel_to = d.measures.back();
        }
        best = d;
    }
    return best;
}

// The point `m` along the drive and its direction (degrees clockwise from north).
std::pair<map::PlanarPoint, double> along(const TunnelDrive& d, double m) {
    std::size_t i = 1;
    while (i + 1 < d.points.size() && d.measures[i] < m) ++i;
    const map::PlanarPoint a = d.points[i - 1], b = d.points[i];
    const double f = std::clamp((m - d.measures[i - 1]) / (d.measures[i] - d.measures[i - 1]), 0.0, 1.0);
    double h = std::atan2(b.x - a.x, b.y - a.y) * 180.0 / M_PI;
    return {{a.x + f * (b.x - a.x), a.y + f * (b.y - a.y)}, h < 0.0 ? h + 360.0 : h};
}

// Distance of p from the drive and how far along it p's nearest point lies.
std::pair<double, double> onDrive(const TunnelDrive& d, map::PlanarPoint p) {
    double best = 1e18, at = 0.0;
    for (std::size_t i = 0; i + 1 < d.points.size(); ++i) {
        const map::PlanarPoint a = d.points[i], b = d.points[i + 1];
        const double dx = b.x - a.x, dy = b.y - a.y, len2 = dx * dx + dy * dy;
        const double t = std::clamp(((p.x - a.x) * dx + (p.y - a.y) * dy) / len2, 0.0, 1.0);
        const double dist = std::hypot(p.x - a.x - t * dx, p.y - a.y - t * dy);
        if (dist < best) best = dist, at = d.measures[i] + t * std::sqrt(len2);
    }
    return {best, at};
}

// NAV_Position (10 Hz, until `gnss_until_m`) and NAV_Motion (50 Hz: course, speed, fix type 3,
// 0 without positions) of a drive at `speed_mps` from `from_m` to `to_m` (data/navmap.dbc).
void writeDriveLog(const fs::path& path, const map::TileStore& store, const TunnelDrive& d, double from_m,
                   double gnss_until_m, double to_m, double speed_mps) {
    std::ofstream out(path);
    char line[128];
    int counter = 0;
    for (int ms = 0;; ms += 20) {
        const double m = from_m + speed_mps * ms / 1000.0;
        if (m > to_m) break;
        const double t = 1618394400.0 + ms / 1000.0;
        const auto [p, heading] = along(d, m);
        const bool gnss = m < gnss_until_m;
        if (gnss && ms % 100 == 0) {
            double lat = 0.0, lon = 0.0;
            store.projection().reverse(p, lat, lon);
            const auto la = static_cast<std::uint32_t>(static_cast<std::int32_t>(std::lround(lat * 1e7)));
            const auto lo = static_cast<std::uint32_t>(static_cast<std::int32_t>(std::lround(lon * 1e7)));
            std::snprintf(line, sizeof line, "(%.6f) vcan0 6A0#%02X%02X%02X%02X%02X%02X%02X%02X\n", t, la & 0xff,
                          (la >> 8) & 0xff, (la >> 16) & 0xff, la >> 24, lo & 0xff, (lo >> 8) & 0xff, (lo >> 16) & 0xff,
                          lo >> 24);
            out << line;
        }
        const auto h = static_cast<std::uint16_t>(std::lround(heading * 100.0) % 36000);
        const auto v = static_cast<std::uint16_t>(std::lround(speed_mps * 3.6 * 100.0));
        const auto fix = static_cast<std::uint8_t>((gnss ? 3 : 0) | ((counter++ & 15) << 4));
        std::snprintf(line, sizeof line, "(%.6f) vcan0 6A1#%02X%02X%02X%02X%02X%02X%02X%02X\n", t + 0.001, h & 0xff,
                      h >> 8, v & 0xff, v >> 8, 0, 0, fix, gnss ? 9 : 0);
        out << line;
    }
}

double luminance(const navmap::ipc::ReceivedFrame& f) {
    double sum = 0.0;
    std::size_t n = 0;
    for (std::uint32_t y = 0; y < f.header.height; y += 4) {
        for (std::uint32_t x = 0; x < f.header.width; x += 4) {
            const std::uint8_t* p = &f.pixels[static_cast<std::size_t>(y) * f.header.stride + x * 4];
            sum += 0.2126 * p[0] + 0.7152 * p[1] + 0.0722 * p[2];
            ++n;
        }
    }
    return n ? sum / n : 0.0;
}

// Pixels of the route's fill in the night style (MapStyle::night().route_color 0.25, 0.65, 1.0).
int routePixels(const navmap::ipc::ReceivedFrame& f) {
    int n = 0;
    for (std::uint32_t y = 0; y < f.header.height; ++y) {
        for (std::uint32_t x = 0; x < f.header.width; ++x) {
            const std::uint8_t* p = &f.pixels[static_cast<std::size_t>(y) * f.header.stride + x * 4];
            n += std::abs(p[0] - 64) <= 16 && std::abs(p[1] - 166) <= 16 && p[2] >= 235 ? 1 : 0;
        }
    }
    return n;
}

TEST(NavmapdTunnel, GnssLostInAnAndorraTunnelTheMarkerFollowsItInTheNightStyle) {
    const fs::path store_path = fs::path(NAVMAP_BINARY_DIR) / "andorra.navmap";
    ASSERT_TRUE(fs::exists(store_path)) << store_path << " (target navmap_default_store)";
    const auto store = map::TileStore::open(store_path);
    const auto drive = findTunnel(store->loadGraph());
    ASSERT_TRUE(drive) << "no road tunnel of 400..1300 m with roads in and out in the store";
    const double tunnel_m = drive->tunnel_to - drive->tunnel_from;
    std::printf("[ measured ] tunnel of way %lld: %.0f m, from %.0f m along the drive\n",
                static_cast<long long>(drive->way_id), tunnel_m, drive->tunnel_from);
    navmap::test::ScratchDir dir("navmapd-tunnel");
    constexpr double kSpeed = 20.0;
    const double start_m = std::max(0.0, drive->tunnel_from - 140.0);
    const double end_m = drive->tunnel_to + 20.0;
    writeDriveLog(dir.dir / "drive.candump", *store, *drive, start_m, drive->tunnel_from - 30.0, end_m, kSpeed);
    const double log_s = (end_m - start_m) / kSpeed;

    const fs::path control_path = dir.dir / "control.sock";
    navmap::test::NavmapdProcess daemon(
        NAVMAPD_PATH,
        "--store " + store_path.string() + " --replay " + (dir.dir / "drive.candump").string() + " --control-socket " +
            control_path.string() + " --frame-socket " + (dir.dir / "frames.sock").string() +
            " --http-port 0 --profiles cluster --log-level info",
        dir.dir / "navmapd.log", control_path);
    auto control = navmap::ipc::ControlClient::connect(control_path.string());
    ASSERT_TRUE(control) << control.error().message << "\n" << daemon.output();
    nlohmann::json route = {{"cmd", "set_route"}, {"id", "tunnel"}, {"points", nlohmann::json::array()}};
    for (const auto& p : drive->points) {
        double lat = 0.0, lon = 0.0;
        store->projection().reverse(p, lat, lon);
        route["points"].push_back({lat, lon});
    }
    const auto reply = control.value().request(route.dump());
    ASSERT_TRUE(reply) << reply.error().message;
    ASSERT_NE(reply.value().find("\"ok\":true"), std::string::npos) << reply.value();

    navmap::ipc::StreamRequest request;
    request.profile = *navmap::ipc::defaultStreamProfile("cluster");
    request.meta = true;
    auto cluster = navmap::ipc::StreamClient::connectUnix((dir.dir / "frames.sock").string(), request, 10s);
    ASSERT_TRUE(cluster) << cluster.error().message << "\n" << daemon.output();
    // The frames until the log ends (it loops then), each classified by where its pose lies.
    int before = 0, inside = 0, inside_stale = 0, off_shape = 0, backwards = 0, with_route = 0, dimmed_seen = 0;
    double lum_before = 0.0, lum_inside = 0.0, last_at = -1.0, first_at = 1e18, max_off = 0.0;
    bool tunnel_reason = false;
    navmap::ipc::ReceivedFrame f;
    const auto until = std::chrono::steady_clock::now() + std::chrono::duration<double>(log_s - 0.5);
    auto next_status = std::chrono::steady_clock::now();
    while (std::chrono::steady_clock::now() < until) {
        auto got = cluster.value()->next(f, 500ms);
        ASSERT_TRUE(got) << got.error().message;
        if (!got.value() || !f.meta || !f.meta->has_pose || f.header.width != 1280u) continue;
        const map::PlanarPoint p = store->projection().forward(f.meta->lat_deg, f.meta->lon_deg);
        const auto [off, at] = onDrive(*drive, p);
        if (at < drive->tunnel_from - 40.0 && at > start_m + 20.0) {
            ++before;
            lum_before += luminance(f);
        } else if (at > drive->tunnel_from + 100.0 && at < drive->tunnel_to - 20.0) {
            // 5 s or more into the tunnel: the fade to night (2 s) is over.
            ++inside;
            inside_stale += (f.header.validity.flags & navmap::ipc::kValidityStalePose) != 0 ? 1 : 0;
            max_off = std::max(max_off, off);
            off_shape += off > 3.0 ? 1 : 0;
            backwards += at < last_at - 0.5 ? 1 : 0;
            first_at = std::min(first_at, at);
            last_at = at;
            lum_inside += luminance(f);
            with_route += routePixels(f) > 300 ? 1 : 0;
            if (std::chrono::steady_clock::now() >= next_status) {
                next_status = std::chrono::steady_clock::now() + 1s;
                const auto st = control.value().request(R"({"cmd":"get_status"})");
                ASSERT_TRUE(st) << st.error().message;
                const auto j = nlohmann::json::parse(st.value(), nullptr, false);
                if (j.is_object() && j.contains("status") && j["status"].contains("style")) {
                    tunnel_reason = tunnel_reason || j["status"]["style"].value("reason", "") == "tunnel";
                    dimmed_seen += j["status"]["style"].value("night_weight", 0.0) == 1.0 ? 1 : 0;
                }
            }
        }
    }
    const std::string log = daemon.output();
    if (std::getenv("NAVMAP_TUNNEL_TEST_LOG"))
        std::printf("%s\n", log.c_str());  // the daemon's log, to look into a run
    std::printf(
        "[ measured ] %d frames before the tunnel, %d in it: %.0f m of it followed, at most %.2f m off its "
        "shape; luminance %.1f before, %.1f in it; %d with the route\n",
        before, inside, last_at - first_at, max_off, before ? lum_before / before : 0.0,
        inside ? lum_inside / inside : 0.0, with_route);
    ASSERT_GT(before, 5) << log;
    ASSERT_GT(inside, 10) << "the marker did not move on into the tunnel\n" << log;
    EXPECT_GT(last_at - first_at, 0.6 * (tunnel_m - 120.0)) << "the marker stopped in the tunnel";
    EXPECT_EQ(off_shape, 0) << "frames with the marker more than 3 m off the tunnel (at most " << max_off << " m)";
    EXPECT_EQ(backwards, 0) << "frames where the marker went back";
    EXPECT_EQ(inside_stale, 0) << "frames in the tunnel marked stale";
    EXPECT_LT(lum_inside / inside, 0.75 * (lum_before / before)) << "not dimmed to the night style";
    EXPECT_TRUE(tunnel_reason) << "get_status never said the style is night for the tunnel";
    EXPECT_GT(dimmed_seen, 0);
    EXPECT_GT(with_route, inside / 2) << "the route (dashed on the surface above the tunnel) is missing";
    EXPECT_EQ(daemon.stop(), 0) << log;
}

}  // namespace
