// SPDX-License-Identifier: Apache-2.0
// The orthoimage input layers in the tile store (store format version 2, docs/tile-store.md): round
// trip in the tile payload, layers of the wrong size refused with a clear error, version 1 stores
// and payloads still read (without layers), and a store compiled with the global inputs.

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "map_test_util.h"
#include "navmap/map/compile/compiler.h"
#include "navmap/map/compile/ortho/marble_inputs.h"
#include "navmap/map/compile/ortho/ortho_preprocess.h"
#include "navmap/map/compile/store_writer.h"
#include "navmap/map/ortho/climate.h"
#include "navmap/map/ortho/super_land_cover.h"
#include "navmap/map/projection.h"
#include "navmap/map/tile_codec.h"
#include "navmap/map/tile_store.h"

namespace {

using namespace navmap::map;
using navmap::map::test::repoData;
using navmap::map::test::sampleTile;
using navmap::map::test::ScratchDir;
namespace fs = std::filesystem;

void addLayers(Tile& t, int cover, int grid) {
    ortho::OrthoLayers& o = t.ortho;
    o.cover_size = static_cast<std::uint16_t>(cover);
    o.grid_size = static_cast<std::uint16_t>(grid);
    o.cover.resize(static_cast<std::size_t>(cover) * cover);
    for (std::size_t i = 0; i < o.cover.size(); ++i)
        o.cover[i] = static_cast<std::uint8_t>(i % ortho::kSuperLandCoverCount);
    const auto n = static_cast<std::size_t>(grid) * grid;
    for (auto* v :
         {&o.climate, &o.temp_dec, &o.temp_jul, &o.precip_dec, &o.precip_jul, &o.lights, &o.slope, &o.aspect}) {
        v->resize(n);
    }
    o.elevation.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
        o.climate[i] = static_cast<std::uint8_t>(i % ortho::kClimateClassCount);
        o.temp_dec[i] = static_cast<std::uint8_t>(i * 3);
        o.temp_jul[i] = static_cast<std::uint8_t>(i * 5);
        o.precip_dec[i] = static_cast<std::uint8_t>(i * 7);
        o.precip_jul[i] = static_cast<std::uint8_t>(i * 11);
        o.lights[i] = static_cast<std::uint8_t>(i);
        o.slope[i] = static_cast<std::uint8_t>(i % 90);
        o.aspect[i] = static_cast<std::uint8_t>(255 - i % 256);
        o.elevation[i] = static_cast<std::int16_t>(static_cast<int>(i) * 37 - 4000);
    }
}

std::string decodeError(const std::vector<std::uint8_t>& bytes) {
    Tile t;
    std::string error;
    return decodeTile(bytes, t, error) ? "" : error;
}

TEST(OrthoStore, LayersRoundTripInTheTilePayload) {
    Tile in = sampleTile({2, 1, 3}, 10, 20, 500);
    addLayers(in, 16, 5);
    const auto bytes = encodeTile(in);
    Tile out;
    std::string error;
    ASSERT_TRUE(decodeTile(bytes, out, error)) << error;
    EXPECT_EQ(out.ortho.cover_size, 16);
    EXPECT_EQ(out.ortho.grid_size, 5);
    EXPECT_EQ(out.ortho.cover, in.ortho.cover);
    EXPECT_EQ(out.ortho.climate, in.ortho.climate);
    EXPECT_EQ(out.ortho.temp_dec, in.ortho.temp_dec);
    EXPECT_EQ(out.ortho.temp_jul, in.ortho.temp_jul);
    EXPECT_EQ(out.ortho.precip_dec, in.ortho.precip_dec);
    EXPECT_EQ(out.ortho.precip_jul, in.ortho.precip_jul);
    EXPECT_EQ(out.ortho.lights, in.ortho.lights);
    EXPECT_EQ(out.ortho.elevation, in.ortho.elevation);
    EXPECT_EQ(out.ortho.slope, in.ortho.slope);
    EXPECT_EQ(out.ortho.aspect, in.ortho.aspect);
    EXPECT_EQ(out.roads.size(), in.roads.size());
    EXPECT_GE(out.byteSize(), in.ortho.cover.size() + 2 * in.ortho.elevation.size());
}

TEST(OrthoStore, ALayerOfTheWrongSizeIsAClearError) {
    Tile t = sampleTile({2, 1, 3}, 10, 20, 500);
    const std::size_t start = encodeTile(t).size() - 1;  // the layer count of a tile without layers
    addLayers(t, 16, 5);
    // count, cover (kind, u16 width, u16 height, 16^2 bytes), climate (kind, w, h, 5^2), then
    // temp_dec's kind and width.
    const std::size_t width_at = start + 1 + 5 + 256 + 5 + 25 + 1;
    auto bytes = encodeTile(t);
    ASSERT_EQ(bytes[width_at - 1], 2);  // kind temp_dec
    bytes[width_at] = 3;
    EXPECT_EQ(decodeError(bytes).rfind("ortho layer temp_dec is 3x5, expected 5x5 (the grid size)", 0), 0u)
        << decodeError(bytes);
    auto cover = encodeTile(t);
    cover[start + 2] = 15;  // cover 15 x 16
    EXPECT_EQ(decodeError(cover).rfind("ortho layer cover is 15x16, expected a square of 1..2048", 0), 0u)
        << decodeError(cover);
    auto cls = encodeTile(t);
    cls[start + 6] = 200;  // the first cover texel
    EXPECT_EQ(decodeError(cls).rfind("bad cover class 200", 0), 0u) << decodeError(cls);
    auto count = encodeTile(t);
    count[start] = 4;
    EXPECT_EQ(decodeError(count).rfind("ortho layer count 4, expected 10", 0), 0u) << decodeError(count);
    auto cut = encodeTile(t);
    cut.resize(cut.size() - 3);
    EXPECT_FALSE(decodeError(cut).empty());
}

