// SPDX-License-Identifier: Apache-2.0
// The global orthoimage inputs (seed 6.4, 6.5): decode tables against known climates and
// heights, the Koeppen-Geiger stand-in, the climate grid's coastline correction and scrambling,
// and inputs of the wrong shape refused with the file named.

#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>

#include <filesystem>

#include "navmap/map/compile/ortho/marble_inputs.h"
#include "navmap/map/ortho/climate.h"
#include "navmap/map/ortho/geo_grid.h"

namespace {

using namespace navmap::map::ortho;
namespace fs = std::filesystem;

GeoGrid constant(int w, int h, float value, const std::array<float, 256>& decode) {
    GeoGrid g;
    g.width = w;
    g.height = h;
    g.decode = decode;
    // The code whose value is closest.
    int best = 0;
    for (int c = 0; c < 256; ++c) {
        if (std::abs(decode[static_cast<std::size_t>(c)] - value) <
            std::abs(decode[static_cast<std::size_t>(best)] - value))
            best = c;
    }
    g.codes.assign(static_cast<std::size_t>(w) * h, static_cast<std::uint8_t>(best));
    return g;
}

TEST(OrthoInputs, DecodeTablesFollowTheLegends) {
    const auto t = temperatureDecode();
    EXPECT_FLOAT_EQ(t[0], -69.0f);
    EXPECT_FLOAT_EQ(t[255], 42.0f);
    const auto p = precipitationDecode();
    EXPECT_FLOAT_EQ(p[0], 0.0f);
    EXPECT_NEAR(p[static_cast<std::size_t>(std::lround(0.5 * 255))], 127.0f, 1.5f);
    const auto e = elevationDecode();
    EXPECT_NEAR(e[static_cast<std::size_t>(std::lround(0.38 * 255))], 0.0f, 20.0f);
    EXPECT_FLOAT_EQ(e[0], -11000.0f);
    for (int c = 1; c < 256; ++c) EXPECT_GE(e[static_cast<std::size_t>(c)], e[static_cast<std::size_t>(c - 1)]);
}

TEST(OrthoInputs, KoeppenGeigerFromTwoMonths) {
    // December and July temperature (C) and precipitation (mm) of known places.
    EXPECT_EQ(classifyClimate(26, 27, 250, 250, -2.0), ClimateClass::Af);  // Amazon
    EXPECT_EQ(classifyClimate(14, 33, 0, 1, 25.0), ClimateClass::BWh);     // Sahara
    EXPECT_EQ(classifyClimate(10, 25, 70, 20, 41.9), ClimateClass::Csa);   // Rome
    EXPECT_EQ(classifyClimate(2, 18, 60, 70, 52.0), ClimateClass::Cfb);    // Berlin-like maritime
    EXPECT_EQ(classifyClimate(-30, 18, 15, 60, 62.0), ClimateClass::Dfc);  // taiga: about 3 months above 10 C
    EXPECT_EQ(classifyClimate(-20, 5, 20, 30, 70.0), ClimateClass::ET);    // tundra
    EXPECT_EQ(classifyClimate(-60, -30, 2, 2, -80.0), ClimateClass::EF);   // Antarctica
    EXPECT_EQ(classifyClimate(15, 29, 10, 300, 22.0), ClimateClass::Cwa);  // monsoon, dry winter
}

TEST(OrthoInputs, ClimateGridIsCorrectedAtTheCoastAndScrambledOnLand) {
    // Without a land cover every pixel is classified where it is.
    const GeoGrid warm = constant(40, 20, 26.0f, temperatureDecode()),
                  wet = constant(40, 20, 250.0f, precipitationDecode());
    const ClimateGrid g = buildClimateGrid(warm, warm, wet, wet, NaturalEarthCover{});
    ASSERT_EQ(g.classes.size(), 800u);
    for (auto c : g.classes) EXPECT_EQ(static_cast<ClimateClass>(c), ClimateClass::Af);
    // Grids of different sizes are refused, naming them.
    GeoGrid small = constant(20, 10, 26.0f, temperatureDecode());
    small.name = "temp-july.jpg";
    GeoGrid dec = warm;
    dec.name = "temp-dec.jpg";
    try {
        (void)buildClimateGrid(dec, small, wet, wet, NaturalEarthCover{});
        FAIL() << "no error";
    } catch (const std::invalid_argument& e) {
        EXPECT_STREQ(e.what(), "temp-july.jpg: 20x10, expected 40x20 as temp-dec.jpg");
    }
}

TEST(OrthoInputs, MarbleRastersOfKnownPlaces) {
    if (!fs::exists(kDebianMarbleData / "maps/earth/temp-dec"))
        GTEST_SKIP() << "marble-qt-data is absent (scripts/install-deps.sh)";
    MarbleInputOptions o;
    o.bounds = std::array<double, 4>{20.0, -10.0, 65.0, 105.0};  // SRTM tiles of the places below
    const GlobalInputs in = loadGlobalInputs(kDebianMarbleData, o);
    EXPECT_EQ(in.temp_dec.width, 2160);
    EXPECT_LT(in.temp_dec.bilinear(62.0, 100.0), -20.0f);  // Siberia in December
    EXPECT_GT(in.temp_jul.bilinear(25.0, 10.0), 28.0f);    // Sahara in July
    EXPECT_LT(in.precip_jul.bilinear(25.0, 10.0), 5.0f);
    EXPECT_NEAR(in.precip_jul.bilinear(48.14, 11.58), 110.0f, 40.0f);  // Munich in July
    EXPECT_GT(in.elevation.bilinear(33.0, 88.0), 4000.0f);             // Tibet
    EXPECT_NEAR(in.elevation.bilinear(48.14, 11.58), 520.0f, 150.0f);  // Munich
    EXPECT_NEAR(in.elevation.bilinear(0.0, -30.0), 0.0f, 1.0f);        // outside the bounds: sea level
    EXPECT_GT(in.lights.bilinear(48.86, 2.35), 0.5f);                  // Paris by night
    EXPECT_LT(in.lights.bilinear(25.0, 10.0), 0.05f);
    EXPECT_EQ(in.climate.nearest(25.0, 10.0), ClimateClass::BWh);
    const ClimateClass siberia = in.climate.nearest(62.0, 100.0);
    EXPECT_TRUE(siberia == ClimateClass::Dfc || siberia == ClimateClass::Dwc || siberia == ClimateClass::Dfd ||
                siberia == ClimateClass::Dwd)
        << climateName(siberia);
}

TEST(OrthoInputs, ARasterOfTheWrongSizeNamesTheFile) {
    const fs::path dir = fs::temp_directory_path() / ("navmap-marble-" + std::to_string(::getpid()));
    fs::create_directories(dir / "maps/earth/temp-dec");
    const fs::path file = dir / "maps/earth/temp-dec/temp-dec.jpg";
    {
        auto out = OIIO::ImageOutput::create(file.string());
        ASSERT_TRUE(out);
        const OIIO::ImageSpec spec(160, 100, 1, OIIO::TypeDesc::UINT8);
        std::vector<std::uint8_t> px(160 * 100, 128);
        ASSERT_TRUE(out->open(file.string(), spec) && out->write_image(OIIO::TypeDesc::UINT8, px.data()) &&
                    out->close());
    }
    try {
        (void)loadGlobalInputs(dir);
        FAIL() << "no error";
    } catch (const OrthoInputError& e) {
        EXPECT_EQ(std::string(e.what()),
                  file.string() + ": 160x100 is not a global raster (the width must be twice the height)");
    }
    fs::remove(file);
    try {
        (void)loadGlobalInputs(dir);
        FAIL() << "no error";
    } catch (const OrthoInputError& e) {
        EXPECT_EQ(std::string(e.what()), file.string() + ": no such file (is marble-qt-data installed?)");
    }
    fs::remove_all(dir);
}

}  // namespace
