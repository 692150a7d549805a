// SPDX-License-Identifier: Apache-2.0
// Speed limits from OSM tags (speed_limit_tags.h): real maxspeed values as they occur in
// OpenStreetMap, conditional limits, and the limit per direction of travel through the whole
// compile (an .osm fixture -> navmap-compile's engine -> the store's road graph), in memory and
// bounded.
#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <map>
#include <string>

#include "map_test_util.h"
#include "navmap/map/compile/compiler.h"
#include "navmap/map/compile/speed_limit_tags.h"
#include "navmap/map/road_graph.h"
#include "navmap/map/tile_store.h"

using namespace navmap::map;
using navmap::map::test::ScratchDir;

namespace {

TagLookup tags(const std::map<std::string, std::string>& kv) {
    return [kv](const char* key) -> const char* {
        const auto it = kv.find(key);
        return it == kv.end() ? nullptr : it->second.c_str();
    };
}

// Values as OpenStreetMap has them on highways (taginfo's list of maxspeed values: numbers,
// units, the implicit country codes and the words), each with the km/h expected (0: unknown).
TEST(SpeedLimitTags, RealMaxspeedValues) {
    const std::pair<const char*, int> cases[] = {
        {"50", 50},
        {"30", 30},
        {"130", 130},
        {"5", 5},
        {" 70 ", 70},
        {"50 km/h", 50},
        {"90 kmh", 90},
        {"80 kph", 80},
        {"20 mph", 32},
        {"30 mph", 48},
        {"70 mph", 113},
        {"10 knots", 19},
        {"5 knots", 9},
        {"FR:urban", 50},
        {"FR:rural", 80},
        {"FR:motorway", 130},
        {"FR:zone30", 0},  // a zone sign's value, not in the wiki's table
        {"DE:urban", 50},
        {"DE:rural", 100},
        {"DE:motorway", 0},  // no general limit
        {"DE:living_street", 0},
        {"DE:bicycle_road", 30},
        {"ES:urban", 30},  // 50 only with two or more lanes each way
        {"ES:rural", 90},
        {"ES:motorway", 120},
        {"IT:urban", 50},
        {"IT:rural", 90},
        {"IT:motorway", 130},
        {"AD:urban", 50},
        {"AD:rural", 60},
        {"AD:motorway", 120},
        {"BE-BRU:urban", 30},
        {"BE-VLG:urban", 50},
        {"BE-WAL:rural", 90},
        {"BE:urban", 0},  // Brussels 30, Flanders and Wallonia 50: no single value
        {"AT:motorway", 130},
        {"CH:rural", 80},
        {"FI:rural", 100},
        {"RS:motorway", 120},
        {"NL:motorway", 130},
        {"SE:motorway", 110},
        {"MT:rural", 80},
        {"AL:urban", 40},
        {"GB:nsl_single", 97},
        {"GB:nsl_dual", 113},
        {"GB:motorway", 113},
        {"RU:urban", 60},
        {"none", 0},
        {"walk", 0},
        {"signals", 0},
        {"variable", 0},
        {"implicit", 0},
        {"50;30", 0},
        {"50;50 mph", 0},
        {"XX:urban", 0},
        {"fr:urban", 0},
        {"0", 0},
        {"-50", 0},
        {"999", 0},
        {"50 km", 0},
        {"fast", 0},
        {"", 0},
        {"30 @ (22:00-06:00)", 0},  // a conditional value in the plain key: not a limit
    };
    for (const auto& [text, kmh] : cases) EXPECT_EQ(parseSpeedLimitKmh(text), kmh) << '"' << text << '"';
    EXPECT_TRUE(implicitSpeedLimitKmh("DE:motorway")) << "a listed code without a fixed limit";
    EXPECT_FALSE(implicitSpeedLimitKmh("XX:urban"));
    EXPECT_FALSE(implicitSpeedLimitKmh("BE:urban")) << "no single Belgian urban limit";
    EXPECT_FALSE(implicitSpeedLimitKmh("CY:rural")) << "not in the table the values come from";
}

TEST(SpeedLimitTags, ConditionalLimits) {
    auto c = parseConditionalSpeedLimits("30 @ (22:00-06:00)");
    ASSERT_EQ(c.size(), 1u);
    EXPECT_EQ(c[0].kmh, 30);
    EXPECT_EQ(c[0].condition, "22:00-06:00");
    EXPECT_TRUE(c[0].time_of_day_only);

    c = parseConditionalSpeedLimits("20 mph @ (07:00-09:00,15:00-17:00)");
    ASSERT_EQ(c.size(), 1u);
    EXPECT_EQ(c[0].kmh, 32);
    EXPECT_TRUE(c[0].time_of_day_only);

    c = parseConditionalSpeedLimits("30 @ (Mo-Fr 07:00-17:00); 80 @ wet");
    ASSERT_EQ(c.size(), 2u);
    EXPECT_EQ(c[0].kmh, 30);
    EXPECT_EQ(c[0].condition, "Mo-Fr 07:00-17:00");
    EXPECT_FALSE(c[0].time_of_day_only) << "weekdays are more than a time of day";
    EXPECT_EQ(c[1].kmh, 80);
    EXPECT_EQ(c[1].condition, "wet");
    EXPECT_FALSE(c[1].time_of_day_only);

    c = parseConditionalSpeedLimits("none @ (06:00-22:00); 120 @ (22:00-06:00)");
    ASSERT_EQ(c.size(), 2u);
    EXPECT_EQ(c[0].kmh, 0);
    EXPECT_EQ(c[1].kmh, 120);
    EXPECT_TRUE(c[1].time_of_day_only);
    EXPECT_TRUE(parseConditionalSpeedLimits("50").empty()) << "no condition";
}

TEST(SpeedLimitTags, DirectionsFromTheTags) {
    auto d = speedLimitsFromTags(tags({{"maxspeed", "50"}}));
    EXPECT_EQ(d.forward_kmh, 50);
    EXPECT_EQ(d.backward_kmh, 50);
    d = speedLimitsFromTags(tags({{"maxspeed", "50"}, {"maxspeed:backward", "30"}}));
    EXPECT_EQ(d.forward_kmh, 50);
    EXPECT_EQ(d.backward_kmh, 30);
    d = speedLimitsFromTags(tags({{"maxspeed:forward", "70"}, {"maxspeed:backward", "none"}}));
    EXPECT_EQ(d.forward_kmh, 70);
    EXPECT_EQ(d.backward_kmh, 0);
    d = speedLimitsFromTags(tags({{"maxspeed", "50"}, {"maxspeed:conditional", "30 @ (22:00-06:00)"}}));
    EXPECT_EQ(d.forward_kmh, 50) << "the store keeps the limit without a condition";
    d = speedLimitsFromTags(tags({{"highway", "primary"}}));
    EXPECT_EQ(d.forward_kmh, 0);
    EXPECT_EQ(d.backward_kmh, 0);
}

// Five short ways, apart from each other, each one graph edge (two for a two-way road).
constexpr const char* kFixture = R"osm(<?xml version="1.0" encoding="UTF-8"?>
<osm version="0.6" generator="test">
 <node id="1" version="1" lat="42.500" lon="1.500"/>
 <node id="2" version="1" lat="42.500" lon="1.505"/>
 <node id="3" version="1" lat="42.505" lon="1.500"/>
 <node id="4" version="1" lat="42.505" lon="1.505"/>
 <node id="5" version="1" lat="42.510" lon="1.500"/>
 <node id="6" version="1" lat="42.510" lon="1.505"/>
 <node id="7" version="1" lat="42.515" lon="1.500"/>
 <node id="8" version="1" lat="42.515" lon="1.505"/>
 <node id="9" version="1" lat="42.520" lon="1.500"/>
 <node id="10" version="1" lat="42.520" lon="1.505"/>
 <way id="100" version="1"><nd ref="1"/><nd ref="2"/><tag k="highway" v="secondary"/>
  <tag k="maxspeed" v="50"/><tag k="maxspeed:backward" v="30"/></way>
 <way id="101" version="1"><nd ref="3"/><nd ref="4"/><tag k="highway" v="primary"/><tag k="oneway" v="yes"/>
  <tag k="maxspeed" v="FR:urban"/></way>
 <way id="102" version="1"><nd ref="5"/><nd ref="6"/><tag k="highway" v="primary"/><tag k="oneway" v="-1"/>
  <tag k="maxspeed:forward" v="90"/><tag k="maxspeed:backward" v="40"/></way>
 <way id="103" version="1"><nd ref="7"/><nd ref="8"/><tag k="highway" v="residential"/><tag k="maxspeed" v="none"/></way>
 <way id="104" version="1"><nd ref="9"/><nd ref="10"/><tag k="highway" v="tertiary"/><tag k="maxspeed" v="30 mph"/>
  <tag k="maxspeed:conditional" v="20 mph @ (22:00-06:00)"/></way>
</osm>
)osm";

