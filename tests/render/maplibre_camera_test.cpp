// SPDX-License-Identifier: Apache-2.0
// MapLibre GL JS camera conventions (maplibre_camera.h) and the camera rig's MapLibre follow
// mode: the map scale of a zoom, the camera distance, the center in the middle of the viewport,
// pitch 0 straight down, bearings clockwise from north.
#include <gtest/gtest.h>

#include <cmath>

#include "navmap/render/camera_rig.h"
#include "navmap/render/maplibre_camera.h"

namespace {

using namespace navmap::render;

constexpr int kW = 1280, kH = 480;
constexpr double kLat = 42.5075, kLon = 1.5218;  // Andorra la Vella

glm::dvec2 project(const Camera& cam, glm::dvec3 p, int w = kW, int h = kH) {
    const glm::mat4 vp = cam.projection(double(w) / h) * cam.viewRelativeTo(cam.target);
    const glm::vec4 c = vp * glm::vec4(glm::vec3(p - cam.target), 1.0f);
    return {(c.x / c.w * 0.5 + 0.5) * w, (1.0 - (c.y / c.w * 0.5 + 0.5)) * h};
}

glm::dvec3 lookDirection(const Camera& c) { return glm::normalize(c.target - c.eye); }

TEST(MapLibreCamera, MetresPerPixelOfZoomAndLatitude) {
    // 512-px tiles: the whole equator on 512 px at zoom 0, half the 256-px slippy-map figures.
    EXPECT_NEAR(mapLibreMetresPerPixel(0.0, 0.0), 78271.517, 1e-3);
    EXPECT_NEAR(mapLibreMetresPerPixel(0.0, 16.0), 1.1943286, 1e-6);
    EXPECT_NEAR(mapLibreMetresPerPixel(60.0, 16.0), 0.5971643, 1e-6);  // cos 60 = 1/2
    EXPECT_NEAR(mapLibreMetresPerPixel(kLat, 16.5),
                40075016.686 * std::cos(kLat * M_PI / 180.0) / (512.0 * std::exp2(16.5)), 1e-12);
    EXPECT_NEAR(mapLibreMetresPerPixel(kLat, 16.5), 0.6226, 1e-3);
    EXPECT_NEAR(mapLibreMetresPerPixel(kLat, 14.5) / mapLibreMetresPerPixel(kLat, 16.5), 4.0, 1e-12);
}

TEST(MapLibreCamera, DistanceIsHalfTheViewportOverTanHalfFov) {
    // tan(36.87 deg / 2) is 1/3 (to 1e-5): the eye sits 1.5 viewport heights (in pixels of the
    // map scale) from the center.
    EXPECT_NEAR(mapLibreCameraDistance(0.0, 16.0, 480), 0.5 * 480 / std::tan(36.87 / 2 * M_PI / 180.0) * 1.1943286,
                1e-4);
    EXPECT_NEAR(mapLibreCameraDistance(0.0, 16.0, 480) / (720.0 * 1.1943286), 1.0, 2e-5);
    EXPECT_NEAR(mapLibreCameraDistance(kLat, 16.5, 480), 448.3, 0.2);
    EXPECT_NEAR(mapLibreCameraDistance(kLat, 14.5, 480), 1793.2, 0.5);
    EXPECT_NEAR(mapLibreCameraDistance(kLat, 16.5, 960) / mapLibreCameraDistance(kLat, 16.5, 480), 2.0, 1e-12);
    const Camera c = mapLibreCameraAt({100.0, 200.0, 1000.0}, kLat, 16.5, 60.0, 30.0, kH);
    EXPECT_NEAR(glm::length(c.target - c.eye), mapLibreCameraDistance(kLat, 16.5, kH), 1e-9);
    EXPECT_DOUBLE_EQ(c.fov_y_deg, kMapLibreFovYDeg);
}

TEST(MapLibreCamera, CenterProjectsToTheViewportCenter) {
    const glm::dvec3 center{-3200.0, 1500.0, 1100.0};
    for (const double pitch : {0.0, 30.0, 60.0, 85.0}) {
        for (const double bearing : {0.0, 45.0, 90.0, 200.0, -30.0}) {
            const Camera c = mapLibreCameraAt(center, kLat, 16.5, pitch, bearing, kH);
            const glm::dvec2 px = project(c, center);
            EXPECT_NEAR(px.x, kW / 2.0, 1e-3) << "pitch " << pitch << " bearing " << bearing;
            EXPECT_NEAR(px.y, kH / 2.0, 1e-3) << "pitch " << pitch << " bearing " << bearing;
        }
    }
}

TEST(MapLibreCamera, PitchZeroLooksStraightDownAtTheZoomsScale) {
    const glm::dvec3 center{0.0, 0.0, 900.0};
    const Camera c = mapLibreCameraAt(center, kLat, 16.5, 0.0, 0.0, kH);
    const glm::dvec3 d = lookDirection(c);
    EXPECT_NEAR(d.z, -1.0, 1e-12);
    // Bearing 0: north at the top. 100 m east is 100 / (metres per pixel) to the right.
    const double mpp = mapLibreMetresPerPixel(kLat, 16.5);
    const glm::dvec2 east = project(c, center + glm::dvec3(100.0, 0.0, 0.0));
    EXPECT_NEAR(east.x - kW / 2.0, 100.0 / mpp, 0.05);
    EXPECT_NEAR(east.y, kH / 2.0, 1e-3);
    const glm::dvec2 north = project(c, center + glm::dvec3(0.0, 100.0, 0.0));
    EXPECT_NEAR(north.x, kW / 2.0, 1e-3);
    EXPECT_NEAR(kH / 2.0 - north.y, 100.0 / mpp, 0.05);
}

TEST(MapLibreCamera, BearingNinetyLooksEast) {
    const glm::dvec3 center{500.0, -200.0, 1000.0};
    const Camera c = mapLibreCameraAt(center, kLat, 16.5, 60.0, 90.0, kH);
    const glm::dvec3 d = lookDirection(c);
    EXPECT_NEAR(std::atan2(d.x, d.y) * 180.0 / M_PI, 90.0, 1e-9);  // the horizontal heading
    EXPECT_NEAR(std::asin(-d.z) * 180.0 / M_PI, 30.0, 1e-9);       // 60 from straight down
    EXPECT_LT(c.eye.x, center.x);                                  // the eye west of the center
    // Straight down with bearing 90: east at the top of the screen.
    const Camera down = mapLibreCameraAt(center, kLat, 16.5, 0.0, 90.0, kH);
    const glm::dvec2 east = project(down, center + glm::dvec3(50.0, 0.0, 0.0));
    EXPECT_NEAR(east.x, kW / 2.0, 1e-3);
    EXPECT_LT(east.y, kH / 2.0 - 10.0);
}

TEST(MapLibreCamera, FromLonLatStandsOnTheTerrainAndBearsFromTrueNorth) {
    const navmap::map::Projection projection(42.55, 1.55);
    MapLibreCamera ml;
    ml.center = {kLat, kLon};
    ml.zoom = 16.5;
    ml.pitch_deg = 0.0;
    ml.bearing_deg = 0.0;
    const auto terrain = [](double x, double y) { return 1000.0 + 0.01 * x + 0.02 * y; };
    const Camera c = cameraFromMapLibre(ml, projection, kH, terrain);
    const navmap::map::PlanarPoint p = projection.forward(kLat, kLon);
    EXPECT_NEAR(c.target.x, p.x, 1e-9);
    EXPECT_NEAR(c.target.y, p.y, 1e-9);
    EXPECT_NEAR(c.target.z, terrain(p.x, p.y), 1e-9);
    // A point due north in latitude lies straight up on screen, although 2 km off the central
    // meridian the store's y axis turns from true north.
    const navmap::map::PlanarPoint n = projection.forward(kLat + 0.001, kLon);
    const glm::dvec2 px = project(c, {n.x, n.y, c.target.z});
    EXPECT_NEAR(px.x, kW / 2.0, 0.01);
    EXPECT_LT(px.y, kH / 2.0 - 100.0);
    const Camera flat = cameraFromMapLibre(ml, projection, kH);
    EXPECT_DOUBLE_EQ(flat.target.z, 0.0);
}

TEST(CameraRigMapLibre, FollowsTheVehicleWithTheMapLibreCamera) {
    const navmap::map::Projection projection(kLat, kLon);
    const VehiclePose pose{{120.0, -40.0, 1050.0}, 75.0, 13.0};
    double lat = 0, lon = 0;
    projection.reverse({pose.position.x, pose.position.y}, lat, lon);
    CameraRig rig;
    rig.setMapLibreFollow({16.5, 60.0, std::nullopt}, projection, kH);
    ASSERT_TRUE(rig.mapLibreFollow().has_value());
    const Camera c = rig.update(pose, 0.0);
    const Camera want = mapLibreCameraAt(pose.position, lat, 16.5, 60.0, 75.0, kH);
    EXPECT_NEAR(glm::length(c.eye - want.eye), 0.0, 1e-6);
    EXPECT_NEAR(glm::length(c.target - want.target), 0.0, 1e-9);
    EXPECT_DOUBLE_EQ(c.fov_y_deg, kMapLibreFovYDeg);
    const glm::dvec2 px = project(c, pose.position);
    EXPECT_NEAR(px.x, kW / 2.0, 1e-3);
    EXPECT_NEAR(px.y, kH / 2.0, 1e-3);

    // North-up: bearing 0 (true north) whatever the heading.
    CameraRig north;
    north.setOrientation(Orientation::NorthUp);
    north.setMapLibreFollow({14.5, 30.0, std::nullopt}, projection, kH);
    const glm::dvec3 d = lookDirection(north.update(pose, 0.0));
    EXPECT_NEAR(std::atan2(d.x, d.y) * 180.0 / M_PI, 0.0, 0.01);
    // A fixed bearing wins over the heading.
    CameraRig fixed;
    fixed.setMapLibreFollow({14.5, 0.0, 90.0}, projection, kH);
    const Camera top = fixed.update(pose, 0.0);
    EXPECT_NEAR(lookDirection(top).z, -1.0, 1e-9);
    const glm::dvec2 east = project(top, pose.position + glm::dvec3(50.0, 0.0, 0.0));
    EXPECT_NEAR(east.x, kW / 2.0, 0.05);
    EXPECT_LT(east.y, kH / 2.0);
}

TEST(CameraRigMapLibre, SwitchingInAndOutMovesSmoothly) {
    const navmap::map::Projection projection(kLat, kLon);
    const VehiclePose pose{{0.0, 0.0, 1000.0}, 0.0, 10.0};
    CameraRig rig;
    rig.setMode(ViewMode::Snail);
    rig.update(pose, 0.0);
    const double snail = rig.state().distance_m;
    rig.setMapLibreFollow({14.5, 30.0, std::nullopt}, projection, kH);
    const double goal = rig.goal(pose).distance_m;
    EXPECT_NEAR(goal, mapLibreCameraDistance(kLat, 14.5, kH), 0.5);
    rig.update(pose, 1.0 / 30.0);
    EXPECT_GT(rig.state().distance_m, snail);
    EXPECT_LT(rig.state().distance_m, snail + 0.2 * (goal - snail)) << "one frame moves only part of the way";
    for (int i = 0; i < 150; ++i) rig.update(pose, 1.0 / 30.0);
    EXPECT_NEAR(rig.state().distance_m, goal, 1.0);
    EXPECT_NEAR(rig.state().pitch_deg, 60.0, 0.1);  // elevation: 90 - pitch
    EXPECT_NEAR(rig.state().fov_y_deg, kMapLibreFovYDeg, 0.01);
    rig.clearMapLibreFollow();
    EXPECT_FALSE(rig.mapLibreFollow().has_value());
    EXPECT_NEAR(rig.goal(pose).distance_m, snail, 1e-9);
}

}  // namespace
