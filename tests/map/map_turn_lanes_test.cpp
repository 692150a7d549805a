// SPDX-License-Identifier: Apache-2.0
// Turn lanes (docs/tile-store.md "Turn lanes", docs/guidance.md "Lanes"): real turn:lanes values
// through the parser, the lanes per direction of travel through the whole compile (an .osm
// fixture -> navmap-compile's engine -> the store's road graph, in memory and bounded), and the
// lanes found before each kind of junction the fixture has: through and left, a slight right, a
// lane merging away, unmarked lanes, lanes tagged backward on a two-way road, lanes that change
// before the junction and lanes of a way farther back.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <map>
#include <optional>
#include <string>

#include "guidance_test_graph.h"
#include "map_test_util.h"
#include "navmap/map/compile/compiler.h"
#include "navmap/map/compile/turn_lane_tags.h"
#include "navmap/map/guidance/lane_guidance.h"
#include "navmap/map/guidance/maneuver_derivation.h"
#include "navmap/map/road_graph.h"
#include "navmap/map/tile_store.h"

using namespace navmap::map;
using namespace navmap::map::guidance;
using navmap::map::test::ScratchDir;
namespace la = navmap::map::lane_arrow;

namespace {

TagLookup tags(const std::map<std::string, std::string>& kv) {
    return [kv](const char* key) -> const char* {
        const auto it = kv.find(key);
        return it == kv.end() ? nullptr : it->second.c_str();
    };
}

using Lanes = std::vector<std::uint16_t>;

// Values as OpenStreetMap has them (taginfo's most used turn:lanes values, and the Andorra
// extract's), each with the lanes expected and the count of values not understood.
TEST(TurnLaneTags, RealValues) {
    struct Case {
        const char* text;
        Lanes lanes;
        std::size_t unknown;
    };
    const Case cases[] = {
        {"left|through", {la::kLeft, la::kThrough}, 0},
        {"through|right", {la::kThrough, la::kRight}, 0},
        {"left|through|through;right", {la::kLeft, la::kThrough, la::kThrough | la::kRight}, 0},
        {"left;through|through;right", {la::kLeft | la::kThrough, la::kThrough | la::kRight}, 0},
        {"slight_left|slight_right", {la::kSlightLeft, la::kSlightRight}, 0},
        {"sharp_left;left|through|sharp_right", {la::kSharpLeft | la::kLeft, la::kThrough, la::kSharpRight}, 0},
        {"reverse;left|through", {la::kReverse | la::kLeft, la::kThrough}, 0},
        {"|merge_to_left", {0, la::kMergeToLeft}, 0},      // Andorra, CG-2 (way 181921084)
        {"none|merge_to_left", {0, la::kMergeToLeft}, 0},  // Andorra, Port d'Envalira (way 28833924)
        {"|merge_to_right", {0, la::kMergeToRight}, 0},
        {"through|through|merge_to_left", {la::kThrough, la::kThrough, la::kMergeToLeft}, 0},
        {"left||right", {la::kLeft, 0, la::kRight}, 0},
        {"none|none", {0, 0}, 0},
        {"left| through ; slight_right ", {la::kLeft, la::kThrough | la::kSlightRight}, 0},
        {"left|slide_right|through", {la::kLeft, 0, la::kThrough}, 1},
        {"left;foo;bar|through", {la::kLeft, la::kThrough}, 2},
        {"Left|THROUGH", {0, 0}, 2},  // values are lower case
        {"||", {0, 0, 0}, 0},
    };
    for (const Case& c : cases) {
        const ParsedTurnLanes p = parseTurnLanes(c.text);
        EXPECT_EQ(p.lanes, c.lanes) << c.text;
        EXPECT_EQ(p.unknown_values, c.unknown) << c.text;
        EXPECT_FALSE(p.too_many) << c.text;
    }
    EXPECT_TRUE(parseTurnLanes("").lanes.empty());
    EXPECT_TRUE(parseTurnLanes("  ").lanes.empty());
    std::string sixteen = "through", seventeen;
    for (int i = 1; i < 16; ++i) sixteen += "|through";
    seventeen = sixteen + "|right";
    EXPECT_EQ(parseTurnLanes(sixteen).lanes.size(), 16u);
    const ParsedTurnLanes many = parseTurnLanes(seventeen);
    EXPECT_TRUE(many.too_many);
    EXPECT_TRUE(many.lanes.empty());
}

TEST(TurnLaneTags, DirectionsFromTheTags) {
    // One-way: plain turn:lanes (or the :forward form) for the direction driven.
    auto d = turnLanesFromTags(tags({{"turn:lanes", "left|through"}}), 1);
    EXPECT_EQ(d.forward, (Lanes{la::kLeft, la::kThrough}));
    EXPECT_TRUE(d.backward.empty());
    d = turnLanesFromTags(tags({{"turn:lanes:forward", "through|right"}}), 1);
    EXPECT_EQ(d.forward, (Lanes{la::kThrough, la::kRight}));
    // oneway=-1: the lanes are of the direction against the nodes.
    d = turnLanesFromTags(tags({{"turn:lanes", "left|through"}}), -1);
    EXPECT_TRUE(d.forward.empty());
    EXPECT_EQ(d.backward, (Lanes{la::kLeft, la::kThrough}));
    // Two-way: each direction its own.
    d = turnLanesFromTags(tags({{"turn:lanes:forward", "left|through"}, {"turn:lanes:backward", "|merge_to_left"}}), 0);
    EXPECT_EQ(d.forward, (Lanes{la::kLeft, la::kThrough}));
    EXPECT_EQ(d.backward, (Lanes{0, la::kMergeToLeft}));
    EXPECT_EQ(d.dropped, 0u);
    // Two-way with plain turn:lanes: only where the counts say it is that direction's.
    d = turnLanesFromTags(tags({{"turn:lanes", "through|right"}, {"lanes", "4"}}), 0);
    EXPECT_EQ(d.forward, (Lanes{la::kThrough, la::kRight}));
    EXPECT_EQ(d.backward, (Lanes{la::kThrough, la::kRight}));
    d = turnLanesFromTags(tags({{"turn:lanes", "through|right"}, {"lanes", "3"}}), 0);
    EXPECT_TRUE(d.forward.empty());
    EXPECT_TRUE(d.backward.empty());
    EXPECT_EQ(d.dropped, 1u);
    d = turnLanesFromTags(
        tags({{"turn:lanes", "through|right"}, {"lanes", "3"}, {"lanes:forward", "2"}, {"lanes:backward", "1"}}), 0);
    EXPECT_EQ(d.forward, (Lanes{la::kThrough, la::kRight}));
    EXPECT_TRUE(d.backward.empty());
    d = turnLanesFromTags(tags({{"turn:lanes", "through|right"}}), 0);  // no counts at all
    EXPECT_TRUE(d.forward.empty());
    EXPECT_EQ(d.dropped, 1u);
    // Unknown values are counted, the lanes kept.
    d = turnLanesFromTags(tags({{"turn:lanes", "left|slide_right"}, {"turn:lanes:forward", "foo|through"}}), 1);
    EXPECT_EQ(d.forward, (Lanes{0, la::kThrough}));
    EXPECT_EQ(d.unknown_values, 2u);
}

// The rule of docs/guidance.md "Lanes".
TEST(LaneGuidanceRule, LanesThatLeadOut) {
    const Lanes left_through{la::kLeft, la::kThrough, la::kThrough | la::kRight};
    EXPECT_EQ(recommendedLanes(left_through, ManeuverType::TurnLeft, -90.0), 0b001u);
    EXPECT_EQ(recommendedLanes(left_through, ManeuverType::Straight, 0.0), 0b110u);
    EXPECT_EQ(recommendedLanes(left_through, ManeuverType::TurnRight, 90.0), 0b100u);
    // No exact arrow: the neighbouring ones.
    EXPECT_EQ(recommendedLanes(left_through, ManeuverType::SlightLeft, -30.0), 0b001u);
    EXPECT_EQ(recommendedLanes(left_through, ManeuverType::SharpRight, 150.0), 0b100u);
    // At a fork: the slight arrows, else the lanes going on straight.
    const Lanes fork{la::kThrough, la::kThrough, la::kSlightRight};
    EXPECT_EQ(recommendedLanes(fork, ManeuverType::KeepRight, 10.0), 0b100u);
    EXPECT_EQ(recommendedLanes(fork, ManeuverType::KeepLeft, -10.0), 0b011u);
    // Nothing matches: none.
    EXPECT_EQ(recommendedLanes(Lanes{la::kLeft, la::kThrough}, ManeuverType::TurnRight, 90.0), 0u);
    // Unmarked lanes go straight on when no lane says so.
    EXPECT_EQ(recommendedLanes(Lanes{la::kLeft, 0, 0}, ManeuverType::Straight, 0.0), 0b110u);
    EXPECT_EQ(recommendedLanes(Lanes{la::kLeft, 0, la::kThrough}, ManeuverType::Straight, 0.0), 0b100u);
    // A lane that merges away is not one to go on in.
    EXPECT_EQ(recommendedLanes(Lanes{0, la::kMergeToLeft}, ManeuverType::Straight, 0.0), 0b01u);
    // Roundabouts and exits by their heading change.
    EXPECT_EQ(recommendedLanes(left_through, ManeuverType::Roundabout, -95.0), 0b001u);
    EXPECT_EQ(recommendedLanes(left_through, ManeuverType::Exit, 80.0), 0b100u);
    EXPECT_EQ(recommendedLanes(left_through, ManeuverType::Depart, 0.0), 0u);
    EXPECT_EQ(recommendedLanes(Lanes{la::kReverse | la::kLeft, la::kThrough}, ManeuverType::UTurn, 180.0), 0b01u);
}

constexpr const char* kFixture = R"osm(<?xml version="1.0" encoding="UTF-8"?>
<osm version="0.6" generator="test">
 <node id="101" version="1" lat="42.5160" lon="1.5000"/>
 <node id="102" version="1" lat="42.5200" lon="1.5000"/>
 <node id="103" version="1" lat="42.5230" lon="1.5000"/>
 <node id="104" version="1" lat="42.5200" lon="1.4960"/>
 <node id="201" version="1" lat="42.5360" lon="1.5000"/>
 <node id="202" version="1" lat="42.5400" lon="1.5000"/>
 <node id="204" version="1" lat="42.5400" lon="1.4960"/>
 <node id="207" version="1" lat="42.5430" lon="1.5025"/>
 <node id="301" version="1" lat="42.5560" lon="1.5000"/>
 <node id="302" version="1" lat="42.5600" lon="1.5000"/>
 <node id="303" version="1" lat="42.5630" lon="1.5000"/>
 <node id="306" version="1" lat="42.5600" lon="1.5040"/>
 <node id="401" version="1" lat="42.5760" lon="1.5000"/>
 <node id="402" version="1" lat="42.5800" lon="1.5000"/>
 <node id="403" version="1" lat="42.5830" lon="1.5000"/>
 <node id="404" version="1" lat="42.5800" lon="1.4960"/>
 <node id="501" version="1" lat="42.5960" lon="1.5000"/>
 <node id="502" version="1" lat="42.6000" lon="1.5000"/>
 <node id="503" version="1" lat="42.6030" lon="1.5000"/>
 <node id="504" version="1" lat="42.6000" lon="1.4960"/>
 <node id="601" version="1" lat="42.6160" lon="1.5000"/>
 <node id="602" version="1" lat="42.6200" lon="1.5000"/>
 <node id="603" version="1" lat="42.6230" lon="1.5000"/>
 <node id="604" version="1" lat="42.6200" lon="1.4960"/>
 <node id="609" version="1" lat="42.6180" lon="1.5000"/>
 <node id="701" version="1" lat="42.6360" lon="1.5000"/>
 <node id="702" version="1" lat="42.6400" lon="1.5000"/>
 <node id="703" version="1" lat="42.6430" lon="1.5000"/>
 <node id="704" version="1" lat="42.6400" lon="1.4960"/>
 <node id="709" version="1" lat="42.6380" lon="1.5000"/>
 <node id="801" version="1" lat="42.6600" lon="1.5000"/>
 <node id="802" version="1" lat="42.6600" lon="1.5050"/>
 <node id="803" version="1" lat="42.6620" lon="1.5000"/>
 <node id="804" version="1" lat="42.6620" lon="1.5050"/>
 <node id="805" version="1" lat="42.6640" lon="1.5000"/>
 <node id="806" version="1" lat="42.6640" lon="1.5050"/>
 <node id="807" version="1" lat="42.6660" lon="1.5000"/>
 <node id="808" version="1" lat="42.6660" lon="1.5050"/>
 <node id="809" version="1" lat="42.6680" lon="1.5000"/>
 <node id="810" version="1" lat="42.6680" lon="1.5050"/>
 <way id="1001" version="1"><nd ref="101"/><nd ref="102"/><tag k="highway" v="secondary"/><tag k="lanes" v="3"/><tag k="lanes:forward" v="2"/><tag k="lanes:backward" v="1"/><tag k="turn:lanes:forward" v="left|through"/></way>
 <way id="1002" version="1"><nd ref="102"/><nd ref="103"/><tag k="highway" v="secondary"/></way>
 <way id="1003" version="1"><nd ref="102"/><nd ref="104"/><tag k="highway" v="residential"/></way>
 <way id="2001" version="1"><nd ref="201"/><nd ref="202"/><tag k="highway" v="secondary"/><tag k="oneway" v="yes"/><tag k="turn:lanes" v="left|slight_right|slight_right"/></way>
 <way id="2003" version="1"><nd ref="202"/><nd ref="204"/><tag k="highway" v="residential"/></way>
 <way id="2007" version="1"><nd ref="202"/><nd ref="207"/><tag k="highway" v="secondary"/></way>
 <way id="3001" version="1"><nd ref="301"/><nd ref="302"/><tag k="highway" v="secondary"/><tag k="oneway" v="yes"/><tag k="lanes" v="3"/><tag k="turn:lanes" v="through|through|merge_to_left"/></way>
 <way id="3002" version="1"><nd ref="302"/><nd ref="303"/><tag k="highway" v="secondary"/></way>
 <way id="3006" version="1"><nd ref="302"/><nd ref="306"/><tag k="highway" v="residential"/></way>
 <way id="4001" version="1"><nd ref="401"/><nd ref="402"/><tag k="highway" v="secondary"/><tag k="lanes" v="3"/><tag k="lanes:forward" v="2"/><tag k="lanes:backward" v="1"/><tag k="turn:lanes:forward" v="left|none"/></way>
 <way id="4002" version="1"><nd ref="402"/><nd ref="403"/><tag k="highway" v="secondary"/></way>
 <way id="4003" version="1"><nd ref="402"/><nd ref="404"/><tag k="highway" v="residential"/></way>
 <way id="5001" version="1"><nd ref="502"/><nd ref="501"/><tag k="highway" v="secondary"/><tag k="lanes" v="3"/><tag k="lanes:forward" v="1"/><tag k="lanes:backward" v="2"/><tag k="turn:lanes:backward" v="left|through;right"/></way>
 <way id="5002" version="1"><nd ref="502"/><nd ref="503"/><tag k="highway" v="secondary"/></way>
 <way id="5003" version="1"><nd ref="502"/><nd ref="504"/><tag k="highway" v="residential"/></way>
 <way id="6001" version="1"><nd ref="601"/><nd ref="609"/><tag k="highway" v="secondary"/><tag k="lanes" v="4"/><tag k="lanes:forward" v="2"/><tag k="lanes:backward" v="2"/><tag k="turn:lanes:forward" v="through|through"/></way>
 <way id="6002" version="1"><nd ref="602"/><nd ref="603"/><tag k="highway" v="secondary"/></way>
 <way id="6003" version="1"><nd ref="602"/><nd ref="604"/><tag k="highway" v="residential"/></way>
 <way id="6004" version="1"><nd ref="609"/><nd ref="602"/><tag k="highway" v="secondary"/><tag k="lanes" v="4"/><tag k="lanes:forward" v="3"/><tag k="lanes:backward" v="1"/><tag k="turn:lanes:forward" v="left|through|through"/></way>
 <way id="7001" version="1"><nd ref="701"/><nd ref="709"/><tag k="highway" v="secondary"/><tag k="oneway" v="yes"/><tag k="turn:lanes" v="left|through"/></way>
 <way id="7002" version="1"><nd ref="702"/><nd ref="703"/><tag k="highway" v="secondary"/></way>
 <way id="7003" version="1"><nd ref="702"/><nd ref="704"/><tag k="highway" v="residential"/></way>
 <way id="7004" version="1"><nd ref="709"/><nd ref="702"/><tag k="highway" v="secondary"/><tag k="oneway" v="yes"/></way>
 <way id="8001" version="1"><nd ref="801"/><nd ref="802"/><tag k="highway" v="tertiary"/><tag k="lanes" v="4"/><tag k="turn:lanes" v="through|right"/></way>
 <way id="8002" version="1"><nd ref="803"/><nd ref="804"/><tag k="highway" v="tertiary"/><tag k="lanes" v="3"/><tag k="turn:lanes" v="through|right"/></way>
 <way id="8003" version="1"><nd ref="805"/><nd ref="806"/><tag k="highway" v="tertiary"/><tag k="oneway" v="yes"/><tag k="turn:lanes" v="left|slide_right|through"/></way>
 <way id="8004" version="1"><nd ref="807"/><nd ref="808"/><tag k="highway" v="tertiary"/><tag k="oneway" v="yes"/><tag k="turn:lanes" v="through|through|through|through|through|through|through|through|through|through|through|through|through|through|through|through|through"/></way>
 <way id="8005" version="1"><nd ref="809"/><nd ref="810"/><tag k="highway" v="tertiary"/><tag k="oneway" v="-1"/><tag k="turn:lanes" v="left|through"/></way>
</osm>
)osm";

