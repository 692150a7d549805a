// SPDX-License-Identifier: Apache-2.0
// The daemon's map frame re-centred on the vehicle: when it is due, how far the scale has drifted,
// and the parts that keep positions in the frame (the estimator, the route) moving into the new
// one without the vehicle or the route moving on the Earth.

#include <gtest/gtest.h>

#include <cmath>

#include "frame_recentring.h"
#include "navmap/daemon/vehicle/vehicle_state_estimator.h"
#include "route_guidance.h"
#include "route_state.h"

using namespace navmap;
using namespace navmap::daemon;

namespace {

const map::Projection kAndorra(42.55, 1.57);

ipc::CanTime at(double s) {
    return ipc::CanTime{} +
           std::chrono::duration_cast<ipc::CanTime::duration>(std::chrono::duration<double>(1.7e9 + s));
}

// A GNSS fix at (x, y) of `frame`, driving north.
ipc::VehicleSample fixAt(const map::Projection& frame, double x, double y, double t) {
    double lat = 0, lon = 0;
    frame.reverse({x, y}, lat, lon);
    ipc::VehicleSample u;
    u.set(ipc::VssSignal::Latitude, lat, at(t));
    u.set(ipc::VssSignal::Longitude, lon, at(t));
    u.set(ipc::VssSignal::Heading, 0.0, at(t));
    u.set(ipc::VssSignal::FixType, 5, at(t));
    return u;
}

}  // namespace

