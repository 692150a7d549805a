// SPDX-License-Identifier: Apache-2.0
// The camera rig: bird's-eye and snail's views, smooth transitions, terrain clamping.
#include <gtest/gtest.h>

#include <cmath>

#include <glm/gtc/matrix_transform.hpp>

#include "navmap/render/camera_rig.h"

namespace {

using namespace navmap::render;

glm::dvec2 project(const Camera& cam, glm::dvec3 p, int w, int h) {
    const glm::mat4 vp = cam.projection(double(w) / h) * cam.viewRelativeTo(glm::dvec3(0.0));
    const glm::vec4 c = vp * glm::vec4(glm::vec3(p), 1.0f);
    return {(c.x / c.w * 0.5 + 0.5) * w, (1.0 - (c.y / c.w * 0.5 + 0.5)) * h};
}

double pitchOf(const Camera& c) {
    const glm::dvec3 d = glm::normalize(c.target - c.eye);
    return -std::asin(d.z) * 180.0 / 3.14159265358979;
}

TEST(CameraRig, BirdIsHighWithModeratePitchSnailIsLowAndSteep) {
    VehiclePose pose{{1000.0, 2000.0, 500.0}, 90.0, 15.0};
    CameraRig bird;
    const Camera b = bird.update(pose, 0.0);
    CameraRig snail;
    snail.setMode(ViewMode::Snail);
    const Camera s = snail.update(pose, 0.0);
    EXPECT_GT(b.eye.z - pose.position.z, 500.0);
    EXPECT_LT(s.eye.z - pose.position.z, 80.0);
    EXPECT_NEAR(pitchOf(b), 50.0, 0.5);
    EXPECT_NEAR(pitchOf(s), 14.0, 0.5);
    // Heading-up: heading 90 (east) means the camera looks east and sits west of the car.
    EXPECT_LT(s.eye.x, pose.position.x);
    EXPECT_GT(s.target.x, pose.position.x);
}

TEST(CameraRig, SnailViewKeepsTheVehicleInTheLowerThird) {
    VehiclePose pose{{0.0, 0.0, 0.0}, 30.0, 20.0};
    CameraRig rig;
    rig.setMode(ViewMode::Snail);
    const Camera cam = rig.update(pose, 0.0);
    const glm::dvec2 px = project(cam, pose.position, 1280, 480);
    EXPECT_GT(px.y, 480.0 * 2.0 / 3.0);
    EXPECT_LT(px.y, 480.0);
    EXPECT_NEAR(px.x, 640.0, 2.0);
}

TEST(CameraRig, ZoomGrowsWithSpeedInBirdsEye) {
    CameraRig rig;
    const double slow = rig.goal({{}, 0.0, 0.0}).distance_m;
    const double fast = rig.goal({{}, 0.0, 40.0}).distance_m;
    EXPECT_GT(fast, slow * 2.0);
}

TEST(CameraRig, ModeSwitchIsSmoothNeverAJump) {
    VehiclePose pose{{0.0, 0.0, 0.0}, 0.0, 10.0};
    CameraRig rig;
    Camera prev = rig.update(pose, 0.0);
    rig.setMode(ViewMode::Snail);
    double max_step = 0.0;
    for (int i = 0; i < 240; ++i) {  // 4 s at 60 Hz
        const Camera cam = rig.update(pose, 1.0 / 60.0);
        max_step = std::max(max_step, glm::length(cam.eye - prev.eye));
        prev = cam;
    }
    const double total = glm::length(rig.goal(pose).distance_m - 0.0);
    EXPECT_LT(max_step, 60.0) << "per-frame eye movement must stay a small part of the ~1 km move";
    EXPECT_GT(total, 0.0);
    EXPECT_NEAR(rig.state().distance_m, 180.0, 2.0) << "settles on the snail distance";
    EXPECT_NEAR(rig.state().pitch_deg, 14.0, 0.2);
}

TEST(CameraRig, YawTakesTheShortArc) {
    CameraRig rig;
    rig.update({{}, 350.0, 0.0}, 0.0);
    for (int i = 0; i < 10; ++i) {
        rig.update({{}, 10.0, 0.0}, 1.0 / 60.0);
        const double y = rig.state().yaw_deg;
        EXPECT_TRUE(y > 340.0 || y < 11.0) << y;  // never swings through 180
    }
}

TEST(CameraRig, SmoothDampIsCriticallyDamped) {
    double v = 0.0, x = 0.0;
    double max_x = 0.0;
    for (int i = 0; i < 600; ++i) {
        x = smoothDamp(x, 1.0, v, 0.5, 1.0 / 60.0);
        max_x = std::max(max_x, x);
    }
    EXPECT_NEAR(x, 1.0, 1e-3);
    EXPECT_LE(max_x, 1.0 + 1e-9) << "no overshoot";
}

TEST(CameraRig, EyeNeverBelowTheTerrainAlongTheView) {
    // A ridge 60 m high between the car and the snail camera.
    auto terrain = [](double x, double y) {
        (void)x;
        return (y < -40.0 && y > -140.0) ? 160.0 : 100.0;
    };
    VehiclePose pose{{0.0, 0.0, 100.0}, 0.0, 10.0};
    CameraRig rig;
    rig.setMode(ViewMode::Snail);
    const Camera cam = rig.update(pose, 0.0, terrain);
    EXPECT_GE(cam.eye.z, terrain(cam.eye.x, cam.eye.y) + 8.0 - 1e-6);
    for (int i = 0; i <= 100; ++i) {
        const glm::dvec3 p = cam.eye + (cam.target - cam.eye) * (i / 100.0);
        EXPECT_GE(p.z + 1e-6, terrain(p.x, p.y)) << "line of sight below the DEM at " << i << "%";
    }
}

}  // namespace