struct DirectedLanes {
    std::int64_t from_osm = 0, to_osm = 0;
    Lanes lanes;
    bool operator==(const DirectedLanes&) const = default;
};

std::map<std::int64_t, std::vector<DirectedLanes>> lanesByWay(const RoadGraph& g) {
    std::map<std::int64_t, std::vector<DirectedLanes>> out;
    for (const GraphEdge& e : g.edges) {
        const auto l = g.lanesOf(e);
        out[e.way_id].push_back({g.nodes[e.from].osm_id, g.nodes[e.to].osm_id, Lanes(l.begin(), l.end())});
    }
    for (auto& [id, v] : out)
        std::sort(v.begin(), v.end(), [](const auto& a, const auto& b) { return a.from_osm < b.from_osm; });
    return out;
}

class TurnLaneFixture : public ::testing::Test {
protected:
    static void SetUpTestSuite() {
        s_dir = new ScratchDir("turn-lanes");
        std::ofstream(*s_dir / "lanes.osm") << kFixture;
        for (const std::uint64_t limit : {std::uint64_t{0}, std::uint64_t{64}}) {
            CompileOptions opt;
            opt.osm = *s_dir / "lanes.osm";
            opt.out = *s_dir / ("lanes-" + std::to_string(limit) + ".navmap");
            opt.leaf_tile_m = 1000;
            opt.memory_limit_mib = limit;
            s_stats[limit] = compileStore(opt);
            s_graphs[limit] = TileStore::open(opt.out)->loadGraph();
        }
    }
    static void TearDownTestSuite() {
        s_graphs.clear();
        s_stats.clear();
        delete s_dir;
    }
    static const RoadGraph& graph() { return s_graphs.at(0); }
    static std::uint32_t node(std::int64_t osm_id) {
        const auto& n = graph().nodes;
        const auto it = std::find_if(n.begin(), n.end(), [&](const GraphNode& g) { return g.osm_id == osm_id; });
        EXPECT_NE(it, n.end()) << "node " << osm_id;
        return static_cast<std::uint32_t>(it - n.begin());
    }
    /// The fastest route between two OSM nodes: its points and derived manoeuvres.
    struct Route {
        std::vector<PlanarPoint> points;
        std::vector<Maneuver> maneuvers;
    };
    static Route route(std::int64_t from, std::int64_t to) {
        const auto line = test::routeLine(graph(), node(from), node(to));
        Route r;
        for (const RoutePoint& p : line) r.points.push_back(p.position);
        r.maneuvers = deriveManeuvers(graph(), line);
        return r;
    }
    /// A route between two nodes with a manoeuvre of `type` given at `junction` (as a control
    /// route brings it) instead of the derived ones.
    static Route routeWith(std::int64_t from, std::int64_t to, std::int64_t junction, ManeuverType type) {
        Route r = route(from, to);
        const GraphNode& j = graph().nodes[node(junction)];
        std::size_t at = 0;
        for (std::size_t i = 0; i < r.points.size(); ++i) {
            if (std::hypot(r.points[i].x - j.x, r.points[i].y - j.y) < 0.5) at = i;
        }
        EXPECT_GT(at, 0u) << "junction " << junction << " not on the route";
        Maneuver m;
        m.type = type;
        m.point = m.end_point = at;
        r.maneuvers = {m};
        return r;
    }
    /// The lanes found before the route's only manoeuvre other than depart and arrive.
    static std::optional<LaneGuidance> lanesOf(const Route& r, ManeuverType expected,
                                               const LaneSearchOptions& options = {}) {
        const LaneFinder finder(graph());
        const auto found = finder.find(r.points, r.maneuvers, options);
        EXPECT_EQ(found.size(), r.maneuvers.size());
        std::optional<LaneGuidance> out;
        int turns = 0;
        for (std::size_t k = 0; k < r.maneuvers.size(); ++k) {
            const ManeuverType t = r.maneuvers[k].type;
            if (t == ManeuverType::Depart || t == ManeuverType::Arrive) {
                EXPECT_FALSE(found[k].has_value()) << "no lanes at depart or arrive";
                continue;
            }
            ++turns;
            EXPECT_EQ(t, expected);
            out = found[k];
        }
        EXPECT_EQ(turns, 1);
        return out;
    }
    static inline ScratchDir* s_dir = nullptr;
    static inline std::map<std::uint64_t, RoadGraph> s_graphs;
    static inline std::map<std::uint64_t, CompileStats> s_stats;
};

