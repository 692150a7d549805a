// SPDX-License-Identifier: Apache-2.0
// Loading render cases (render_case.h): every shipped case loads, a case's keys become the
// frame it describes, and each kind of malformed case.json is refused with its file and reason.
#include <gtest/gtest.h>

#include <fstream>
#include <ostream>
#include <string>

#include "render_case.h"
#include "test_paths.h"

namespace {

using navmap::test::CaseScene;
using navmap::test::loadRenderCase;
using navmap::test::RenderCase;

const std::filesystem::path kScratch = navmap::test::binaryDir() / "render_case_load_test";

// Writes `json` as <scratch>/<name>/case.json and returns the directory.
std::filesystem::path caseDir(const std::string& name, const std::string& json) {
    auto dir = kScratch / name;
    std::filesystem::create_directories(dir);
    std::ofstream(dir / "case.json") << json;
    return dir;
}

// A valid drive case with `extra` keys added to it.
std::string driveCase(const std::string& extra = {}) {
    return R"({"scene": "andorra_drive", "view": "snail", "pose": {"measure_m": 450.5, "speed_mps": 8},
               "size": [800, 240], "tolerance": {"channel": 10, "max_differing_fraction": 0.01})" +
           (extra.empty() ? std::string() : ", " + extra) + "}";
}

TEST(RenderCaseLoad, EveryShippedCaseLoads) {
    const auto dirs = navmap::test::listRenderCases(navmap::test::sourceDir() / "tests" / "render" / "cases");
    EXPECT_GE(dirs.size(), 23u);
    for (const auto& dir : dirs) {
        std::string error;
        EXPECT_TRUE(loadRenderCase(dir, &error)) << error;
        EXPECT_TRUE(std::filesystem::exists(dir / "expected.png")) << dir;
    }
}

TEST(RenderCaseLoad, KeysDescribeTheFrame) {
    std::string error;
    const auto c = loadRenderCase(caseDir("hud", driveCase(R"("style": "hud", "frames": 3, "msaa": 4,
            "layers": {"preset": "hud", "marker": true, "road_technique": "shadow_volume", "glow_mode": "road_color"},
            "guidance": {"junction_m": 439.25, "arrow": {"before_m": 30}, "junction_roads_radius_m": 60,
                         "overlay": {"symbol": "turn_left", "distance": "300 m", "street": "Carrer"}},
            "stats": {"at_least": {"tiles_drawn": 4}, "equal": {"sv_roads": true}},
            "fallback": {"feature_off": "shadow-volume roads", "expected_case": "other",
                         "stats": {"equal": {"sv_roads": false}}})")),
                                  &error);
    ASSERT_TRUE(c) << error;
    EXPECT_EQ(c->name, "hud");
    EXPECT_EQ(c->scene, CaseScene::AndorraDrive);
    EXPECT_EQ(c->view, navmap::render::ViewMode::Snail);
    EXPECT_EQ(c->measure_m, 450.5);
    EXPECT_EQ(c->speed_mps, 8.0);
    EXPECT_EQ(c->width, 800);
    EXPECT_EQ(c->height, 240);
    EXPECT_EQ(c->msaa_samples, 4);
    EXPECT_EQ(c->frames, 3);
    EXPECT_EQ(c->style, "hud");
    EXPECT_FALSE(c->layers.terrain) << "the hud preset";
    EXPECT_TRUE(c->layers.marker) << "set over the preset";
    EXPECT_EQ(c->layers.road_technique, navmap::render::RoadTechnique::ShadowVolume);
    EXPECT_EQ(c->layers.glow_mode, navmap::render::MapLayers::GlowMode::RoadColor);
    ASSERT_TRUE(c->guidance);
    EXPECT_EQ(c->guidance->junction_m, 439.25);
    EXPECT_TRUE(c->guidance->arrow);
    EXPECT_EQ(c->guidance->arrow_before_m, 30.0);
    EXPECT_EQ(c->guidance->arrow_after_m, 25.0) << "the default";
    EXPECT_EQ(c->guidance->junction_roads_radius_m, 60.0);
    ASSERT_TRUE(c->guidance->overlay);
    EXPECT_EQ(c->guidance->overlay->symbol, navmap::render::ManeuverSymbol::TurnLeft);
    EXPECT_EQ(c->guidance->overlay->distance, "300 m");
    EXPECT_EQ(c->tolerance.channel, 10);
    EXPECT_EQ(c->tolerance.max_differing_fraction, 0.01);
    EXPECT_EQ(c->stats.at_least.at("tiles_drawn"), 4u);
    EXPECT_TRUE(c->stats.equal.at("sv_roads"));
    ASSERT_TRUE(c->fallback);
    EXPECT_EQ(c->fallback->feature_off, "shadow-volume roads");
    EXPECT_EQ(c->expectedPath(c->fallback->expected_case), kScratch / "other" / "expected.png");
    EXPECT_FALSE(c->fallback->stats.equal.at("sv_roads"));
    EXPECT_EQ(c->expectedPath(), kScratch / "hud" / "expected.png");
}

TEST(RenderCaseLoad, AHeightfieldCaseNamesItsFileAndCamera) {
    std::string error;
    const auto c = loadRenderCase(caseDir("heightfield", R"({"scene": "heightfield", "hgt": "N42E001.hgt",
        "camera": "andorra_overview", "size": [1280, 480], "msaa": 4,
        "tolerance": {"channel": 8, "max_differing_fraction": 0.005}})"),
                                  &error);
    ASSERT_TRUE(c) << error;
    EXPECT_EQ(c->scene, CaseScene::Heightfield);
    EXPECT_EQ(c->hgt, "N42E001.hgt");
    EXPECT_EQ(c->camera, "andorra_overview");
}

