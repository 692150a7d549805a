// SPDX-License-Identifier: Apache-2.0
// The trajectory loader of navmap-label-quality (drive_trajectory.h) on the vendored Andorra
// drive and on broken files, and the --camera spec parser.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <string>

#include "drive_trajectory.h"
#include "label_quality.h"
#include "test_paths.h"

namespace {

namespace nt = navmap::render::tools;

std::string errorOf(const std::string& text) {
    try {
        nt::parseTrajectory(text, "drive.json");
    } catch (const nt::TrajectoryError& e) {
        return e.what();
    }
    return "(no error)";
}

std::string frame(const std::string& members) {
    return R"({"frames":[{"t":0,"s":0,"lon":1.5,"lat":42.5,"bearing":10},)" + members + "]}";
}

TEST(DriveTrajectory, LoadsTheVendoredUrbanDrive) {
    const auto d = nt::loadTrajectory(navmap::test::dataDir() / "drives" / "andorra-urban-trajectory.json");
    ASSERT_EQ(d.frames.size(), 1800U);
    EXPECT_DOUBLE_EQ(d.fps, 30.0);
    EXPECT_DOUBLE_EQ(d.frames[0].position.lon_deg, 1.5188885);
    EXPECT_DOUBLE_EQ(d.frames[0].position.lat_deg, 42.5036297);
    EXPECT_DOUBLE_EQ(d.frames[0].bearing_deg, 96.6818);
    EXPECT_DOUBLE_EQ(d.frames[1].t_s, 0.033333);
    EXPECT_DOUBLE_EQ(d.frames[1799].s_m, 832.87);
    EXPECT_NEAR(d.frames[1799].t_s, 59.966667, 1e-9);
    for (std::size_t i = 1; i < d.frames.size(); ++i) {
        EXPECT_NEAR(d.frames[i].t_s - d.frames[i - 1].t_s, 1.0 / 30.0, 1e-5) << "frame " << i;
    }
}

TEST(DriveTrajectory, NormalisesBearingsAndIgnoresOtherMembers) {
    const auto d = nt::parseTrajectory(
        R"({"route":"x","frames":[{"i":0,"t":0,"s":0,"lon":1.5,"lat":42.5,"bearing":-90,"note":"a"},{"t":0.1,"s":0,"lon":1.5,"lat":42.5,"bearing":360}]})",
        "d.json");
    ASSERT_EQ(d.frames.size(), 2U);
    EXPECT_DOUBLE_EQ(d.frames[0].bearing_deg, 270.0);
    EXPECT_DOUBLE_EQ(d.frames[1].bearing_deg, 0.0);
    EXPECT_DOUBLE_EQ(d.fps, 0.0);
}

TEST(DriveTrajectory, BadFilesGetErrorsNamingFileAndProblem) {
    EXPECT_EQ(errorOf("{\"frames\": [}").rfind("drive.json: invalid JSON: parse error at line 1, column 13", 0), 0U)
        << errorOf("{\"frames\": [}");
    EXPECT_EQ(errorOf("[1, 2]"), "drive.json: must be a JSON object with \"frames\", not array");
    EXPECT_EQ(errorOf("{}"), "drive.json: missing \"frames\"");
    EXPECT_EQ(errorOf(R"({"frames": 3})"), "drive.json: \"frames\" must be an array, not number");
    EXPECT_EQ(errorOf(R"({"frames": []})"), "drive.json: \"frames\" is empty");
    EXPECT_EQ(errorOf(R"({"fps": -30, "frames": []})"), "drive.json: fps: must be a positive number");
    EXPECT_EQ(errorOf(frame("7")), "drive.json: frames[1]: must be an object");
    EXPECT_EQ(errorOf(frame(R"({"t":1,"s":1,"lon":1.5,"bearing":10})")), "drive.json: frames[1]: missing \"lat\"");
    EXPECT_EQ(errorOf(frame(R"({"t":1,"s":1,"lon":1.5,"lat":"42.5","bearing":10})")),
              "drive.json: frames[1].lat: must be a number, not string");
    EXPECT_EQ(errorOf(frame(R"({"t":1,"s":1,"lon":1.5,"lat":95,"bearing":10})")),
              "drive.json: frames[1].lat: 95 out of range [-90, 90]");
    EXPECT_EQ(errorOf(frame(R"({"t":1,"s":1,"lon":181,"lat":42,"bearing":10})")),
              "drive.json: frames[1].lon: 181 out of range [-180, 180]");
    EXPECT_EQ(errorOf(frame(R"({"t":1,"s":1,"lon":1,"lat":42,"bearing":400})")),
              "drive.json: frames[1].bearing: 400 out of range [-360, 360]");
    EXPECT_EQ(errorOf(frame(R"({"t":0,"s":1,"lon":1,"lat":42,"bearing":10})")),
              "drive.json: frames[1].t: 0 is not after the previous frame's 0");
    EXPECT_EQ(errorOf(frame(R"({"t":1,"s":-1,"lon":1,"lat":42,"bearing":10})")),
              "drive.json: frames[1].s: -1 is less than the previous frame's 0");
    EXPECT_EQ(errorOf(frame(R"({"i":5,"t":1,"s":1,"lon":1,"lat":42,"bearing":10})")),
              "drive.json: frames[1].i: 5 is not the frame's index 1");
}

TEST(DriveTrajectory, MissingFileNamesTheCallAndPath) {
    try {
        nt::loadTrajectory("/nonexistent/drive.json");
        FAIL() << "no error";
    } catch (const nt::TrajectoryError& e) {
        EXPECT_STREQ(e.what(), "open(/nonexistent/drive.json): No such file or directory");
    }
}

TEST(CameraSpec, ParsesZoomPitchAndBearing) {
    std::string error;
    auto c = nt::parseCameraSpec("zoom=16.5,pitch=60", &error);
    ASSERT_TRUE(c) << error;
    EXPECT_DOUBLE_EQ(c->zoom, 16.5);
    EXPECT_DOUBLE_EQ(c->pitch_deg, 60.0);
    EXPECT_FALSE(c->bearing_deg);
    EXPECT_EQ(nt::cameraSpecName(*c), "zoom=16.5,pitch=60");
    c = nt::parseCameraSpec("pitch=0,zoom=14.5,bearing=-45", &error);
    ASSERT_TRUE(c) << error;
    EXPECT_DOUBLE_EQ(*c->bearing_deg, -45.0);
    EXPECT_EQ(nt::cameraSpecName(*c), "zoom=14.5,pitch=0,bearing=-45");
}

TEST(CameraSpec, RejectsMalformedAndOutOfRange) {
    const std::pair<const char*, const char*> cases[] = {
        {"zoom=16.5", "camera \"zoom=16.5\": needs zoom and pitch (zoom=Z,pitch=P[,bearing=B])"},
        {"zoom=25,pitch=60", "camera \"zoom=25,pitch=60\": zoom 25 out of range [0, 24]"},
        {"zoom=16,pitch=86", "camera \"zoom=16,pitch=86\": pitch 86 out of range [0, 85]"},
        {"zoom=16,pitch=-1", "camera \"zoom=16,pitch=-1\": pitch -1 out of range [0, 85]"},
        {"zoom=x,pitch=60", "camera \"zoom=x,pitch=60\": zoom must be a number, not \"x\""},
        {"zoom=16,pitch=60,roll=3",
         "camera \"zoom=16,pitch=60,roll=3\": expected zoom=Z,pitch=P[,bearing=B], not \"roll=3\""},
        {"zoom=16,zoom=17,pitch=1", "camera \"zoom=16,zoom=17,pitch=1\": zoom given twice"},
        {"", "camera \"\": expected zoom=Z,pitch=P[,bearing=B], not \"\""},
    };
    for (const auto& [spec, want] : cases) {
        std::string error;
        EXPECT_FALSE(nt::parseCameraSpec(spec, &error)) << spec;
        EXPECT_EQ(error, want);
    }
}

}  // namespace