struct DirectedLimit {
    std::int64_t from_osm = 0, to_osm = 0;
    int kmh = 0;
    bool operator==(const DirectedLimit&) const = default;
};

std::map<std::int64_t, std::vector<DirectedLimit>> limitsByWay(const RoadGraph& g) {
    std::map<std::int64_t, std::vector<DirectedLimit>> out;
    for (const GraphEdge& e : g.edges)
        out[e.way_id].push_back({g.nodes[e.from].osm_id, g.nodes[e.to].osm_id, e.speed_limit_kmh});
    for (auto& [id, v] : out)
        std::sort(v.begin(), v.end(), [](const auto& a, const auto& b) { return a.from_osm < b.from_osm; });
    return out;
}

TEST(SpeedLimitCompile, EachDirectionKeepsItsLimitInTheStore) {
    ScratchDir dir("speed-limit");
    std::ofstream(dir / "limits.osm") << kFixture;
    for (const std::uint64_t limit : {std::uint64_t{0}, std::uint64_t{64}}) {
        CompileOptions opt;
        opt.osm = dir / "limits.osm";
        opt.out = dir / "limits.navmap";
        opt.leaf_tile_m = 1000;
        opt.memory_limit_mib = limit;
        compileStore(opt);
        const auto ways = limitsByWay(TileStore::open(opt.out)->loadGraph());
        const auto edges = [&](std::int64_t way) {
            return ways.count(way) ? ways.at(way) : std::vector<DirectedLimit>{};
        };
        // Two-way: along the nodes maxspeed, against them maxspeed:backward.
        EXPECT_EQ(edges(100), (std::vector<DirectedLimit>{{1, 2, 50}, {2, 1, 30}})) << "limit " << limit;
        // One-way along the nodes: one edge, the implicit French urban limit.
        EXPECT_EQ(edges(101), (std::vector<DirectedLimit>{{3, 4, 50}})) << "limit " << limit;
        // oneway=-1: the only direction runs against the nodes, so maxspeed:backward applies.
        EXPECT_EQ(edges(102), (std::vector<DirectedLimit>{{6, 5, 40}})) << "limit " << limit;
        EXPECT_EQ(edges(103), (std::vector<DirectedLimit>{{7, 8, 0}, {8, 7, 0}})) << "limit " << limit;
        EXPECT_EQ(edges(104), (std::vector<DirectedLimit>{{9, 10, 48}, {10, 9, 48}})) << "limit " << limit;
    }
}