TEST_F(TurnLaneFixture, EachDirectionKeepsItsLanesInTheStore) {
    for (const auto& [limit, g] : s_graphs) {
        const auto ways = lanesByWay(g);
        const auto edges = [&](std::int64_t way) {
            return ways.count(way) ? ways.at(way) : std::vector<DirectedLanes>{};
        };
        // Forward lanes on the way's direction, none against it.
        EXPECT_EQ(edges(1001), (std::vector<DirectedLanes>{{101, 102, {la::kLeft, la::kThrough}}, {102, 101, {}}}))
            << "limit " << limit;
        EXPECT_EQ(edges(2001),
                  (std::vector<DirectedLanes>{{201, 202, {la::kLeft, la::kSlightRight, la::kSlightRight}}}))
            << "limit " << limit;
        // Backward lanes on the reversed twin.
        EXPECT_EQ(edges(5001),
                  (std::vector<DirectedLanes>{{501, 502, {la::kLeft, la::kThrough | la::kRight}}, {502, 501, {}}}))
            << "limit " << limit;
        // Plain turn:lanes on a two-way road: both directions with lanes = 4, none with lanes = 3.
        EXPECT_EQ(edges(8001), (std::vector<DirectedLanes>{{801, 802, {la::kThrough, la::kRight}},
                                                           {802, 801, {la::kThrough, la::kRight}}}))
            << "limit " << limit;
        EXPECT_EQ(edges(8002), (std::vector<DirectedLanes>{{803, 804, {}}, {804, 803, {}}})) << "limit " << limit;
        // An unknown value leaves its lane without arrows; 17 lanes are too many to keep.
        EXPECT_EQ(edges(8003), (std::vector<DirectedLanes>{{805, 806, {la::kLeft, 0, la::kThrough}}}))
            << "limit " << limit;
        EXPECT_EQ(edges(8004), (std::vector<DirectedLanes>{{807, 808, {}}})) << "limit " << limit;
        // oneway=-1: the only edge runs against the nodes and has the lanes.
        EXPECT_EQ(edges(8005), (std::vector<DirectedLanes>{{810, 809, {la::kLeft, la::kThrough}}}))
            << "limit " << limit;
    }
    // Counted: 11 ways with lanes, "slide_right" ignored, way 8002's plain turn:lanes (lanes = 3)
    // and way 8004's 17 lanes not used.
    for (const auto& [limit, st] : s_stats) {
        EXPECT_EQ(st.turn_lane_ways, 11u) << "limit " << limit;
        EXPECT_EQ(st.turn_lane_values_ignored, 1u) << "limit " << limit;
        EXPECT_EQ(st.turn_lane_tags_dropped, 2u) << "limit " << limit;
    }
    EXPECT_NE(formatSummary(s_stats.at(0)).find("turn lanes on 11 ways (1 unknown values ignored, 2 tags not used)"),
              std::string::npos)
        << formatSummary(s_stats.at(0));
    // The bounded compile writes the same graph.
    EXPECT_EQ(s_graphs.at(0).lane_arrows.size(), s_graphs.at(64).lane_arrows.size());
}