struct Malformed {
    const char* name;
    std::string json;
    std::string reason;  // what the error says after "<dir>/case.json: "
};

// The test's name in listings, not the object's bytes.
void PrintTo(const Malformed& m, std::ostream* os) { *os << m.name; }

class RenderCaseMalformed : public ::testing::TestWithParam<Malformed> {};

TEST_P(RenderCaseMalformed, IsRefusedWithTheFileAndTheReason) {
    const Malformed& m = GetParam();
    const auto dir = caseDir(m.name, m.json);
    std::string error;
    EXPECT_FALSE(loadRenderCase(dir, &error));
    EXPECT_EQ(error.rfind((dir / "case.json").string() + ": " + m.reason, 0), 0u) << error;
}

INSTANTIATE_TEST_SUITE_P(
    Kinds, RenderCaseMalformed,
    ::testing::Values(
        Malformed{"empty", "", "not JSON: parse error at line 1, column 1"},
        Malformed{"truncated", "{\"scene\": \"andorra_drive\",\n\"view\": ", "not JSON: parse error at line 2"},
        Malformed{"array", "[1, 2]", "must hold a JSON object"},
        Malformed{"no_scene", R"({"size": [1, 1]})", "\"scene\" is missing"},
        Malformed{"unknown_scene", R"({"scene": "moon"})", R"("scene" must be one of "andorra_drive", "heightfield")"},
        Malformed{"unknown_key", driveCase(R"("colour": "red")"), "unknown key \"colour\" (known: description, "},
        Malformed{"no_view", R"({"scene": "andorra_drive", "pose": {"measure_m": 1}})", "\"view\" is missing"},
        Malformed{"no_measure", R"({"scene": "andorra_drive", "view": "bird", "pose": {}})",
                  "\"pose.measure_m\" is missing"},
        Malformed{"negative_measure", R"({"scene": "andorra_drive", "view": "bird", "pose": {"measure_m": -1}})",
                  "\"pose.measure_m\" must be a number from 0 to 1e+07"},
        Malformed{"size_of_one", R"({"scene": "andorra_drive", "view": "bird", "pose": {"measure_m": 1},
                  "size": [640]})",
                  "\"size\" must be [width, height]"},
        Malformed{"fractional_size", R"({"scene": "andorra_drive", "view": "bird", "pose": {"measure_m": 1},
                  "size": [640.5, 240]})",
                  "\"size\" width must be an integer from 1 to 4096"},
        Malformed{"huge_size", R"({"scene": "andorra_drive", "view": "bird", "pose": {"measure_m": 1},
                  "size": [640, 100000]})",
                  "\"size\" height must be an integer from 1 to 4096"},
        Malformed{"no_tolerance", R"({"scene": "andorra_drive", "view": "bird", "pose": {"measure_m": 1},
                  "size": [640, 240]})",
                  "\"tolerance\" is missing"},
        Malformed{"fraction_above_one", R"({"scene": "andorra_drive", "view": "bird", "pose": {"measure_m": 1},
                  "size": [640, 240], "tolerance": {"channel": 10, "max_differing_fraction": 2}})",
                  "\"tolerance.max_differing_fraction\" must be a number from 0 to 1"},
        Malformed{"zero_frames", driveCase(R"("frames": 0)"), "\"frames\" must be an integer from 1 to 600"},
        Malformed{"layer_as_text", driveCase(R"("layers": {"roads": "yes"})"),
                  "\"layers.roads\" must be true or false"},
        Malformed{"misspelt_layer", driveCase(R"("layers": {"raods": true})"), "unknown key \"layers.raods\""},
        Malformed{"unknown_preset", driveCase(R"("layers": {"preset": "night"})"),
                  R"("layers.preset" must be one of "default", "hud")"},
        Malformed{"unknown_style", driveCase(R"("style": "dusk")"), "\"style\" must be one of \"day\", "},
        Malformed{"unknown_count", driveCase(R"("stats": {"at_least": {"frames_per_second": 30}})"),
                  "\"stats.at_least.frames_per_second\" is no count of the frame statistics"},
        Malformed{"negative_count", driveCase(R"("stats": {"at_least": {"tiles_drawn": -1}})"),
                  "\"stats.at_least.tiles_drawn\" must be an integer from 0 to "},
        Malformed{"flag_as_number", driveCase(R"("stats": {"equal": {"sv_roads": 1}})"),
                  "\"stats.equal.sv_roads\" must be true or false"},
        Malformed{"no_junction", driveCase(R"("guidance": {"arrow": {}})"), "\"guidance.junction_m\" is missing"},
        Malformed{"unknown_symbol", driveCase(R"("guidance": {"junction_m": 5, "overlay": {"symbol": "left"}})"),
                  "\"guidance.overlay.symbol\": \"left\" is no manoeuvre"},
        Malformed{"fallback_outside", driveCase(R"("fallback": {"feature_off": "x", "expected_case": "../x"})"),
                  "\"fallback.expected_case\" must name a case directory beside this one"},
        Malformed{"heightfield_with_view", R"({"scene": "heightfield", "view": "bird"})",
                  "unknown key \"view\" (known: "},
        Malformed{"heightfield_path", R"({"scene": "heightfield", "hgt": "../secret.hgt"})",
                  "\"hgt\" must name a file in data/ (no path)"},
        Malformed{"unknown_camera", R"({"scene": "heightfield", "hgt": "N42E001.hgt", "camera": "orbit"})",
                  R"("camera" must be one of "andorra_overview")"}),
    [](const auto& p) { return std::string(p.param.name); });