TEST(FrameRecentring, TheScaleDriftsNorthAndSouthOnlyAndTheFrameMovesPastTheLimit) {
    FrameRecentring frames(kAndorra);
    // tan(42.55) / 6371 km: 0.0143 % per km north, larger to the north, smaller to the south.
    EXPECT_NEAR(FrameRecentring::scaleError(kAndorra, 0.0, 10'000.0), 0.00144, 0.00005);
    EXPECT_NEAR(FrameRecentring::scaleError(kAndorra, 0.0, -10'000.0), -0.00142, 0.00005);
    EXPECT_NEAR(FrameRecentring::scaleError(kAndorra, 150'000.0, 0.0), 0.0, 1e-9) << "none east or west";
    EXPECT_FALSE(frames.due(0.0, 30'000.0)) << "0.43 %";
    EXPECT_FALSE(frames.due(180'000.0, 0.0));
    EXPECT_FALSE(frames.due(std::nan(""), 0.0));
    const auto north = frames.due(0.0, 36'000.0);  // 0.52 %
    ASSERT_TRUE(north);
    EXPECT_TRUE(frames.due(210'000.0, 0.0)) << "the distance limit";
    EXPECT_TRUE(frames.due(0.0, -36'000.0));

    // The new frame is centred on the vehicle and true to scale there; the transform takes the
    // old frame's points to the same places on the Earth.
    double lat = 0, lon = 0;
    kAndorra.reverse({0.0, 36'000.0}, lat, lon);
    EXPECT_NEAR(north->originLat(), lat, 1e-12);
    const map::FrameTransform t = frames.adopt(*north);
    EXPECT_EQ(frames.epoch(), 1u);
    EXPECT_NEAR(t.scale * 0.0 + t.offset_x, 0.0, 1e-6);
    EXPECT_NEAR(t.scale * 36'000.0 + t.offset_y, 0.0, 1e-6);
    EXPECT_NEAR(t.scale, 1.0 / (1.0 + FrameRecentring::scaleError(kAndorra, 0.0, 36'000.0)), 1e-9);
    EXPECT_NEAR(FrameRecentring::scaleError(frames.frame(), 0.0, 0.0), 0.0, 1e-12);
    EXPECT_FALSE(frames.due(0.0, 0.0));
}

TEST(FrameRecentring, TheEstimatorAndTheRouteMoveIntoTheNewFrameWithoutMovingOnTheEarth) {
    // A route 40 km north from the origin, and a vehicle driving along it to 36 km.
    auto control = std::make_shared<ipc::RouteState>();
    control->id = "north";
    control->version = 1;
    for (int i = 0; i <= 4; ++i) {
        double lat = 0, lon = 0;
        kAndorra.reverse({0.0, 10'000.0 * i}, lat, lon);
        control->points.push_back({lat, lon});
    }
    RouteState route(kAndorra);
    ASSERT_TRUE(route.update(control));
    VehicleStateEstimator estimator(kAndorra, nullptr);
    VehicleStateEstimator stays(kAndorra, nullptr);  // the same fixes, never re-centred
    estimator.setRoute(route.line());
    for (int i = 0; i <= 10; ++i) {
        estimator.addSample(fixAt(kAndorra, 0.0, 35'900.0 + 10.0 * i, i));
        stays.addSample(fixAt(kAndorra, 0.0, 35'900.0 + 10.0 * i, i));
    }
    const EstimatedPose before = estimator.snapshot()->poseAt(at(10));
    ASSERT_TRUE(before.valid && before.on_route);
    EXPECT_GT(before.y, 35'900.0);

    FrameRecentring frames(kAndorra);
    const auto next = frames.due(before.x, before.y);
    ASSERT_TRUE(next);
    const map::FrameTransform t = frames.adopt(*next);
    route.rebase(*next);
    estimator.rebase(*next, t, nullptr, 500'000.0, frames.epoch());
    estimator.setRoute(route.line());
    const EstimatedPose after = estimator.snapshot()->poseAt(at(10));
    ASSERT_TRUE(after.valid);
    EXPECT_EQ(after.frame_epoch, 1u);
    EXPECT_NEAR(after.x, 0.0, 0.01);
    EXPECT_NEAR(after.y, 0.0, 0.01) << "the vehicle stands where it stood, at the new origin";
    EXPECT_NEAR(after.heading_deg, before.heading_deg, 1e-9);
    // The route is the same line on the Earth: its points are the control points in the new frame,
    // and the vehicle is on it, about as far along.
    ASSERT_NE(route.line(), nullptr);
    const map::PlanarPoint end = next->forward(control->points.back().lat_deg, control->points.back().lon_deg);
    EXPECT_NEAR(route.line()->points().back().x, end.x, 1e-6);
    EXPECT_NEAR(route.line()->points().back().y, end.y, 1e-6);
    EXPECT_NEAR(end.y, (40'000.0 - before.y) * t.scale, 0.01);
    EXPECT_TRUE(after.on_route);
    EXPECT_NEAR(after.route_driven_m, before.route_driven_m, 0.01 * before.route_driven_m);
    EXPECT_EQ(route.id(), "north");

    // Fixes after the rebase are taken in the new frame.
    estimator.addSample(fixAt(kAndorra, 0.0, 36'010.0, 11));
    stays.addSample(fixAt(kAndorra, 0.0, 36'010.0, 11));
    const EstimatedPose later = estimator.snapshot()->poseAt(at(11));
    const EstimatedPose old_frame = stays.snapshot()->poseAt(at(11));
    EXPECT_GT(later.y, 0.0);
    EXPECT_NEAR(later.x, t.scale * old_frame.x + t.offset_x, 0.01);
    EXPECT_NEAR(later.y, t.scale * old_frame.y + t.offset_y, 0.01);
    EXPECT_EQ(estimator.counters().rejected_jump, 0u);

    // The guidance follows the same route in the new frame: under 4 km left, not 36 km back.
    RouteGuidance guidance(kAndorra, GuidanceConfig{}, nullptr, Log{Log::kErr});
    guidance.setRoute(control);
    guidance.rebase(*next);
    guidance.update(later, 11.0);
    EXPECT_NEAR(guidance.snapshot().remaining_m, end.y - later.y, 0.01);
    EXPECT_FALSE(guidance.snapshot().off_route);
}
