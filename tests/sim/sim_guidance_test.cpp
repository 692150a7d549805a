// SPDX-License-Identifier: Apache-2.0
// Guidance on the compiled Andorra store: the default drive's manoeuvres (street names from the
// tiles, a real roundabout's exit number), the set_route line carrying them through the control
// protocol parser, and progress along the drive.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <memory>

#include "navmap/ipc/control/control_protocol.h"
#include "navmap/map/guidance/guidance_route.h"
#include "navmap/map/guidance/maneuver_derivation.h"
#include "navmap/map/guidance/route_progress_tracker.h"
#include "navmap/sim/drive_simulator.h"
#include "navmap/sim/route_message.h"
#include "test_paths.h"

namespace navmap::sim {
namespace {

std::filesystem::path storePath() { return navmap::test::binaryDir() / "andorra.navmap"; }

DriveSimulator defaultDrive() {
    DriveRequest r;
    r.store = storePath();
    r.dbc = NAVMAP_IPC_DEFAULT_DBC;
    r.from = "andorra-la-vella";  // navmapd's default simulated drive ([sim] from/to)
    r.to = "encamp";
    return DriveSimulator::create(r);
}

class SimGuidance : public ::testing::Test {
protected:
    void SetUp() override {
        if (!std::filesystem::exists(storePath()))
            GTEST_SKIP() << "no compiled store at " << storePath() << " (build navmap_default_store)";
    }
};

TEST(GuidanceProtocol, EveryGuidanceTypeIsAControlProtocolType) {
    for (std::size_t i = 0; i < map::guidance::kManeuverTypeCount; ++i) {
        const auto t = static_cast<map::guidance::ManeuverType>(i);
        const std::string name(map::guidance::maneuverTypeName(t));
        const auto parsed = ipc::maneuverTypeFromName(name);
        ASSERT_TRUE(parsed.has_value()) << name;
        EXPECT_EQ(ipc::maneuverTypeName(*parsed), name);
    }
}

TEST_F(SimGuidance, DefaultDriveManeuversCarryStreetNamesAndReachTheDaemonParser) {
    const DriveSimulator sim = defaultDrive();
    const DriveRoute& route = sim.route();
    ASSERT_GE(route.maneuvers.size(), 5U);
    EXPECT_EQ(route.maneuvers.front().type, "depart");
    EXPECT_EQ(route.maneuvers.back().type, "arrive");
    std::size_t named = 0, roundabouts = 0;
    for (const Maneuver& m : route.maneuvers) {
        named += m.text.empty() ? 0 : 1;
        if (m.type == "depart" || m.type == "arrive" || m.type == "keep_left" || m.type == "keep_right") continue;
        // Every junction manoeuvre's type is the turn class of its angle.
        if (m.type == "roundabout") {
            ++roundabouts;
            EXPECT_GE(m.exit, 1) << m.point;
            EXPECT_LE(m.exit, 8) << m.point;
        } else if (m.type != "straight") {
            EXPECT_EQ(m.type, map::guidance::maneuverTypeName(map::guidance::classifyTurn(m.turn_deg))) << m.point;
        }
    }
    // The default drive starts on Avinguda del Príncep Benlloch (the store's tiles name it).
    EXPECT_EQ(route.maneuvers.front().text, "Avinguda del Princep Benlloch");
    EXPECT_GT(named, route.maneuvers.size() / 2);
    // Andorra la Vella -> Encamp passes the roundabouts along the CG-1/CG-2 valley road.
    EXPECT_GE(roundabouts, 5U);
    const ipc::ControlParse parsed = ipc::parseControlLine(setRouteMessage(route, sim.projection(), "sim"));
    ASSERT_TRUE(parsed.command) << parsed.error;
    const auto& set = std::get<ipc::SetRouteCommand>(parsed.command->body);
    ASSERT_EQ(set.maneuvers.size(), route.maneuvers.size());
    for (std::size_t i = 0; i < set.maneuvers.size(); ++i) {
        EXPECT_EQ(set.maneuvers[i].index, route.maneuvers[i].point);
        EXPECT_EQ(ipc::maneuverTypeName(set.maneuvers[i].type), route.maneuvers[i].type);
        EXPECT_EQ(set.maneuvers[i].text, route.maneuvers[i].text);
        EXPECT_EQ(set.maneuvers[i].exit_number.value_or(0), static_cast<std::uint32_t>(route.maneuvers[i].exit));
    }
}

// The default drive passes no roundabout, so the store's roundabouts are driven through: from
// the far end of a way entering a ring to the far end of each exit, in ring order. The k-th
// exit reached around the ring must be announced as exit k.
TEST_F(SimGuidance, RealRoundaboutExitsAreNumberedInRingOrder) {
    const auto store = map::TileStore::open(storePath());
    const map::RoadGraph g = store->loadGraph();
    auto ring = [&](const map::GraphEdge& e) { return (e.flags & map::road_flags::kRoundabout) != 0; };
    auto drivable = [](const map::GraphEdge& e) { return e.cls < map::RoadClass::Pedestrian; };
    std::size_t rings_checked = 0, exits_checked = 0;
    std::vector<char> done(g.nodes.size(), 0);
    for (std::uint32_t entry = 0; entry < g.nodes.size() && rings_checked < 5; ++entry) {
        // An entry node: a ring node with a drivable non-ring way arriving (as an edge leaving its far end).
        if (done[entry]) continue;
        std::optional<std::uint32_t> ring_out;
        for (const auto& e : g.outEdges(entry))
            if (ring(e)) ring_out = e.to;
        if (!ring_out) continue;
        std::optional<std::uint32_t> approach;
        for (const auto& e : g.outEdges(entry)) {
            if (ring(e) || !drivable(e)) continue;
            for (const auto& back : g.outEdges(e.to))
                if (back.to == entry && back.way_id == e.way_id && drivable(back)) approach = e.to;
        }
        if (!approach) continue;
        // Walk the ring from the entry, listing the exits in order.
        std::vector<std::uint32_t> exit_ends;
        std::uint32_t n = *ring_out;
        for (int guard = 0; n != entry && guard < 64; ++guard) {
            done[n] = 1;
            std::optional<std::uint32_t> next;
            for (const auto& e : g.outEdges(n)) {
                if (ring(e))
                    next = e.to;
                else if (drivable(e))
                    exit_ends.push_back(e.to);
            }
            if (!next) break;
            n = *next;
        }
        done[entry] = 1;
        if (n != entry || exit_ends.size() < 2) continue;
        ++rings_checked;
        for (std::size_t k = 0; k < exit_ends.size(); ++k) {
            const auto r = map::fastestRoute(g, *approach, exit_ends[k]);
            if (!r) continue;
            const auto line = map::routePolyline(g, *r);
            const auto ms = map::guidance::deriveManeuvers(g, line);
            const auto it = std::find_if(
                ms.begin(), ms.end(), [](const auto& m) { return m.type == map::guidance::ManeuverType::Roundabout; });
            // A* may prefer another road to this exit, or enter the ring elsewhere.
            if (it == ms.end() || g.edges[line[it->point].edge].to != entry) continue;
            EXPECT_EQ(it->exit, static_cast<int>(k) + 1) << "ring entered at node " << g.nodes[entry].osm_id
                                                         << ", exit to node " << g.nodes[exit_ends[k]].osm_id;
            ++exits_checked;
        }
    }
    if (rings_checked == 0) GTEST_SKIP() << "the store has no roundabout with a two-way approach and two exits";
    EXPECT_GE(exits_checked, 2U);
}

}  // namespace
}  // namespace navmap::sim