TEST_F(TurnLaneFixture, ThroughAndLeft) {
    const auto left = lanesOf(route(101, 104), ManeuverType::TurnLeft);
    ASSERT_TRUE(left);
    EXPECT_EQ(left->lanes, (Lanes{la::kLeft, la::kThrough}));
    EXPECT_EQ(left->recommended, 0b01u);
    EXPECT_EQ(left->way_id, 1001);
    EXPECT_NEAR(left->before_junction_m, 0.0, 0.01);
    const auto straight = lanesOf(routeWith(101, 103, 102, ManeuverType::Straight), ManeuverType::Straight);
    ASSERT_TRUE(straight);
    EXPECT_EQ(straight->recommended, 0b10u);
}

TEST_F(TurnLaneFixture, SlightRight) {
    const auto g = lanesOf(route(201, 207), ManeuverType::SlightRight);
    ASSERT_TRUE(g);
    EXPECT_EQ(g->lanes, (Lanes{la::kLeft, la::kSlightRight, la::kSlightRight}));
    EXPECT_EQ(g->recommended, 0b110u);
    const auto left = lanesOf(route(201, 204), ManeuverType::TurnLeft);
    ASSERT_TRUE(left);
    EXPECT_EQ(left->recommended, 0b001u);
}

TEST_F(TurnLaneFixture, MergeTo) {
    const auto on = lanesOf(routeWith(301, 303, 302, ManeuverType::Straight), ManeuverType::Straight);
    ASSERT_TRUE(on);
    EXPECT_EQ(on->lanes, (Lanes{la::kThrough, la::kThrough, la::kMergeToLeft}));
    EXPECT_EQ(on->recommended, 0b011u);  // not the lane that ends
    // A right turn no lane shows: the lanes are shown, none highlighted.
    const auto right = lanesOf(route(301, 306), ManeuverType::TurnRight);
    ASSERT_TRUE(right);
    EXPECT_EQ(right->lanes.size(), 3u);
    EXPECT_EQ(right->recommended, 0u);
}