// The road graph's encoding keeps each edge's limit ("GRG2"); a graph of an earlier compile
// ("GRG1", no limits) still decodes, every limit unknown.
template <class T>
void put(std::vector<std::uint8_t>& out, T v) {
    const auto* b = reinterpret_cast<const std::uint8_t*>(&v);
    out.insert(out.end(), b, b + sizeof(T));  // little-endian hosts, as the store
}

TEST(SpeedLimitGraph, EncodingKeepsTheLimitAndOlderGraphsReadAsUnknown) {
    RoadGraph g;
    g.nodes = {{0, 0, 1}, {0, 100, 2}};
    g.shape = {{0, 0}, {0, 100}};
    GraphEdge e{0, 1, 100, 50, RoadClass::Secondary, 0, 0, 2, 7, 50};
    GraphEdge back = e;
    std::swap(back.from, back.to);
    back.flags = edge_flags::kReversed;
    back.speed_limit_kmh = 130;
    g.edges = {e, back};
    indexEdges(g);
    const std::vector<std::uint8_t> bytes = encodeRoadGraph(g);
    ASSERT_GE(bytes.size(), 4u);
    EXPECT_EQ(std::string(bytes.begin(), bytes.begin() + 4), "GRG3");  // GRG2 and the turn lanes
    RoadGraph decoded;
    std::string error;
    ASSERT_TRUE(decodeRoadGraph(bytes, decoded, error)) << error;
    ASSERT_EQ(decoded.edges.size(), 2u);
    EXPECT_EQ(decoded.edges[0].speed_limit_kmh, 50);
    EXPECT_EQ(decoded.edges[1].speed_limit_kmh, 130);

    // The same graph's first edge as a GRG1 compile wrote it: no limit after the way id.
    std::vector<std::uint8_t> v1 = {'G', 'R', 'G', '1', 2};
    for (const GraphNode& n : g.nodes) {
        put(v1, n.x);
        put(v1, n.y);
        v1.push_back(static_cast<std::uint8_t>(n.osm_id * 2));  // zigzag
    }
    v1.insert(v1.end(), {1, 0, 1});  // one edge, from 0 to 1
    put(v1, 100.0f);
    put(v1, 50.0f);
    v1.insert(v1.end(), {static_cast<std::uint8_t>(RoadClass::Secondary), 0, 0, 2, 14});  // way 7
    v1.push_back(2);
    for (const LocalPoint& q : g.shape) {
        put(v1, q.x);
        put(v1, q.y);
    }
    ASSERT_TRUE(decodeRoadGraph(v1, decoded, error)) << error;
    ASSERT_EQ(decoded.edges.size(), 1u);
    EXPECT_EQ(decoded.edges[0].way_id, 7);
    EXPECT_EQ(decoded.edges[0].speed_limit_kmh, 0);
    v1[3] = '4';  // no such version (GRG3 has the turn lanes)
    EXPECT_FALSE(decodeRoadGraph(v1, decoded, error));
    EXPECT_EQ(error, "not a road graph (bad magic)");
}

}  // namespace
