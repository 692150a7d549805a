// SPDX-License-Identifier: Apache-2.0
// End to end: route guidance in navmapd. navmap-sim drives from Andorra la Vella towards Encamp
// and writes the drive as a candump log and the set_route line an HMI would send. navmapd replays
// the log; a control client sets a route that follows the drive through its first two
// manoeuvres and then turns away from it. Route progress passes both manoeuvres, then the
// vehicle, still on the simulated road, leaves the route: off_route arrives once, with the route
// id and the distance from the route (docs/guidance.md, docs/ipc.md). A display client watching
// the cluster stream meanwhile gets the guidance in each frame's metadata (the next manoeuvre,
// what is left of the route, the map-matched street) and, once the vehicle is off the route,
// frames marked off_route (docs/frame-protocol.md "Frame validity").
#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <string>
#include <thread>

#include <nlohmann/json.hpp>

#include "navmap/ipc/client/stream_client.h"
#include "navmap/ipc/control/control_client.h"
#include "navmapd_process.h"
#include "test_paths.h"

namespace {

namespace fs = std::filesystem;
using namespace std::chrono_literals;
using nlohmann::json;

// Metres between two [lat, lon] points (equirectangular: enough over a few kilometres).
double metres(const json& a, const json& b) {
    const double lat0 = a[0].get<double>() * M_PI / 180.0;
    const double dy = (b[0].get<double>() - a[0].get<double>()) * M_PI / 180.0 * 6371008.8;
    const double dx = (b[1].get<double>() - a[1].get<double>()) * M_PI / 180.0 * 6371008.8 * std::cos(lat0);
    return std::hypot(dx, dy);
}

// What a display client saw of the guidance in the frames' validity and metadata.
struct FrameGuidance {
    std::mutex mutex;
    int frames = 0;
    int with_next = 0;         // a next manoeuvre with a known type and a distance
    int with_remaining = 0;    // remaining distance and time
    int named_street = 0;      // the map-matched road's name
    int off_route = 0;         // frames flagged off_route
    int first_off_route = -1;  // frames received before the first flagged one
    std::string last_next_street;
};

void watchFrames(const fs::path& socket, const std::atomic<bool>& run, FrameGuidance* g) {
    navmap::ipc::StreamRequest request;
    request.profile = *navmap::ipc::defaultStreamProfile("cluster");
    request.meta = true;
    std::unique_ptr<navmap::ipc::StreamClient> client;
    navmap::ipc::ReceivedFrame f;
    while (run) {
        if (!client) {
            auto c = navmap::ipc::StreamClient::connectUnix(socket.string(), request, 2s);
            if (!c) {
                std::this_thread::sleep_for(100ms);
                continue;
            }
            client = std::move(c.value());
        }
        auto got = client->next(f, 200ms);
        if (!got) return;
        if (!got.value() || !f.meta) continue;
        std::lock_guard lock(g->mutex);
        ++g->frames;
        const auto& m = *f.meta;
        if (m.has_next && navmap::ipc::metaManeuverName(m.next_type) != nullptr && m.next_distance_m >= 0.0) {
            ++g->with_next;
            g->last_next_street = m.next_street;
        }
        g->with_remaining += m.has_remaining && m.remaining_m > 0.0 && m.remaining_s > 0.0 ? 1 : 0;
        g->named_street += m.current_street.empty() ? 0 : 1;
        if ((f.header.validity.flags & navmap::ipc::kValidityOffRoute) != 0) {
            if (g->off_route++ == 0) g->first_off_route = g->frames - 1;
        }
    }
}

TEST(NavmapdGuidance, ProgressPassesTwoManoeuvresThenLeavingTheRouteIsReported) {
    const fs::path store = navmap::test::binaryDir() / "andorra.navmap";
    ASSERT_TRUE(fs::exists(store)) << store << " (target navmap_default_store)";
    const fs::path dir = fs::temp_directory_path() / ("navmapd-guidance-" + std::to_string(::getpid()));
    fs::remove_all(dir);
    fs::create_directories(dir);
    const std::string sim = std::string(NAVMAP_SIM_PATH) + " -q --store " + store.string() + " --dbc " +
                            (navmap::test::dataDir() / "navmap.dbc").string() +
                            " --from andorra-la-vella --to encamp --duration 240 --standstill 1 --out " +
                            (dir / "drive.candump").string() + " --route-out " + (dir / "route.json").string();
    ASSERT_EQ(std::system(sim.c_str()), 0) << sim;

    std::ifstream in(dir / "route.json");
    json route = json::parse(in, nullptr, false);
    ASSERT_TRUE(route.is_object() && route.contains("points") && route.contains("maneuvers"))
        << route.dump().substr(0, 300);
    const json& points = route["points"];
    std::vector<double> measure(points.size(), 0.0);
    for (std::size_t i = 1; i < points.size(); ++i) measure[i] = measure[i - 1] + metres(points[i - 1], points[i]);
    // The first two manoeuvres after the departure.
    std::vector<std::size_t> turns;
    for (const json& m : route["maneuvers"]) {
        if (m["type"] != "depart" && m["type"] != "arrive" && turns.size() < 2)
            turns.push_back(m["index"].get<std::size_t>());
    }
    ASSERT_EQ(turns.size(), 2u) << route["maneuvers"].dump();
    const double second_m = measure[turns[1]];
    ASSERT_LT(second_m, 1500.0) << "the drive's second manoeuvre should come within the replayed minutes";
    // The route given to navmapd: the drive's own up to 150 m past the second manoeuvre, then
    // straight off to a point 1.5 km to the south of that place.
    std::size_t cut = turns[1];
    while (cut + 1 < points.size() && measure[cut] < second_m + 150.0) ++cut;
    json given = route;
    given["id"] = "e2e-guidance";
    given["points"] = json::array();
    for (std::size_t i = 0; i <= cut; ++i) given["points"].push_back(points[i]);
    given["points"].push_back(json::array({points[cut][0].get<double>() - 0.0135, points[cut][1].get<double>()}));
    given["maneuvers"] = json::array();
    for (const json& m : route["maneuvers"]) {
        if (m["index"].get<std::size_t>() <= cut && m["type"] != "arrive") given["maneuvers"].push_back(m);
    }

    const fs::path control_path = dir / "control.sock";
    navmap::test::NavmapdProcess daemon(
        NAVMAPD_PATH,
        "--noop --replay " + (dir / "drive.candump").string() + " --speed 4 --control-socket " + control_path.string() +
            " --frame-socket " + (dir / "frames.sock").string() + " --http-port 0 --log-level info",
        dir / "navmapd.log", control_path);
    auto control = navmap::ipc::ControlClient::connect(control_path.string());
    ASSERT_TRUE(control) << control.error().message << "\n" << daemon.output();
    const auto reply = control.value().request(given.dump());
    ASSERT_TRUE(reply) << reply.error().message;
    ASSERT_NE(reply.value().find("\"ok\":true"), std::string::npos) << reply.value();
    const auto sub = control.value().request(R"({"cmd":"subscribe"})");
    ASSERT_TRUE(sub) << sub.error().message;
    FrameGuidance seen;
    std::atomic<bool> watching{true};
    std::thread watcher(watchFrames, dir / "frames.sock", std::cref(watching), &seen);

    double driven_max = 0.0;
    int off_route = 0;
    json off_event;
    const auto until = std::chrono::steady_clock::now() + 150s;
    while (std::chrono::steady_clock::now() < until && off_route == 0) {
        const auto line = control.value().nextEvent(2s);
        if (!line) continue;
        const json e = json::parse(line.value(), nullptr, false);
        if (!e.is_object()) continue;
        if (e["event"] == "route_progress" && e["id"] == "e2e-guidance") {
            driven_max = std::max(driven_max, e["driven_m"].get<double>());
        } else if (e["event"] == "off_route") {
            ++off_route;
            off_event = e;
        }
    }
    // The frames rendered after the event carry the flag (4 s of replay at 4x: still off the route).
    std::this_thread::sleep_for(2s);
    watching = false;
    watcher.join();
    ASSERT_EQ(off_route, 1) << "driven " << driven_max << " m\n" << daemon.output();
    EXPECT_EQ(off_event["id"], "e2e-guidance");
    EXPECT_GT(off_event["offset_m"].get<double>(), 40.0) << off_event.dump();
    EXPECT_GT(driven_max, second_m) << "progress passed both manoeuvres before the vehicle left the route";
    EXPECT_NE(daemon.output().find("off the route"), std::string::npos) << daemon.output();
    // The same guidance, frame by frame, as a display reads it.
    EXPECT_GT(seen.frames, 20);
    EXPECT_GT(seen.with_next, 0) << "the next manoeuvre while on the route";
    EXPECT_FALSE(seen.last_next_street.empty()) << "the street it turns into";
    EXPECT_GT(seen.with_remaining, seen.frames / 2);
    EXPECT_GT(seen.named_street, 0) << "the map-matched road's name";
    EXPECT_GT(seen.off_route, 0) << "frames after leaving the route are flagged off_route";
    // The frames on the route before are not: the flag follows the guidance's state.
    EXPECT_GT(seen.first_off_route, 10);
    fs::remove_all(dir);
}

}  // namespace
