// SPDX-License-Identifier: Apache-2.0
// The spill files of the bounded-memory compile: records and raw features round-trip exactly; a
// truncated, damaged or foreign file is an error naming the file and the byte.
#include <gtest/gtest.h>

#include <fstream>

#include "feature_spill.h"
#include "map_test_util.h"
#include "navmap/map/compile/spill_file.h"

using namespace navmap::map;
using namespace navmap::map::detail;
using navmap::map::test::ScratchDir;
using navmap::map::test::withFileSizeLimit;

namespace {

namespace fs = std::filesystem;

std::vector<std::uint8_t> bytesOf(const std::string& s) { return {s.begin(), s.end()}; }

/// The message of the SpillError `f` throws ("" when it throws none).
template <typename F>
std::string spillError(F&& f) {
    try {
        f();
    } catch (const SpillError& e) {
        return e.what();
    }
    return {};
}

void writeRecords(const fs::path& path, const std::vector<std::string>& records) {
    SpillWriter w(path, 16);  // a small buffer: several write() calls
    for (const auto& r : records) w.append(bytesOf(r));
    w.close();
}

std::vector<std::string> readAll(const fs::path& path) {
    SpillReader r(path);
    std::vector<std::string> out;
    std::vector<std::uint8_t> payload;
    while (r.next(payload)) out.emplace_back(payload.begin(), payload.end());
    return out;
}

void overwriteByte(const fs::path& path, std::uint64_t at, char value) {
    std::fstream f(path, std::ios::in | std::ios::out | std::ios::binary);
    f.seekp(static_cast<std::streamoff>(at));
    f.put(value);
}

}  // namespace

TEST(SpillFile, RecordsComeBackInOrderAndByOffset) {
    ScratchDir dir("spill");
    const std::vector<std::string> records = {"first", "", std::string(100000, 'x'), std::string("last\0byte", 9)};
    std::vector<std::uint64_t> offsets;
    {
        SpillWriter w(dir / "a.spill", 64);
        for (const auto& r : records) offsets.push_back(w.append(bytesOf(r)));
        EXPECT_EQ(w.records(), 4u);
        w.close();
        EXPECT_EQ(w.bytes(), fs::file_size(dir / "a.spill"));
    }
    EXPECT_EQ(readAll(dir / "a.spill"), records);
    // 8 bytes of magic, then 8 bytes of length and CRC before each payload.
    EXPECT_EQ(offsets[0], 8u);
    EXPECT_EQ(offsets[1], 8u + 8u + 5u);
    SpillReader r(dir / "a.spill");
    std::vector<std::uint8_t> payload;
    r.readAt(offsets[3], payload);
    EXPECT_EQ(std::string(payload.begin(), payload.end()), records[3]);
    r.readAt(offsets[2], payload);
    EXPECT_EQ(payload.size(), 100000u);
    // An empty file of records: the header only.
    writeRecords(dir / "empty.spill", {});
    EXPECT_TRUE(readAll(dir / "empty.spill").empty());
    EXPECT_EQ(fs::file_size(dir / "empty.spill"), 8u);
}

TEST(SpillFile, TruncatedDamagedAndForeignFilesNameTheFileAndTheByte) {
    ScratchDir dir("spill-bad");
    const fs::path path = dir / "f.spill";
    writeRecords(path, {"abcdef", "ghijkl"});  // records at 8 and 22, file of 36 bytes
    ASSERT_EQ(fs::file_size(path), 36u);

    fs::resize_file(path, 30);  // inside the second payload
    EXPECT_EQ(spillError([&] { readAll(path); }),
              path.string() + ": truncated: the record at byte 30 needs 6 bytes, the file ends at 30");
    fs::resize_file(path, 25);  // inside the second record's header
    EXPECT_EQ(spillError([&] { readAll(path); }),
              path.string() + ": truncated: the record header at byte 22 needs 8 bytes, the file ends at 25");

    writeRecords(dir / "g.spill", {"abcdef", "ghijkl"});
    overwriteByte(dir / "g.spill", 31, 'X');  // a payload byte of the second record
    EXPECT_EQ(spillError([&] { readAll(dir / "g.spill"); }),
              (dir / "g.spill").string() + ": damaged: checksum mismatch in the record at byte 22");
    // The first record still reads: the damage is found where it is.
    SpillReader g(dir / "g.spill");
    std::vector<std::uint8_t> payload;
    EXPECT_TRUE(g.next(payload));
    EXPECT_EQ(std::string(payload.begin(), payload.end()), "abcdef");

    writeRecords(dir / "h.spill", {"abcdef"});
    overwriteByte(dir / "h.spill", 11, '\x7f');  // the length's top byte: ~2 GiB
    EXPECT_EQ(spillError([&] { readAll(dir / "h.spill"); }),
              (dir / "h.spill").string() + ": damaged: the record at byte 8 claims 2130706438 bytes");

    std::ofstream(dir / "foreign.spill") << "PK\x03\x04 not a spill file";
    EXPECT_EQ(spillError([&] { SpillReader r(dir / "foreign.spill"); }),
              (dir / "foreign.spill").string() + ": not a spill file (no NMSPILL1 header)");
    std::ofstream(dir / "short.spill") << "NMS";
    EXPECT_EQ(spillError([&] { SpillReader r(dir / "short.spill"); }),
              (dir / "short.spill").string() + ": not a spill file (3 bytes, no header)");
    EXPECT_EQ(spillError([&] { SpillReader r(dir / "absent.spill"); }),
              "open(" + (dir / "absent.spill").string() + "): No such file or directory");
}

