// SPDX-License-Identifier: Apache-2.0
// The orthoimage inputs of a tile's pixels from its layers (seed 6.6.2, OrthoTileSampler): land
// cover as the trained class with its share, blending at borders; scalars interpolated between
// the grid samples; rows encoded south first; layers of the wrong size refused by name.

#include <gtest/gtest.h>

#include <stdexcept>

#include "navmap/map/ortho/tile_sampler.h"
#include "ortho_test_tile.h"

namespace {

using namespace navmap;
using namespace navmap::map::ortho;

std::uint8_t global(GlobalCover c) { return static_cast<std::uint8_t>(c); }

// Forest west of x = 1000 m, residential east of it; elevation 100 m + 0.5 m per metre north.
std::shared_ptr<map::Tile> twoCoverTile() {
    return test::orthoTile(
        [](double x, double) { return x < 1000 ? SuperLandCover::Forest : SuperLandCover::Residential; },
        [](double, double y) { return static_cast<float>(100.0 + 0.5 * y); });
}

TEST(OrthoTileSampler, LandCoverIsTheTrainedClassWithItsShare) {
    const auto tile = twoCoverTile();
    const OrthoTileSampler s(*tile);
    // Inside each area: one class, all of the pixel; OSM forest trains as land, residential as urban.
    const OrthoPixel west = s.pixel(300, 700), east = s.pixel(1700, 700);
    EXPECT_EQ(west.cover.first, global(GlobalCover::Land));
    EXPECT_FLOAT_EQ(west.cover.first_share, 1.0f);
    EXPECT_EQ(east.cover.first, global(GlobalCover::Urban));
    EXPECT_FLOAT_EQ(east.cover.first_share, 1.0f);
    // On the border (x = 1000 m is a texel edge) the two classes share the pixel equally.
    const OrthoPixel border = s.pixel(1000, 700);
    EXPECT_NEAR(border.cover.first_share, 0.5f, 1e-4f);
    EXPECT_NEAR(border.cover.second_share, 0.5f, 1e-4f);
    EXPECT_EQ(border.cover.first + border.cover.second, global(GlobalCover::Land) + global(GlobalCover::Urban));
    // A quarter texel into the forest: three quarters forest.
    const double texel = 2000.0 / 256;
    const OrthoPixel near = s.pixel(1000 - 0.25 * texel, 700);
    EXPECT_EQ(near.cover.first, global(GlobalCover::Land));
    EXPECT_NEAR(near.cover.first_share, 0.75f, 1e-4f);
    EXPECT_EQ(s.coverAt(999, 5), SuperLandCover::Forest);
    EXPECT_EQ(s.coverAt(1001, 5), SuperLandCover::Residential);
}

TEST(OrthoTileSampler, ScalarsAreInterpolatedBetweenTheGridSamples) {
    const auto tile = twoCoverTile();
    const OrthoTileSampler s(*tile);
    const double spacing = 2000.0 / 32;
    // At samples: the stored values (heights are whole metres there), between them bilinear.
    EXPECT_FLOAT_EQ(s.pixel(0, 0).elevation_m, 100.0f);
    EXPECT_FLOAT_EQ(s.pixel(5 * spacing, 4 * spacing).elevation_m, static_cast<float>(100 + 0.5 * 4 * spacing));
    EXPECT_NEAR(s.pixel(0, 4.5 * spacing).elevation_m, 100 + 0.5 * 4.5 * spacing, 0.51);
    const OrthoPixel p = s.pixel(777, 1234);
    EXPECT_FLOAT_EQ(p.temp_dec_c, 2.0f);
    EXPECT_FLOAT_EQ(p.temp_jul_c, 18.0f);
    EXPECT_NEAR(p.precip_dec_mm, 80.0f, 2.0f);  // the layer stores sqrt-coded steps
    EXPECT_EQ(p.climate.first, static_cast<std::uint8_t>(ClimateClass::Cfb));
    EXPECT_FLOAT_EQ(p.climate.first_share, 1.0f);
    EXPECT_FLOAT_EQ(p.lights, 0.0f);
}

TEST(OrthoTileSampler, RowsAreEncodedSouthFirstAtPixelCentres) {
    const auto tile = twoCoverTile();
    const OrthoTileSampler s(*tile);
    constexpr int kSize = 8;
    std::vector<OrthoInput> rows(static_cast<std::size_t>(kSize) * 3);
    // Rows 2..4 of an 8 x 8 raster over the tile's south-east quarter.
    s.encodeRows(1000, 0, 1000, kSize, 2, 5, rows.data());
    for (int r = 2; r < 5; ++r) {
        for (int c = 0; c < kSize; ++c) {
            const OrthoInput expected = encodeInput(s.pixel(1000 + (c + 0.5) * 125, (r + 0.5) * 125));
            EXPECT_EQ(rows[static_cast<std::size_t>((r - 2) * kSize + c)], expected) << "row " << r << " column " << c;
        }
    }
    // Further north is higher: the elevation node's value grows from row to row.
    auto elevation = [&](const OrthoInput& in) { return expandInput(in)[kElevationNode]; };
    EXPECT_LT(elevation(rows[0]), elevation(rows[kSize]));
    EXPECT_LT(elevation(rows[kSize]), elevation(rows[2 * kSize]));
}

TEST(OrthoTileSampler, LayersOfTheWrongSizeAreRefusedByName) {
    auto tile = twoCoverTile();
    EXPECT_EQ(orthoLayersProblem(*tile), "");
    tile->ortho.temp_dec.resize(1000);
    EXPECT_EQ(orthoLayersProblem(*tile), "tile 6/33/17: ortho layer temp_dec has 1000 samples, expected 1089 (33x33)");
    try {
        const OrthoTileSampler s(*tile);
        ADD_FAILURE() << "a temp_dec layer of 1000 samples was accepted";
    } catch (const std::invalid_argument& e) {
        EXPECT_STREQ(e.what(), "tile 6/33/17: ortho layer temp_dec has 1000 samples, expected 1089 (33x33)");
    }
    tile = twoCoverTile();
    tile->ortho.cover.pop_back();
    EXPECT_EQ(orthoLayersProblem(*tile), "tile 6/33/17: ortho layer cover has 65535 texels, expected 65536 (256x256)");
    tile->ortho = {};
    EXPECT_EQ(orthoLayersProblem(*tile), "tile 6/33/17: no ortho layers");
    EXPECT_THROW(OrthoTileSampler{*tile}, std::invalid_argument);
}

}  // namespace
