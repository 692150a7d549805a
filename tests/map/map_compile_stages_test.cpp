// SPDX-License-Identifier: Apache-2.0
// The stages of compileStore (map/compile/src/compile_stages.h), each run alone on a small input
// made here: a .osm XML file of a few objects, an SRTM3 tile, raw features built in memory.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "compile_stages.h"
#include "map_test_util.h"

using namespace navmap::map;
using namespace navmap::map::detail;
using navmap::map::test::ScratchDir;

namespace {

namespace fs = std::filesystem;

// A forest square of about 800 m named "Bosc" (ways 1), a primary road through it (way 2) that
// meets a residential street (way 3) at node 12, a 12 m building (way 4) and a village (node 30).
constexpr const char* kOsm = R"(<?xml version="1.0" encoding="UTF-8"?>
<osm version="0.6" generator="test">
  <node id="1" lat="42.500" lon="1.500"/>
  <node id="2" lat="42.500" lon="1.510"/>
  <node id="3" lat="42.507" lon="1.510"/>
  <node id="4" lat="42.507" lon="1.500"/>
  <node id="10" lat="42.501" lon="1.501"/>
  <node id="11" lat="42.502" lon="1.503"/>
  <node id="12" lat="42.503" lon="1.505"/>
  <node id="13" lat="42.504" lon="1.508"/>
  <node id="20" lat="42.5050" lon="1.5020"/>
  <node id="21" lat="42.5050" lon="1.5023"/>
  <node id="22" lat="42.5052" lon="1.5023"/>
  <node id="23" lat="42.5052" lon="1.5020"/>
  <node id="30" lat="42.5035" lon="1.5045">
    <tag k="place" v="village"/>
    <tag k="name" v="Poble"/>
  </node>
  <way id="1">
    <nd ref="1"/><nd ref="2"/><nd ref="3"/><nd ref="4"/><nd ref="1"/>
    <tag k="landuse" v="forest"/>
    <tag k="name" v="Bosc"/>
  </way>
  <way id="2">
    <nd ref="10"/><nd ref="11"/><nd ref="12"/>
    <tag k="highway" v="primary"/>
    <tag k="name" v="Carrer Major"/>
  </way>
  <way id="3">
    <nd ref="12"/><nd ref="13"/>
    <tag k="highway" v="residential"/>
  </way>
  <way id="4">
    <nd ref="20"/><nd ref="21"/><nd ref="22"/><nd ref="23"/><nd ref="20"/>
    <tag k="building" v="yes"/>
    <tag k="height" v="12"/>
  </way>
</osm>
)";

fs::path writeOsm(const ScratchDir& dir, const std::string& text = kOsm) {
    fs::path path = dir / "small.osm";
    std::ofstream(path) << text;
    return path;
}

// An SRTM3 tile N42E001 at `height` m (big-endian), with sample (row, col) a void where void_at.
fs::path writeHgt(const ScratchDir& dir, std::int16_t height, bool void_at, int row = 600, int col = 600,
                  const std::string& name = "N42E001.hgt") {
    constexpr int kSide = 1201;
    std::vector<char> bytes(static_cast<std::size_t>(kSide) * kSide * 2);
    for (std::size_t i = 0; i < bytes.size(); i += 2) {
        const auto v = static_cast<std::uint16_t>(height);
        bytes[i] = static_cast<char>(v >> 8);
        bytes[i + 1] = static_cast<char>(v & 0xFF);
    }
    if (void_at) {
        const std::size_t i = (static_cast<std::size_t>(row) * kSide + col) * 2;
        bytes[i] = static_cast<char>(0x80);
        bytes[i + 1] = 0;
    }
    fs::path path = dir / name;
    std::ofstream(path, std::ios::binary).write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    return path;
}

LatLonBounds boundsOf4(double south, double west, double north, double east) {
    LatLonBounds b;
    b.grow({south, west});
    b.grow({north, east});
    return b;
}