TEST(SpillFile, UnwritablePlacesAndExistingFilesAreErrorsNamingThePath) {
    ScratchDir dir("spill-write");
    EXPECT_EQ(spillError([&] { SpillWriter w(dir / "no-such-folder" / "a.spill"); }),
              "open(" + (dir / "no-such-folder" / "a.spill").string() + "): No such file or directory");
    writeRecords(dir / "a.spill", {"x"});
    // Never reuses a file that is there already (something planted in the spill folder).
    EXPECT_EQ(spillError([&] { SpillWriter w(dir / "a.spill"); }),
              "open(" + (dir / "a.spill").string() + "): File exists");
}

TEST(SpillFile, AFullDiskIsAnErrorNamingTheFile) {
    // RLIMIT_FSIZE stands in for a full disk (withFileSizeLimit).
    ScratchDir dir("spill-full");
    const fs::path path = dir / "big.spill";
    std::string error;
    ASSERT_TRUE(withFileSizeLimit(4096, [&] {
        error = spillError([&] {
            SpillWriter w(path, 1024);
            for (int i = 0; i < 100; ++i) w.append(std::vector<std::uint8_t>(1000, 7));
            w.close();
        });
    }));
    EXPECT_EQ(error, "write(" + path.string() + "): File too large");
}

TEST(FeatureSpill, EveryKindOfFeatureRoundTripsExactly) {
    RawRoad road;
    road.id = 4'000'000'123;
    road.cls = RoadClass::Secondary;
    road.flags = 0x5;
    road.layer = -2;
    road.maxspeed = 90;
    road.name =
        "Carretera General d\xE2\x80\x99"
        "Andorra";
    road.ref = "CG-1";
    road.points = {{42.5063, 1.5218}, {42.50631234567891, 1.52190000000001}, {-89.9, -179.9}};
    RawBuilding building;
    building.polygon.id = -77;  // a relation's area id
    building.polygon.outers = {{{1, 2}, {3, 4}, {5, 6}}, {{7, 8}, {9, 10}, {11, 12}}};
    building.polygon.inners = {{{1.5, 2.5}, {3.5, 4.5}, {5.5, 6.5}}};
    building.height_m = 12.5f;
    building.min_height_m = 3.0f;
    RawArea area;
    area.polygon.id = 99;
    area.polygon.outers = {{{0.1, 0.2}, {0.3, 0.4}, {0.5, 0.6}, {0.7, 0.8}}};
    area.cls = AreaClass::Water;
    area.name = "Estany";
    RawPointLabel point;
    point.kind = LabelKind::Poi;
    point.subclass = static_cast<std::uint8_t>(PoiClass::Peak);
    point.name = "Coma Pedrosa";
    point.pos = {42.5917, 1.4440};
    point.importance = 0.625f;
    point.id = 26864263;
    RawAreaLabel place;
    place.polygon.id = 5;
    place.polygon.outers = {{{42, 1}, {42.1, 1}, {42.1, 1.1}}};
    place.subclass = static_cast<std::uint8_t>(PlaceClass::Village);
    place.name = "Ordino";
    place.importance = 0.4f;
    RawGraphWay way;
    way.id = 8;
    way.cls = RoadClass::Primary;
    way.flags = 2;
    way.speed_kmh = 67.5f;
    way.limit_forward_kmh = 50;
    way.limit_backward_kmh = 300;
    way.lanes_forward = {lane_arrow::kLeft, 0, lane_arrow::kThrough | lane_arrow::kRight};
    way.lanes_backward = {lane_arrow::kMergeToRight};
    way.oneway = true;
    way.nodes = {9'000'000'000, 12, 9'000'000'001, -3};  // deltas of both signs
    way.points = {{42, 1}, {42.001, 1.001}, {42.002, 1.002}, {42.003, 1.003}};

    RawFeatures out;
    std::string error;
    for (const auto& record : {encodeFeature(road), encodeFeature(building), encodeFeature(area), encodeFeature(point),
                               encodeFeature(place), encodeFeature(way)}) {
        ASSERT_TRUE(decodeFeature(record, out, error)) << error;
    }
    ASSERT_EQ(out.roads.size(), 1u);
    const RawRoad& r = out.roads[0];
    EXPECT_EQ(r.id, road.id);
    EXPECT_EQ(r.cls, road.cls);
    EXPECT_EQ(r.flags, road.flags);
    EXPECT_EQ(r.layer, road.layer);
    EXPECT_EQ(r.maxspeed, road.maxspeed);
    EXPECT_EQ(r.name, road.name);
    EXPECT_EQ(r.ref, road.ref);
    ASSERT_EQ(r.points.size(), road.points.size());
    for (std::size_t i = 0; i < r.points.size(); ++i) {
        EXPECT_EQ(r.points[i].lat_deg, road.points[i].lat_deg);  // bit for bit, not near
        EXPECT_EQ(r.points[i].lon_deg, road.points[i].lon_deg);
    }
    ASSERT_EQ(out.buildings.size(), 1u);
    EXPECT_EQ(out.buildings[0].polygon.id, -77);
    ASSERT_EQ(out.buildings[0].polygon.outers.size(), 2u);
    EXPECT_EQ(out.buildings[0].polygon.outers[1][2].lon_deg, 12.0);
    ASSERT_EQ(out.buildings[0].polygon.inners.size(), 1u);
    EXPECT_EQ(out.buildings[0].polygon.inners[0][1].lat_deg, 3.5);
    EXPECT_EQ(out.buildings[0].height_m, 12.5f);
    EXPECT_EQ(out.buildings[0].min_height_m, 3.0f);
    ASSERT_EQ(out.areas.size(), 1u);
    EXPECT_EQ(out.areas[0].cls, AreaClass::Water);
    EXPECT_EQ(out.areas[0].name, "Estany");
    EXPECT_EQ(out.areas[0].polygon.outers[0].size(), 4u);
    ASSERT_EQ(out.points.size(), 1u);
    EXPECT_EQ(out.points[0].kind, LabelKind::Poi);
    EXPECT_EQ(out.points[0].subclass, point.subclass);
    EXPECT_EQ(out.points[0].name, "Coma Pedrosa");
    EXPECT_EQ(out.points[0].pos.lat_deg, 42.5917);
    EXPECT_EQ(out.points[0].importance, 0.625f);
    EXPECT_EQ(out.points[0].id, 26864263);
    ASSERT_EQ(out.places.size(), 1u);
    EXPECT_EQ(out.places[0].name, "Ordino");
    EXPECT_EQ(out.places[0].subclass, place.subclass);
    EXPECT_EQ(out.places[0].importance, 0.4f);
    ASSERT_EQ(out.graph_ways.size(), 1u);
    EXPECT_EQ(out.graph_ways[0].nodes, way.nodes);
    EXPECT_TRUE(out.graph_ways[0].oneway);
    EXPECT_EQ(out.graph_ways[0].speed_kmh, 67.5f);
    EXPECT_EQ(out.graph_ways[0].limit_forward_kmh, 50);
    EXPECT_EQ(out.graph_ways[0].limit_backward_kmh, 300);
    EXPECT_EQ(out.graph_ways[0].lanes_forward, way.lanes_forward);
    EXPECT_EQ(out.graph_ways[0].lanes_backward, way.lanes_backward);
    EXPECT_EQ(out.graph_ways[0].points.size(), 4u);
    // Counted where first given to a band, not where repeated.
    auto repeated = encodeFeature(road);
    repeated[0] |= kRepeatFlag;
    ASSERT_TRUE(decodeFeature(repeated, out, error)) << error;
    EXPECT_EQ(out.roads_counted, (std::vector<char>{1, 0}));
    EXPECT_EQ(out.roads[1].name, road.name);
}

