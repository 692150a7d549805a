// SPDX-License-Identifier: Apache-2.0
// Pre-processing onto tiles (seed 6.5, map/compile/include/navmap/map/compile/ortho/ortho_preprocess.h): OSM
// areas rasterized into the super land cover in their painting order, the layer encodings, and
// the layers of an Andorra tile from the compiled store and marble-qt-data's global inputs.

#include <gtest/gtest.h>

#include <filesystem>

#include "navmap/map/compile/ortho/marble_inputs.h"
#include "navmap/map/compile/ortho/ortho_preprocess.h"
#include "navmap/map/feature_classes.h"
#include "navmap/map/ortho/super_land_cover.h"
#include "navmap/map/tile_store.h"
#include "test_paths.h"

namespace {

using namespace navmap::map;
using namespace navmap::map::ortho;
namespace fs = std::filesystem;

/// An axis-aligned rectangle area (two counter-clockwise triangles) in tile-local metres.
Area rectangle(AreaClass cls, float x0, float y0, float x1, float y1) {
    Area a;
    a.cls = cls;
    a.polygon.vertices = {{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}};
    a.polygon.ring_ends = {4};
    a.polygon.indices = {0, 1, 2, 0, 2, 3};
    return a;
}

TEST(OrthoPreprocess, AreasAreRasterizedInTheirPaintingOrder) {
    Tile t;
    t.size_m = 100;
    // Water first in the list, forest after it: water is still painted last (on top).
    t.areas.push_back(rectangle(AreaClass::Water, 20, 20, 40, 40));
    t.areas.push_back(rectangle(AreaClass::Forest, 0, 0, 50, 100));
    t.areas.push_back(rectangle(AreaClass::Residential, 50, 50, 100, 100));
    std::vector<std::uint8_t> cover;
    rasterizeAreas(t, 10, cover);  // 10 m texels, centres at 5, 15, ...
    ASSERT_EQ(cover.size(), 100u);
    auto at = [&](int r, int c) { return cover[static_cast<std::size_t>(r * 10 + c)]; };
    auto code = [](SuperLandCover s) { return static_cast<std::uint8_t>(static_cast<int>(s) + 1); };
    for (int r = 0; r < 10; ++r) {
        for (int c = 0; c < 10; ++c) {
            const double x = c * 10 + 5, y = r * 10 + 5;
            std::uint8_t want = 0;
            if (x < 50) want = code(SuperLandCover::Forest);
            if (x > 50 && y > 50) want = code(SuperLandCover::Residential);
            if (x > 20 && x < 40 && y > 20 && y < 40) want = code(SuperLandCover::Lake);  // OSM water is the lake class
            EXPECT_EQ(at(r, c), want) << "texel row " << r << " column " << c;
        }
    }
    EXPECT_LT(areaDrawOrder(AreaClass::Sea), areaDrawOrder(AreaClass::Forest));
    EXPECT_LT(areaDrawOrder(AreaClass::Forest), areaDrawOrder(AreaClass::Residential));
    EXPECT_LT(areaDrawOrder(AreaClass::Residential), areaDrawOrder(AreaClass::Water));
}

TEST(OrthoPreprocess, LayerEncodingsRoundTrip) {
    for (float t = -70.0f; t <= 57.0f; t += 0.37f) EXPECT_NEAR(temperatureFromCode(temperatureCode(t)), t, 0.25f) << t;
    EXPECT_EQ(temperatureCode(-100.0f), 0);
    EXPECT_EQ(temperatureCode(100.0f), 255);
    for (float p : {0.0f, 5.0f, 40.0f, 127.0f, 500.0f, 2000.0f}) {
        const float back = precipitationFromCode(precipitationCode(p));
        EXPECT_NEAR(back, p, 0.5f + 0.02f * p) << p;  // finer steps where it rains little
    }
    EXPECT_EQ(precipitationCode(-3.0f), 0);
    EXPECT_EQ(trainedAs(SuperLandCover::Residential), GlobalCover::Urban);
    EXPECT_EQ(trainedAs(SuperLandCover::Forest), GlobalCover::Land);
    EXPECT_EQ(trainedAs(SuperLandCover::Glacier), GlobalCover::Glacier);
    EXPECT_EQ(fromArea(AreaClass::Water), SuperLandCover::Lake);
}

TEST(OrthoPreprocess, LayersOfAnAndorraTile) {
    if (!fs::exists(kDebianMarbleData / "maps/earth/temp-dec/temp-dec.jpg")) {
        GTEST_SKIP() << kDebianMarbleData << " is absent (Debian package marble-qt-data, scripts/install-deps.sh)";
    }
    const auto store = TileStore::open(navmap::test::binaryDir() / "andorra.navmap");
    const Projection proj(store->info().origin_lat, store->info().origin_lon);
    const auto& scheme = store->info().scheme;
    const auto id = scheme.tileAt(scheme.leafLevel(), proj.forward(42.5075, 1.5218));  // Andorra la Vella
    ASSERT_TRUE(id);
    const auto r = store->load(*id);
    ASSERT_TRUE(r.tile) << r.error;
    MarbleInputOptions options;
    options.bounds = std::array<double, 4>{42.0, 1.0, 43.0, 2.0};
    const GlobalInputs in = loadGlobalInputs(kDebianMarbleData, options);
    const OrthoLayers o = sampleOrthoLayers(*r.tile, in, proj);
    ASSERT_EQ(o.cover_size, kOrthoCoverSize);
    ASSERT_EQ(o.grid_size, kOrthoGridSize);
    ASSERT_EQ(o.cover.size(), std::size_t{kOrthoCoverSize} * kOrthoCoverSize);
    std::array<int, kSuperLandCoverCount> count{};
    for (auto c : o.cover) {
        ASSERT_LT(c, kSuperLandCoverCount);
        ++count[c];
    }
    EXPECT_GT(count[static_cast<std::size_t>(SuperLandCover::Residential)], 1000);  // the town, from OSM
    EXPECT_GT(count[static_cast<std::size_t>(SuperLandCover::Forest)], 1000);
    EXPECT_EQ(count[static_cast<std::size_t>(SuperLandCover::Ocean)], 0);
    const std::size_t centre = std::size_t{kOrthoGridSize / 2} * kOrthoGridSize + kOrthoGridSize / 2;
    // The region's DEM: Andorra la Vella's valley floor at about 1000-1100 m, its slopes higher.
    EXPECT_GT(o.elevation[centre], 900);
    EXPECT_LT(o.elevation[centre], 2600);
    const float jul = temperatureFromCode(o.temp_jul[centre]), dec = temperatureFromCode(o.temp_dec[centre]);
    EXPECT_GT(jul, 5.0f);
    EXPECT_LT(jul, 25.0f);
    EXPECT_LT(dec, jul);
    EXPECT_GT(precipitationFromCode(o.precip_dec[centre]), 20.0f);
    EXPECT_NE(static_cast<ClimateClass>(o.climate[centre]), ClimateClass::EF);
    int steep = 0;
    for (auto v : o.slope) steep += v > 20;
    EXPECT_GT(steep, 50);  // the valley sides
}

}  // namespace