TEST_F(TurnLaneFixture, NoneLanes) {
    const auto left = lanesOf(route(401, 404), ManeuverType::TurnLeft);
    ASSERT_TRUE(left);
    EXPECT_EQ(left->lanes, (Lanes{la::kLeft, 0}));
    EXPECT_EQ(left->recommended, 0b01u);
    const auto straight = lanesOf(routeWith(401, 403, 402, ManeuverType::Straight), ManeuverType::Straight);
    ASSERT_TRUE(straight);
    EXPECT_EQ(straight->recommended, 0b10u);  // the unmarked lane goes straight on
}

TEST_F(TurnLaneFixture, BackwardOnATwoWayRoad) {
    // Way 5001 runs from the junction south: the route drives against it.
    const auto left = lanesOf(route(501, 504), ManeuverType::TurnLeft);
    ASSERT_TRUE(left);
    EXPECT_EQ(left->lanes, (Lanes{la::kLeft, la::kThrough | la::kRight}));
    EXPECT_EQ(left->recommended, 0b01u);
    EXPECT_EQ(left->way_id, 5001);
}

TEST_F(TurnLaneFixture, LanesChangeBeforeTheJunction) {
    // Two lanes, then three just before the junction: the last tagged way's.
    const auto left = lanesOf(route(601, 604), ManeuverType::TurnLeft);
    ASSERT_TRUE(left);
    EXPECT_EQ(left->lanes, (Lanes{la::kLeft, la::kThrough, la::kThrough}));
    EXPECT_EQ(left->recommended, 0b001u);
    EXPECT_EQ(left->way_id, 6004);
    // Tagged 222 m before the junction, untagged after: the tagged way's lanes, within the distance.
    const auto back = lanesOf(route(701, 704), ManeuverType::TurnLeft);
    ASSERT_TRUE(back);
    EXPECT_EQ(back->lanes, (Lanes{la::kLeft, la::kThrough}));
    EXPECT_EQ(back->way_id, 7001);
    EXPECT_NEAR(back->before_junction_m, 222.4, 1.0);
    LaneSearchOptions near;
    near.distance_m = 150.0;
    EXPECT_FALSE(lanesOf(route(701, 704), ManeuverType::TurnLeft, near).has_value());
    // A manoeuvre between them (at node 709, where the tagged way ends): the lanes lead to that
    // one, not to the left turn after it.
    Route two = route(701, 704);
    const Route first = routeWith(701, 704, 709, ManeuverType::KeepLeft);
    two.maneuvers.insert(two.maneuvers.begin() + 1, first.maneuvers.front());
    ASSERT_EQ(two.maneuvers.size(), 4u);
    const auto found = LaneFinder(graph()).find(two.points, two.maneuvers);
    ASSERT_TRUE(found[1].has_value());
    EXPECT_EQ(found[1]->way_id, 7001);
    EXPECT_EQ(two.maneuvers[2].type, ManeuverType::TurnLeft);
    EXPECT_FALSE(found[2].has_value());
}