RawRoad rawRoad(std::int64_t id, RoadClass cls, std::string name, std::vector<navmap::GeoCoordinate> points) {
    RawRoad r;
    r.id = id;
    r.cls = cls;
    r.name = std::move(name);
    r.points = std::move(points);
    return r;
}

RawPolygon square(std::int64_t id, double south, double west, double side_deg) {
    RawPolygon p;
    p.id = id;
    p.outers.push_back({{south, west},
                        {south, west + side_deg},
                        {south + side_deg, west + side_deg},
                        {south + side_deg, west},
                        {south, west}});
    return p;
}

std::vector<std::uint8_t> fileBytes(const fs::path& path) {
    std::ifstream in(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// ---- read ----

TEST(CompileStages, ReadClassifiesTheOsmObjectsIntoRawFeatures) {
    ScratchDir dir("navmap-stage-read");
    std::vector<std::string> warnings;
    CompileLog log(nullptr, warnings);
    const OsmInput in = readOsm(writeOsm(dir), {8.0f, true, nullptr}, log);
    EXPECT_EQ(in.roads, 2u);
    EXPECT_EQ(in.buildings, 1u);
    EXPECT_EQ(in.areas, 1u);
    EXPECT_EQ(in.points, 1u);
    ASSERT_EQ(in.features.roads.size(), 2u);
    EXPECT_EQ(in.features.roads[0].id, 2);
    EXPECT_EQ(in.features.roads[0].cls, RoadClass::Primary);
    EXPECT_EQ(in.features.roads[0].name, "Carrer Major");
    ASSERT_EQ(in.features.roads[0].points.size(), 3u);
    EXPECT_DOUBLE_EQ(in.features.roads[0].points[1].lat_deg, 42.502);
    EXPECT_DOUBLE_EQ(in.features.roads[0].points[1].lon_deg, 1.503);
    EXPECT_EQ(in.features.roads[1].cls, RoadClass::Residential);
    ASSERT_EQ(in.features.buildings.size(), 1u);
    EXPECT_FLOAT_EQ(in.features.buildings[0].height_m, 12.0f);
    ASSERT_EQ(in.features.areas.size(), 1u);
    EXPECT_EQ(in.features.areas[0].cls, AreaClass::Forest);
    EXPECT_EQ(in.features.areas[0].name, "Bosc");
    ASSERT_EQ(in.features.points.size(), 1u);
    EXPECT_EQ(in.features.points[0].kind, LabelKind::Place);
    EXPECT_EQ(in.features.points[0].subclass, static_cast<std::uint8_t>(PlaceClass::Village));
    EXPECT_EQ(in.features.graph_ways.size(), 2u);
    EXPECT_DOUBLE_EQ(in.bounds.south, 42.500);
    EXPECT_DOUBLE_EQ(in.bounds.north, 42.507);
    EXPECT_DOUBLE_EQ(in.bounds.west, 1.500);
    EXPECT_DOUBLE_EQ(in.bounds.east, 1.510);
    EXPECT_TRUE(in.coast.empty());
    EXPECT_TRUE(warnings.empty());
}

TEST(CompileStages, ReadWithoutTheGraphKeepsNoGraphWays) {
    ScratchDir dir("navmap-stage-read-nograph");
    std::vector<std::string> warnings;
    CompileLog log(nullptr, warnings);
    const OsmInput in = readOsm(writeOsm(dir), {8.0f, false, nullptr}, log);
    EXPECT_EQ(in.features.roads.size(), 2u);
    EXPECT_TRUE(in.features.graph_ways.empty());
}

TEST(CompileStages, ReadBoundedSpillsTheFeaturesInsteadOfKeepingThem) {
    ScratchDir dir("navmap-stage-read-spill");
    std::vector<std::string> warnings;
    CompileLog log(nullptr, warnings);
    Spill spill(dir.path(), nullptr);
    const OsmInput in = readOsm(writeOsm(dir), {8.0f, true, &spill}, log);
    EXPECT_EQ(in.roads + in.buildings + in.areas + in.points + in.places, 5u);
    EXPECT_EQ(featureCount(in.features), 0u);
    EXPECT_EQ(spill.features->records(), 5u);
    EXPECT_EQ(spill.graph->records(), 2u);
    EXPECT_FALSE(fs::exists(spill.dir / "nodes.index"));
    EXPECT_DOUBLE_EQ(in.bounds.east, 1.510);
}

TEST(CompileStages, ReadRefusesAFileWithoutMapFeatures) {
    ScratchDir dir("navmap-stage-read-empty");
    std::vector<std::string> warnings;
    CompileLog log(nullptr, warnings);
    const fs::path osm =
        writeOsm(dir, R"(<?xml version="1.0"?><osm version="0.6"><node id="1" lat="1" lon="1"/></osm>)");
    try {
        (void)readOsm(osm, {8.0f, true, nullptr}, log);
        FAIL() << "no error";
    } catch (const CompileError& e) {
        EXPECT_EQ(std::string(e.what()),
                  osm.string() + ": no map features (roads, buildings, areas, places, coastlines) found");
    }
}

TEST(CompileStages, ReadDemsLoadsFillsAndNamesFilesOfVoidsOnly) {
    ScratchDir dir("navmap-stage-dem");
    std::vector<std::string> warnings;
    CompileLog log(nullptr, warnings);
    const fs::path hgt = writeHgt(dir, 700, true);
    const DemInput dem = readDems({hgt}, 0, log);
    EXPECT_EQ(dem.dems.size(), 1u);
    EXPECT_EQ(dem.voids_filled, 1u);
    EXPECT_NEAR(dem.spacing_m, 111320.0 / 1200.0, 1e-6);
    EXPECT_TRUE(dem.all_void.empty());
    EXPECT_TRUE(warnings.empty());
    const auto h = dem.dems.sample(42.5, 1.5);  // the filled void
    ASSERT_TRUE(h.has_value());
    EXPECT_NEAR(*h, 700.0f, 1e-3);

    ScratchDir voids("navmap-stage-dem-voids");
    const DemInput none = readDems({writeHgt(voids, -32768, false)}, 0, log);
    ASSERT_EQ(none.all_void.size(), 1u);
    ASSERT_EQ(warnings.size(), 1u);
    EXPECT_EQ(warnings[0],
              "DEM N42E001.hgt: all 1442401 samples are voids: it gives no heights, its area is flat (0 m)");

    const DemInput empty = readDems({}, 0, log);
    EXPECT_TRUE(empty.dems.empty());
    EXPECT_EQ(warnings.back(), "no DEM given: terrain is flat (0 m)");
}

// ---- frame ----

TEST(CompileStages, FrameCentresTheProjectionOnTheFeaturesAndTheCoast) {
    const LatLonBounds features = boundsOf4(42.5, 1.5, 42.6, 1.6);
    const Frame plain = frameOf(features, {}, 2000.0);
    EXPECT_DOUBLE_EQ(plain.proj.originLat(), 42.55);
    EXPECT_DOUBLE_EQ(plain.proj.originLon(), 1.55);
    // The world level nearest 2000 m ground tiles at the origin.
    EXPECT_GT(plain.scheme.tileSize(plain.scheme.leafLevel()), 2000.0 / std::sqrt(2.0));
    EXPECT_LT(plain.scheme.tileSize(plain.scheme.leafLevel()), 2000.0 * std::sqrt(2.0));
    EXPECT_LT(plain.data_bounds.min_x, 0.0);
    EXPECT_GT(plain.data_bounds.max_x, 0.0);
    EXPECT_EQ(plain.grid.leaf_level, plain.scheme.leafLevel());

    RawCoastWay coast;
    coast.points = {{42.5, 1.5}, {42.7, 1.7}};
    const Frame with_coast = frameOf(features, {coast}, 2000.0);
    EXPECT_DOUBLE_EQ(with_coast.bounds.north, 42.7);
    EXPECT_DOUBLE_EQ(with_coast.proj.originLat(), 42.6);
    EXPECT_DOUBLE_EQ(with_coast.proj.originLon(), 1.6);

    const StoreInfo info = storeInfoOf(with_coast, 33);
    EXPECT_DOUBLE_EQ(info.origin_lat, 42.6);
    EXPECT_DOUBLE_EQ(info.east, 1.7);
    EXPECT_EQ(info.dem_samples, 33u);
}

// ---- assemble ----

TEST(CompileStages, AssembleMakesTheSeaAroundAnIsland) {
    const Frame frame = frameOf(boundsOf4(42.50, 1.50, 42.52, 1.52), {}, 2000.0);
    RawCoastWay island;  // counter-clockwise: land inside
    island.id = 7;
    island.first_node = island.last_node = 100;
    island.points = {{42.505, 1.505}, {42.505, 1.510}, {42.510, 1.510}, {42.510, 1.505}, {42.505, 1.505}};
    CompileStats stats;
    CompileLog log(nullptr, stats.warnings);
    const std::optional<PArea> sea = assembleSea({island}, frame, stats, log);
    ASSERT_TRUE(sea.has_value());
    EXPECT_EQ(sea->cls, AreaClass::Sea);
    EXPECT_EQ(sea->poly.outers.size(), 1u);
    EXPECT_EQ(sea->poly.inners.size(), 1u);
    EXPECT_EQ(stats.coast_ways, 1u);
    EXPECT_EQ(stats.sea_rings, 1u);
    EXPECT_EQ(stats.islands, 1u);
    EXPECT_EQ(stats.areas, 1u);
    const double box =
        (frame.data_bounds.max_x - frame.data_bounds.min_x) * (frame.data_bounds.max_y - frame.data_bounds.min_y);
    const double island_area = std::abs(ringSignedArea(project(frame.proj, island.points)));
    EXPECT_NEAR(sea->poly.area, box - island_area, 1.0);

    CompileStats none;
    CompileLog quiet(nullptr, none.warnings);
    EXPECT_FALSE(assembleSea({}, frame, none, quiet).has_value());
    EXPECT_EQ(none.areas, 0u);
}

TEST(CompileStages, AssembleJoinsTheGraphWaysAtTheirSharedNode) {
    ScratchDir dir("navmap-stage-graph");
    std::vector<std::string> warnings;
    CompileLog log(nullptr, warnings);
    const OsmInput in = readOsm(writeOsm(dir), {8.0f, true, nullptr}, log);
    const Frame frame = frameOf(in.bounds, in.coast, 2000.0);
    const RoadGraph graph = assembleGraph(in.features.graph_ways, frame.proj);
    EXPECT_EQ(graph.nodes.size(), 3u);  // nodes 10, 12 (the junction) and 13
    EXPECT_EQ(graph.edges.size(), 4u);  // two two-way edges
}

// ---- project ----

TEST(CompileStages, ProjectOrdersRoadsByClassAndDerivesTheirLabels) {
    RawFeatures raw;
    raw.roads.push_back(rawRoad(1, RoadClass::Residential, "Carrer", {{42.50, 1.50}, {42.50, 1.51}}));
    raw.roads.push_back(rawRoad(2, RoadClass::Motorway, "", {{42.51, 1.50}, {42.51, 1.51}}));
    raw.roads.back().ref = "AP-7";
    raw.roads.push_back(rawRoad(3, RoadClass::Primary, "Tunel", {{42.52, 1.50}, {42.52, 1.51}}));
    raw.roads.back().flags = road_flags::kTunnel;
    raw.roads_counted = {1, 1, 0};
    RawArea forest;
    forest.polygon = square(40, 42.50, 1.50, 0.01);
    forest.cls = AreaClass::Forest;
    forest.name = "Bosc";
    raw.areas.push_back(forest);
    RawPointLabel peak;
    peak.kind = LabelKind::Poi;
    peak.subclass = static_cast<std::uint8_t>(PoiClass::Peak);
    peak.name = "Pic";
    peak.pos = {42.505, 1.505};
    raw.points.push_back(peak);

    const Projection proj(42.5, 1.5);
    CompileStats stats;
    const ProjectedFeatures p = projectFeatures(raw, proj, nullptr, stats);
    ASSERT_EQ(p.roads.size(), 3u);
    EXPECT_EQ(p.roads[0].raw->id, 2);  // motorway, primary, residential
    EXPECT_EQ(p.roads[1].raw->id, 3);
    EXPECT_EQ(p.roads[2].raw->id, 1);
    EXPECT_NEAR(p.roads[2].pts[0].x, 0.0, 1e-6);
    EXPECT_NEAR(p.roads[2].pts[0].y, 0.0, 1e-6);
    EXPECT_NEAR(p.roads[2].pts[1].x, proj.forward(42.50, 1.51).x, 1e-9);
    EXPECT_EQ(stats.roads, 2u);  // road 3 counted in another band
    EXPECT_EQ(stats.road_vertices, 4u);
    ASSERT_EQ(p.areas.size(), 1u);
    EXPECT_GT(p.areas[0].poly.area, 0.0);
    EXPECT_EQ(stats.areas, 1u);
    // Area, point, then road labels; the tunnel has none, the motorway goes by its ref.
    ASSERT_EQ(p.labels.size(), 4u);
    EXPECT_EQ(p.labels[0].kind, LabelKind::Area);
    EXPECT_EQ(*p.labels[0].name, "Bosc");
    EXPECT_EQ(p.labels[1].kind, LabelKind::Poi);
    EXPECT_DOUBLE_EQ(p.labels[1].max_tile, 16000.0);
    EXPECT_EQ(*p.labels[2].name, "AP-7");
    EXPECT_DOUBLE_EQ(p.labels[2].max_tile, kAlways);
    EXPECT_EQ(*p.labels[3].name, "Carrer");
    EXPECT_DOUBLE_EQ(p.labels[3].max_tile, 8000.0);
    EXPECT_EQ(stats.road_labels, 2u);
    EXPECT_EQ(stats.poi_labels, 1u);
    EXPECT_EQ(stats.area_labels, 1u);
}

// ---- tile ----

struct TileFixture {
    explicit TileFixture(const LatLonBounds& bounds, int dem_samples = 0)
        : frame(frameOf(bounds, {}, 2000.0)), ctx{frame.proj, frame.scheme, frame.data_bounds, frame.grid,
                                                  dems,       90.0,         dem_samples,       nullptr,
                                                  nullptr,    ShardSpec{},  BandRange{},       {},
                                                  {}} {}
    Frame frame;
    DemMosaic dems;
    TilingContext ctx;
};

TEST(CompileStages, TileCutsARoadAtTheLeafLevelIntoTileCoordinates) {
    TileFixture f(boundsOf4(42.50, 1.50, 42.53, 1.55));
    RawFeatures raw;
    raw.roads.push_back(rawRoad(9, RoadClass::Track, "", {{42.51, 1.51}, {42.511, 1.511}}));
    CompileStats stats;
    const ProjectedFeatures p = projectFeatures(raw, f.frame.proj, nullptr, stats);
    const int leaf = f.frame.scheme.leafLevel();
    const LevelTiles lt = tileLevel(p, f.ctx, leaf, stats);
    const TileRange all = f.frame.scheme.range(leaf, f.frame.data_bounds);
    EXPECT_EQ(lt.tiles.size(), static_cast<std::size_t>(all.x1 - all.x0 + 1) * (all.y1 - all.y0 + 1));
    std::size_t roads = 0;
    for (const auto& [key, t] : lt.tiles) {
        EXPECT_EQ(t.id.key(), key);
        EXPECT_DOUBLE_EQ(t.size_m, f.frame.scheme.tileSize(leaf));
        EXPECT_TRUE(t.dem.heights.empty());  // no DEM grid asked for
        for (const Road& r : t.roads) {
            ++roads;
            EXPECT_EQ(r.osm_id, 9);
            EXPECT_EQ(r.cls, RoadClass::Track);
        }
    }
    // About 140 m long: in one tile, or clipped into one piece in each of two.
    EXPECT_GE(roads, 1u);
    EXPECT_LE(roads, 2u);
    const PlanarPoint a = f.frame.proj.forward(42.51, 1.51);
    const auto first = f.frame.scheme.tileAt(leaf, a);
    ASSERT_TRUE(first.has_value());
    const Tile& t = lt.tiles.at(first->key());
    ASSERT_EQ(t.roads.size(), 1u);
    EXPECT_NEAR(t.roads[0].points[0].x, a.x - t.origin_x, 1e-2);
    EXPECT_NEAR(t.roads[0].points[0].y, a.y - t.origin_y, 1e-2);
    // A track is a leaf-only road: none above the leaf level.
    const LevelTiles above = tileLevel(p, f.ctx, leaf - 1, stats);
    for (const auto& [key, tile] : above.tiles) EXPECT_TRUE(tile.roads.empty());
}

TEST(CompileStages, TileGivesEveryTileADemGridAndCountsLeavesWithoutOne) {
    TileFixture f(boundsOf4(42.50, 1.50, 42.51, 1.51), 5);
    CompileStats stats;
    const LevelTiles lt = tileLevel(ProjectedFeatures{}, f.ctx, f.frame.scheme.leafLevel(), stats);
    ASSERT_FALSE(lt.tiles.empty());
    for (const auto& [key, t] : lt.tiles) {
        EXPECT_EQ(t.dem.size, 5u);
        EXPECT_EQ(t.dem.heights.size(), 25u);
        EXPECT_FLOAT_EQ(t.dem.coverage, 0.0f);  // the mosaic is empty
    }
    EXPECT_EQ(stats.tiles_without_dem, lt.tiles.size());
}

TEST(CompileStages, TileFeaturesEmitsEveryLevelInKeyOrder) {
    TileFixture f(boundsOf4(42.50, 1.50, 42.53, 1.55));
    RawFeatures raw;
    raw.roads.push_back(rawRoad(5, RoadClass::Motorway, "A", {{42.50, 1.50}, {42.53, 1.55}}));
    std::vector<TileId> emitted;
    f.ctx.emit = [&](const Tile& t) { emitted.push_back(t.id); };
    CompileStats stats;
    stats.tiles_per_level.assign(static_cast<std::size_t>(f.frame.scheme.levelCount()), 0);
    tileFeatures(raw, f.ctx, stats);
    EXPECT_EQ(emitted.size(), stats.tiles);
    EXPECT_TRUE(std::is_sorted(emitted.begin(), emitted.end(),
                               [](const TileId& a, const TileId& b) { return a.key() < b.key(); }));
    EXPECT_EQ(stats.tiles_per_level.front(), 1u);
    EXPECT_EQ(emitted.front().level, 0);
    EXPECT_EQ(emitted.back().level, f.frame.scheme.leafLevel());
    EXPECT_EQ(stats.roads, 1u);
    EXPECT_EQ(stats.road_labels, 1u);
}

// ---- band ----

TEST(CompileStages, BandsAreTheLongestRunsOfFineBandsWithinTheBudget) {
    // Four fine bands of 10, 10, 30, 10 bytes (features within one band each).
    const std::vector<std::uint64_t> bytes{10, 10, 30, 10};
    const std::vector<BandRange> bands = bandsWithin(bytes, bytes, 25);
    ASSERT_EQ(bands.size(), 3u);
    EXPECT_EQ(bands[0].first, 0);
    EXPECT_EQ(bands[0].last, 1);
    EXPECT_EQ(bands[1].first, 2);  // over the budget on its own: a band of its own
    EXPECT_EQ(bands[1].last, 2);
    EXPECT_EQ(bands[2].first, 3);
    EXPECT_EQ(bands[2].last, 3);
    EXPECT_EQ(bands[2].count, 4);
    // A feature over fine bands 0..3 counts in every run.
    EXPECT_EQ(bandsWithin({40, 0, 0, 0}, {0, 0, 0, 40}, 39).size(), 4u);
    EXPECT_EQ(bandsWithin({40, 0, 0, 0}, {0, 0, 0, 40}, 40).size(), 1u);
}

TEST(CompileStages, BandsOfAFeatureAreTheColumnsItsTilesLieIn) {
    const Frame frame = frameOf(boundsOf4(42.0, 1.0, 42.1, 2.0), {}, 2000.0);
    RawFeatures west;
    west.roads.push_back(rawRoad(1, RoadClass::Track, "", {{42.05, 1.01}, {42.05, 1.02}}));
    RawFeatures east;
    east.roads.push_back(rawRoad(2, RoadClass::Track, "", {{42.05, 1.98}, {42.05, 1.99}}));
    const auto w = featureBands(west, frame.proj, frame.scheme, frame.grid, 8);
    const auto e = featureBands(east, frame.proj, frame.scheme, frame.grid, 8);
    ASSERT_EQ(w.size(), 1u);  // leaf only: one range
    ASSERT_EQ(e.size(), 1u);
    EXPECT_EQ(w[0].first, 0);
    EXPECT_EQ(w[0].second, 0);
    EXPECT_EQ(e[0].first, 7);
    EXPECT_EQ(e[0].second, 7);
    // A motorway shows on every level: its ranges reach the coarse tiles' bands.
    RawFeatures motorway;
    motorway.roads.push_back(rawRoad(3, RoadClass::Motorway, "", {{42.05, 1.01}, {42.05, 1.02}}));
    const auto m = featureBands(motorway, frame.proj, frame.scheme, frame.grid, 8);
    ASSERT_FALSE(m.empty());
    EXPECT_EQ(m.front().first, 0);
    EXPECT_GT(m.back().second, 0);  // the coarse tiles are built by the band of their centre
}

TEST(CompileStages, BandPlanAndSplitPutEachFeatureInTheBandsThatTileIt) {
    ScratchDir dir("navmap-stage-band");
    std::vector<std::string> warnings;
    CompileLog log(nullptr, warnings);
    Spill spill(dir.path(), nullptr);
    const OsmInput in = readOsm(writeOsm(dir), {8.0f, true, &spill}, log);
    const Frame frame = frameOf(in.bounds, in.coast, 2000.0);
    const BandPlan plan = planBands(spill.dir, frame, ShardSpec{}, std::uint64_t{64} << 20);
    ASSERT_EQ(plan.bands.size(), 1u);  // 5 small features: one band
    EXPECT_EQ(plan.bands[0].first, 0);
    EXPECT_EQ(plan.bands[0].last, kMaxBands - 1);
    EXPECT_EQ(plan.used, std::vector<char>{1});
    EXPECT_EQ(plan.budget, static_cast<std::uint64_t>((64.0 * 1048576) / 2.0 / kMemoryPerSpilledByte));
    splitIntoBands(spill.dir, plan);
    EXPECT_FALSE(fs::exists(spill.dir / "features.spill"));
    std::uint64_t bytes = 0;
    const RawFeatures band = readBand(spill.dir, 0, bytes);
    EXPECT_GT(bytes, 0u);
    EXPECT_EQ(featureCount(band), 5u);
    EXPECT_EQ(band.roads.size(), 2u);
    EXPECT_EQ(band.roads_counted, (std::vector<char>{1, 1}));  // counted in their first band
    EXPECT_FALSE(fs::exists(spill.dir / "band-0.spill"));
}

// ---- write ----

TEST(CompileStages, WriteInMemoryAndFromBandsGiveTheSameStore) {
    ScratchDir dir("navmap-stage-write");
    std::vector<std::string> warnings;
    CompileLog log(nullptr, warnings);
    const fs::path osm = writeOsm(dir);

    CompileStats mem_stats;
    OsmInput mem = readOsm(osm, {8.0f, true, nullptr}, log);
    const Frame frame = frameOf(mem.bounds, mem.coast, 500.0);
    DemInput dem;
    TilingContext ctx{frame.proj, frame.scheme, frame.data_bounds, frame.grid,  dem.dems, 90.0, 0,
                      nullptr,    nullptr,      ShardSpec{},       BandRange{}, {},       {}};
    mem_stats.tiles_per_level.assign(static_cast<std::size_t>(frame.scheme.levelCount()), 0);
    const StoreInfo info = storeInfoOf(frame, 0);
    const std::uint64_t mem_bytes =
        writeInMemory(StoreLock(dir / "mem.navmap"), info, mem.features, true, ctx, mem_stats, log);
    EXPECT_EQ(mem_bytes, fs::file_size(dir / "mem.navmap"));
    EXPECT_EQ(mem_stats.graph_nodes, 3u);
    EXPECT_EQ(mem_stats.buildings, 1u);
    EXPECT_GT(mem_stats.tiles, 0u);

    CompileStats band_stats;
    band_stats.tiles_per_level.assign(static_cast<std::size_t>(frame.scheme.levelCount()), 0);
    Spill spill(dir.path(), nullptr);
    (void)readOsm(osm, {8.0f, true, &spill}, log);
    DemInput band_dem;
    TilingContext band_ctx{frame.proj, frame.scheme, frame.data_bounds, frame.grid,  band_dem.dems, 90.0,
                           0,          nullptr,      nullptr,           ShardSpec{}, BandRange{},   {},
                           {}};
    const std::uint64_t band_bytes =
        writeBounded(StoreLock(dir / "band.navmap"), info, spill, band_dem, 64, true, frame, band_ctx, band_stats, log);
    EXPECT_EQ(band_bytes, mem_bytes);
    EXPECT_EQ(band_stats.tiles, mem_stats.tiles);
    EXPECT_EQ(band_stats.graph_edges, mem_stats.graph_edges);
    EXPECT_EQ(band_stats.features_per_band, std::vector<std::size_t>{5});
    EXPECT_EQ(fileBytes(dir / "band.navmap"), fileBytes(dir / "mem.navmap"));
    EXPECT_TRUE(warnings.empty());
}

TEST(CompileStages, WriteWarnsAboutLeafTilesTheDemDoesNotCover) {
    std::vector<std::string> warnings;
    CompileLog log(nullptr, warnings);
    CompileStats stats;
    stats.tiles_per_level = {1, 4};
    stats.dem_files = 1;
    DemInput dem;
    warnDemCoverage(stats, dem, log);
    EXPECT_TRUE(warnings.empty());  // every tile covered
    stats.tiles_without_dem = 3;
    warnDemCoverage(stats, dem, log);
    dem.all_void.push_back("N42E001.hgt");
    warnDemCoverage(stats, dem, log);
    ASSERT_EQ(warnings.size(), 2u);
    EXPECT_EQ(warnings[0], "3 of 4 leaf tiles lie partly outside the DEM; missing areas are flat (0 m)");
    EXPECT_EQ(warnings[1],
              "3 of 4 leaf tiles have no heights: the DEM is all voids (N42E001.hgt); terrain is flat (0 m)");
}

}  // namespace