TEST(RenderCaseLoad, ADirectoryWithoutCaseJsonIsRefused) {
    const auto dir = kScratch / "no_case_json";
    std::filesystem::create_directories(dir);
    std::filesystem::remove(dir / "case.json");
    std::string error;
    EXPECT_FALSE(loadRenderCase(dir, &error));
    EXPECT_EQ(error,
              (dir / "case.json").string() + ": cannot be read (a case directory holds case.json and expected.png)");
}

TEST(RenderCaseLoad, TestNamesKeepLettersDigitsAndUnderscores) {
    EXPECT_EQ(navmap::test::caseTestName("andorra_bird_full2"), "andorra_bird_full2");
    EXPECT_EQ(navmap::test::caseTestName("night-view.v2"), "night_view_v2");
}

TEST(RenderCaseLoad, CasesAreListedByName) {
    std::filesystem::remove_all(kScratch / "list");
    for (const char* name : {"b", "a", "c"}) std::filesystem::create_directories(kScratch / "list" / name);
    std::ofstream(kScratch / "list" / "note.txt") << "not a case";
    const auto dirs = navmap::test::listRenderCases(kScratch / "list");
    ASSERT_EQ(dirs.size(), 3u);
    EXPECT_EQ(dirs[0].filename(), "a");
    EXPECT_EQ(dirs[2].filename(), "c");
    EXPECT_TRUE(navmap::test::listRenderCases(kScratch / "does_not_exist").empty());
}

}  // namespace