// A route of many points close together: the work bound ends the search (no lanes), it does not
// take seconds. The same route with the bound unspent finds the lanes.
TEST_F(TurnLaneFixture, TheSearchHasAWorkBound) {
    Route r = route(101, 104);
    Route dense;
    for (std::size_t i = 0; i + 1 < r.points.size(); ++i) {
        for (int k = 0; k < 2000; ++k) {
            const double t = k / 2000.0;
            dense.points.push_back({r.points[i].x + t * (r.points[i + 1].x - r.points[i].x),
                                    r.points[i].y + t * (r.points[i + 1].y - r.points[i].y)});
        }
        for (Maneuver m : r.maneuvers) {
            if (m.point != i) continue;
            m.point = m.end_point = dense.points.size() - 2000;
            dense.maneuvers.push_back(m);
        }
    }
    dense.points.push_back(r.points.back());
    Maneuver arrive = r.maneuvers.back();
    arrive.point = arrive.end_point = dense.points.size() - 1;
    dense.maneuvers.push_back(arrive);
    ASSERT_EQ(dense.maneuvers.size(), 3u);
    EXPECT_TRUE(lanesOf(dense, ManeuverType::TurnLeft).has_value());
    LaneSearchOptions small;
    small.max_tests = 1000;
    EXPECT_FALSE(lanesOf(dense, ManeuverType::TurnLeft, small).has_value());
}

