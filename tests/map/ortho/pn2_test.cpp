// SPDX-License-Identifier: Apache-2.0
// Marble's .pn2 polygon files (map/include/navmap/map/ortho/pn2.h): hand-made files of every
// record kind, damaged ones, and every file of the Debian package read to its last byte.

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>

#include "navmap/map/compile/ortho/marble_inputs.h"
#include "navmap/map/ortho/natural_earth.h"
#include "navmap/map/ortho/pn2.h"

namespace {

using namespace navmap::map::ortho;

struct Bytes {
    std::vector<std::uint8_t> b;
    Bytes& u8(int v) {
        b.push_back(static_cast<std::uint8_t>(v));
        return *this;
    }
    Bytes& u32(std::uint32_t v) {
        for (int s = 24; s >= 0; s -= 8) b.push_back(static_cast<std::uint8_t>(v >> s));
        return *this;
    }
    Bytes& i16(int v) {
        b.push_back(static_cast<std::uint8_t>((v >> 8) & 0xff));
        b.push_back(static_cast<std::uint8_t>(v & 0xff));
        return *this;
    }
    /// A node at (lat, lon) in 1/120 degree with child offsets.
    Bytes& node(int lat, int lon, const std::vector<std::pair<int, int>>& children = {}) {
        i16(lat).i16(lon).i16(static_cast<int>(children.size()));
        for (auto [a, o] : children) u8(a & 0xff).u8(o & 0xff);
        return *this;
    }
};

std::string error(const std::vector<std::uint8_t>& b) {
    try {
        (void)parsePn2(b, "t.pn2");
    } catch (const Pn2Error& e) {
        return e.what();
    }
    return "";
}

TEST(Pn2, ReadsEveryRecordKind) {
    Bytes f;
    f.u8(2).u32(5).u8(0);
    // Outer boundary: one node with three children relative to it (not to each other).
    f.u8(2).u32(1).u32(1).node(120, 240, {{0, 12}, {12, 12}, {12, 0}});
    f.u8(3).u32(1).u32(1).node(3, 243, {{0, 3}, {3, 3}, {3, 0}});  // its hole
    f.u8(4).u32(7).u8(2);                                          // multi-geometry of two parts
    f.u8(1).u32(7).u32(1).node(-120, -240, {{0, 6}, {6, 6}});
    f.u8(1).u32(7).u32(1).node(-240, -240, {{0, 6}, {6, 6}});
    f.u8(0).u32(9).u32(2).node(0, 0).node(60, 60);  // a line of two nodes
    const Pn2File p = parsePn2(f.b, "t.pn2");
    EXPECT_EQ(p.records, 5u);
    ASSERT_EQ(p.polygons.size(), 3u);
    ASSERT_EQ(p.polygons[0].outer.size(), 4u);
    EXPECT_DOUBLE_EQ(p.polygons[0].outer[0].lat_deg, 1.0);
    EXPECT_DOUBLE_EQ(p.polygons[0].outer[0].lon_deg, 2.0);
    EXPECT_DOUBLE_EQ(p.polygons[0].outer[2].lat_deg, 1.1);  // 120 + 12
    EXPECT_DOUBLE_EQ(p.polygons[0].outer[2].lon_deg, 2.1);
    ASSERT_EQ(p.polygons[0].holes.size(), 1u);
    EXPECT_EQ(p.polygons[0].holes[0].size(), 4u);
    EXPECT_EQ(p.polygons[1].id, 7u);
    EXPECT_DOUBLE_EQ(p.polygons[2].outer[0].lat_deg, -2.0);
    ASSERT_EQ(p.lines.size(), 1u);
    EXPECT_DOUBLE_EQ(p.lines[0][1].lon_deg, 0.5);
}

TEST(Pn2, ColourIndexFollowsTheIdExceptForHoles) {
    Bytes f;
    f.u8(2).u32(2).u8(1);
    f.u8(2).u32(1).u8(9).u32(1).node(0, 0, {{0, 1}, {1, 1}});
    f.u8(3).u32(1).u32(1).node(0, 0, {{0, 1}, {1, 0}});
    const Pn2File p = parsePn2(f.b, "t.pn2");
    ASSERT_EQ(p.polygons.size(), 1u);
    EXPECT_EQ(p.polygons[0].holes.size(), 1u);
}

TEST(Pn2, PartsOfAMultiGeometryHaveNoColourIndex) {
    // As in ne_50m_admin_0_countries.pn2: the multi-geometry carries the colour, its two parts
    // (an outer boundary and its hole) do not; a plain polygon after it has its own again.
    Bytes f;
    f.u8(2).u32(3).u8(1);
    f.u8(4).u32(3).u8(5).u8(2);
    f.u8(2).u32(3).u32(1).node(0, 0, {{0, 12}, {12, 12}, {12, 0}});
    f.u8(3).u32(3).u32(1).node(3, 3, {{0, 3}, {3, 3}, {3, 0}});
    f.u8(2).u32(4).u8(6).u32(1).node(120, 120, {{0, 1}, {1, 1}});
    const Pn2File p = parsePn2(f.b, "t.pn2");
    EXPECT_EQ(p.records, 3u);
    ASSERT_EQ(p.polygons.size(), 2u);
    EXPECT_EQ(p.polygons[0].id, 3u);
    EXPECT_EQ(p.polygons[0].holes.size(), 1u);
    EXPECT_EQ(p.polygons[1].id, 4u);
    EXPECT_DOUBLE_EQ(p.polygons[1].outer[0].lat_deg, 1.0);
}

TEST(Pn2, DamagedFilesAreClearErrors) {
    Bytes good;
    good.u8(2).u32(1).u8(0).u8(2).u32(1).u32(1).node(0, 0, {{0, 1}, {1, 1}});
    auto truncated = good.b;
    truncated.resize(truncated.size() - 1);
    EXPECT_EQ(error(truncated), "t.pn2: truncated at byte 24 (child longitude)");
    auto v1 = good.b;
    v1[0] = 1;
    EXPECT_EQ(error(v1), "t.pn2: unsupported .pn2 version 1 (this reader reads version 2) at byte 1");
    auto kind = good.b;
    kind[6] = 7;
    EXPECT_EQ(error(kind), "t.pn2: unknown record kind 7 at byte 11");
    auto extra = good.b;
    extra.push_back(0);
    EXPECT_EQ(error(extra), "t.pn2: 1 bytes after the last of 1 records at byte 25");
    Bytes range;
    range.u8(2).u32(1).u8(0).u8(0).u32(1).u32(1).node(91 * 120, 0);
    EXPECT_NE(error(range.b).find("coordinate out of range (lat 91"), std::string::npos) << error(range.b);
    Bytes hole;
    hole.u8(2).u32(1).u8(0).u8(3).u32(1).u32(1).node(0, 0);
    EXPECT_EQ(error(hole.b), "t.pn2: inner boundary without an outer boundary before it at byte 21");
    Bytes huge;
    huge.u8(2).u32(1).u8(0).u8(2).u32(1).u32(0x7fffffff);
    EXPECT_EQ(error(huge.b), "t.pn2: node count 2147483647 exceeds the file at byte 15");
    EXPECT_EQ(error({}), "t.pn2: truncated at byte 0 (header)");
}

TEST(Pn2, ScanlinesFillPolygonsAndKeepHolesOpen) {
    // A 4 x 4 degree square with a 2 x 2 degree hole.
    Pn2Polygon square{1, {{0, 0}, {0, 4}, {4, 4}, {4, 0}}, {{{1, 1}, {1, 3}, {3, 3}, {3, 1}}}};
    const PolygonLayer layer({square});
    GeoWindow w;
    w.south = -1;
    w.north = 5;
    w.west = -1;
    w.east = 5;
    w.width = w.height = 6;  // one degree per pixel, centres at .5
    std::vector<std::uint8_t> out(36, 0);
    layer.paint(w, 1, out);
    for (int r = 0; r < 6; ++r) {
        for (int c = 0; c < 6; ++c) {
            const double lat = w.lat(r), lon = w.lon(c);
            const bool in_square = lat > 0 && lat < 4 && lon > 0 && lon < 4;
            const bool in_hole = lat > 1 && lat < 3 && lon > 1 && lon < 3;
            EXPECT_EQ(out[static_cast<std::size_t>(r * 6 + c)], (in_square && !in_hole) ? 1 : 0) << lat << ", " << lon;
        }
    }
}

TEST(Pn2, EveryNaturalEarthFileOfMarbleReadsToItsEnd) {
    const auto dir = kDebianMarbleData / "naturalearth";
    if (!std::filesystem::exists(dir))
        GTEST_SKIP() << dir << " is absent (Debian package marble-qt-data, scripts/install-deps.sh)";
    int files = 0;
    for (const auto& e : std::filesystem::directory_iterator(dir)) {
        if (e.path().extension() != ".pn2") continue;
        ++files;
        Pn2File p;
        ASSERT_NO_THROW(p = readPn2(e.path())) << e.path();
        EXPECT_GT(p.records, 0u) << e.path();
    }
    EXPECT_GE(files, 16);
    const Pn2File land = readPn2(dir / "ne_50m_land.pn2");
    EXPECT_EQ(land.polygons.size(), 1420u);  // outer boundaries; the one inner boundary is a hole
    // A cut file is refused with the byte where it ends.
    std::ifstream in(dir / "ne_50m_lakes.pn2", std::ios::binary);
    std::vector<std::uint8_t> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    bytes.resize(bytes.size() / 2);
    // (the last node count that still fits, or the bytes of a node, run past the end)
    const std::string e = error(bytes);
    EXPECT_TRUE(e.starts_with("t.pn2: truncated at byte") ||
                (e.starts_with("t.pn2: node count ") && e.find(" exceeds the file at byte ") != std::string::npos))
        << e;
}

TEST(NaturalEarth, ClassesOfKnownPlaces) {
    if (!std::filesystem::exists(kDebianMarbleData / "naturalearth")) GTEST_SKIP() << "marble-qt-data is absent";
    const NaturalEarthCover cover = NaturalEarthCover::load(kDebianMarbleData);
    auto at = [&](double lat, double lon) {
        GeoWindow w;
        w.south = lat - 0.005;
        w.north = lat + 0.005;
        w.west = lon - 0.005;
        w.east = lon + 0.005;
        w.width = w.height = 1;
        return static_cast<GlobalCover>(cover.rasterize(w)[0]);
    };
    EXPECT_EQ(at(42.5, 1.55), GlobalCover::Land);         // Andorra
    EXPECT_EQ(at(0.0, -30.0), GlobalCover::Ocean);        // Atlantic
    EXPECT_EQ(at(46.45, 6.55), GlobalCover::Lake);        // Lake Geneva
    EXPECT_EQ(at(75.0, -40.0), GlobalCover::Glacier);     // Greenland
    EXPECT_EQ(at(48.86, 2.35), GlobalCover::Urban);       // Paris
    EXPECT_EQ(at(-80.0, -170.0), GlobalCover::IceShelf);  // Ross ice shelf
    EXPECT_EQ(at(40.2, -113.5), GlobalCover::Playa);      // Great Salt Lake Desert
}

}  // namespace