TEST(OrthoStore, StoresBeforeTheWorldTileSchemeAreRefusedNamingTheirVersion) {
    ScratchDir dir("ortho-v2");
    StoreInfo info;
    info.origin_lat = 42.5;
    info.origin_lon = 1.5;
    info.scheme = TileScheme(Projection(42.5, 1.5), worldTileAt(14, 42.5, 1.5), 1);
    info.dem_samples = 5;
    const fs::path path = dir / "v2.navmap";
    {
        StoreWriter w(path, info);
        const Box b = info.scheme.bounds({0, 0, 0});
        w.addTile(sampleTile({0, 0, 0}, b.min_x, b.min_y, info.scheme.tileSize(0)));
        w.finish();
    }
    EXPECT_EQ(TileStore::open(path)->info().format_version, 3u);
    for (const std::uint8_t version : {1, 2, 4}) {
        std::fstream f(path, std::ios::in | std::ios::out | std::ios::binary);
        f.seekp(8);
        const char bytes[4] = {static_cast<char>(version), 0, 0, 0};
        f.write(bytes, 4);
        f.close();
        try {
            (void)TileStore::open(path);
            ADD_FAILURE() << "version " << int(version) << " was read";
        } catch (const StoreError& e) {
            const std::string expected = path.string() + ": tile store format version " + std::to_string(version) +
                                         ", this build reads version 3 (" +
                                         (version < 3 ? "versions before 3 have no world tile addresses; " : "") +
                                         "recompile the store with this navmap-compile)";
            EXPECT_EQ(std::string(e.what()), expected);
        }
    }
}

TEST(OrthoStore, AndorraCompiledWithTheGlobalInputs) {
    const fs::path marble = ortho::kDebianMarbleData;
    if (!fs::exists(marble / "maps/earth/temp-dec/temp-dec.jpg")) {
        GTEST_SKIP() << marble << " is absent (Debian package marble-qt-data, scripts/install-deps.sh)";
    }
    ScratchDir dir("ortho-andorra");
    CompileOptions opt;
    opt.osm = repoData("andorra-2021-04-14.osm.pbf");
    opt.dems = {repoData("N42E001.hgt")};
    opt.out = dir / "andorra.navmap";
    opt.ortho_inputs = [&](const std::array<double, 4>& bounds) {
        ortho::MarbleInputOptions o;
        o.bounds = bounds;
        return std::make_shared<const ortho::GlobalInputs>(ortho::loadGlobalInputs(marble, o));
    };
    const CompileStats stats = compileStore(opt);
    EXPECT_EQ(stats.tiles_with_ortho, stats.tiles);
    EXPECT_NE(formatSummary(stats).find("ortho:      " + std::to_string(stats.tiles) + " tiles with orthoimage layers"),
              std::string::npos);
    const auto store = TileStore::open(opt.out);
    EXPECT_EQ(store->info().format_version, kStoreFormatVersion);
    const Projection proj(store->info().origin_lat, store->info().origin_lon);
    const auto& scheme = store->info().scheme;
    const auto id = scheme.tileAt(scheme.leafLevel(), proj.forward(42.5075, 1.5218));  // Andorra la Vella
    ASSERT_TRUE(id);
    const auto r = store->load(*id);
    ASSERT_TRUE(r.tile) << r.error;
    const ortho::OrthoLayers& o = r.tile->ortho;
    ASSERT_FALSE(o.empty());
    EXPECT_EQ(o.cover_size, ortho::kOrthoCoverSize);
    EXPECT_EQ(o.grid_size, ortho::kOrthoGridSize);
    std::array<int, ortho::kSuperLandCoverCount> count{};
    for (auto c : o.cover) ++count[c];
    EXPECT_GT(count[static_cast<std::size_t>(ortho::SuperLandCover::Residential)], 1000);
    EXPECT_EQ(count[static_cast<std::size_t>(ortho::SuperLandCover::Ocean)], 0);
    // The root tile has them too (every level is sampled).
    const auto root = store->load({0, 0, 0});
    ASSERT_TRUE(root.tile) << root.error;
    EXPECT_FALSE(root.tile->ortho.empty());

    // A missing input names the file and fails the compile.
    CompileOptions bad = opt;
    bad.out = dir / "bad.navmap";
    bad.ortho_inputs = [&](const std::array<double, 4>&) -> std::shared_ptr<const ortho::GlobalInputs> {
        return std::make_shared<const ortho::GlobalInputs>(ortho::loadGlobalInputs(dir.path()));
    };
    try {
        (void)compileStore(bad);
        FAIL() << "no error";
    } catch (const CompileError& e) {
        EXPECT_NE(std::string(e.what()).find("temp-dec.jpg: no such file (is marble-qt-data installed?)"),
                  std::string::npos)
            << e.what();
    }
}

}  // namespace