TEST_F(TurnLaneFixture, RouteOffTheGraphHasNoLanes) {
    Route r = route(101, 104);
    for (PlanarPoint& p : r.points) p.x += 300.0;  // beside every road
    const LaneFinder finder(graph());
    for (const auto& l : finder.find(r.points, r.maneuvers)) EXPECT_FALSE(l.has_value());
}

// The graph's encoding keeps each edge's lanes ("GRG3"), and rejects damaged ones.
TEST(TurnLaneGraph, EncodingKeepsTheLanes) {
    RoadGraph g;
    g.nodes = {{0, 0, 1}, {0, 100, 2}};
    g.shape = {{0, 0}, {0, 100}};
    g.lane_arrows = {la::kLeft, la::kThrough | la::kRight, 0, la::kMergeToLeft};
    GraphEdge e{0, 1, 100, 50, RoadClass::Secondary, 0, 0, 2, 7, 50};
    e.lane_count = 2;
    e.lanes_begin = 0;
    GraphEdge back = e;
    std::swap(back.from, back.to);
    back.flags = edge_flags::kReversed;
    back.lanes_begin = 2;
    g.edges = {e, back};
    indexEdges(g);
    std::vector<std::uint8_t> bytes = encodeRoadGraph(g);
    EXPECT_EQ(std::string(bytes.begin(), bytes.begin() + 4), "GRG3");
    RoadGraph decoded;
    std::string error;
    ASSERT_TRUE(decodeRoadGraph(bytes, decoded, error)) << error;
    ASSERT_EQ(decoded.edges.size(), 2u);
    const auto lanes = [&](const GraphEdge& x) {
        const auto s = decoded.lanesOf(x);
        return Lanes(s.begin(), s.end());
    };
    EXPECT_EQ(lanes(decoded.edges[0]), (Lanes{la::kLeft, la::kThrough | la::kRight}));
    EXPECT_EQ(lanes(decoded.edges[1]), (Lanes{0, la::kMergeToLeft}));
    // Another store's graph appended after this one keeps its lanes (the ranges move with them).
    RoadGraph both = decoded;
    appendRoadGraph(both, decoded, FrameTransform{});
    ASSERT_EQ(both.edges.size(), 4u);
    for (std::size_t k = 0; k < 2; ++k) {
        const auto a = both.lanesOf(both.edges[k]), b = both.lanesOf(both.edges[k + 2]);
        EXPECT_EQ(Lanes(a.begin(), a.end()), Lanes(b.begin(), b.end())) << k;
    }
    EXPECT_EQ(both.edges[2].lanes_begin, 4u);
    // A lane range beyond the lanes, and an unknown arrow bit, are damage.
    RoadGraph bad = g;
    bad.edges[1].lanes_begin = 3;
    EXPECT_FALSE(decodeRoadGraph(encodeRoadGraph(bad), decoded, error));
    EXPECT_NE(error.find("out of range"), std::string::npos) << error;
    bad = g;
    bad.lane_arrows[0] = 1U << 12;
    EXPECT_FALSE(decodeRoadGraph(encodeRoadGraph(bad), decoded, error));
    EXPECT_NE(error.find("unknown lane arrows"), std::string::npos) << error;
}

}  // namespace