TEST(FeatureSpill, DamagedRecordsAreRefusedWithTheReason) {
    RawRoad road;
    road.name = "x";
    road.points = {{1, 2}, {3, 4}};
    const auto good = encodeFeature(road);
    RawFeatures out;
    std::string error;
    // Cut anywhere: never a feature, never a read past the end.
    for (std::size_t n = 0; n < good.size(); ++n) {
        const std::vector<std::uint8_t> cut(good.begin(), good.begin() + static_cast<std::ptrdiff_t>(n));
        EXPECT_FALSE(decodeFeature(cut, out, error)) << n;
        EXPECT_FALSE(error.empty());
    }
    EXPECT_TRUE(out.roads.empty());
    std::vector<std::uint8_t> unknown = good;
    unknown[0] = 9;
    EXPECT_FALSE(decodeFeature(unknown, out, error));
    EXPECT_EQ(error, "unknown feature tag 9");
    std::vector<std::uint8_t> longer = good;
    longer.push_back(0);
    EXPECT_FALSE(decodeFeature(longer, out, error));
    EXPECT_EQ(error, "1 bytes left over after the feature");
    // A vertex count far beyond the record.
    std::vector<std::uint8_t> huge = good;
    huge[huge.size() - 33] = 0xff;  // the count's byte before the two points (a one-byte varint: 2)
    EXPECT_FALSE(decodeFeature(huge, out, error));
    EXPECT_NE(error.find("beyond the record"), std::string::npos) << error;
}
