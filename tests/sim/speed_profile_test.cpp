// SPDX-License-Identifier: Apache-2.0
// SpeedProfile: target speed, curve slowing (lateral acceleration), acceleration and braking
// limits, standing start and full stop, yaw rate consistent with the heading.
#include <gtest/gtest.h>

#include <cmath>

#include "navmap/sim/speed_profile.h"
#include "sim_test_util.h"

namespace navmap::sim {
namespace {

constexpr double kDt = 0.01;

// Checks the invariants on a dense time sampling and returns the max speed seen.
double checkInvariants(const SpeedProfile& p, const DriveParams& q) {
    double vmax = 0.0;
    VehicleState prev = p.stateAt(0.0);
    EXPECT_DOUBLE_EQ(prev.speed_mps, 0.0);
    EXPECT_DOUBLE_EQ(prev.measure_m, 0.0);
    for (double t = kDt; t <= p.duration() + kDt; t += kDt) {
        const VehicleState s = p.stateAt(t);
        EXPECT_GE(s.measure_m, prev.measure_m - 1e-9) << "t=" << t;
        EXPECT_LE(s.speed_mps, s.limit_mps + 1e-6) << "t=" << t;
        EXPECT_LE(s.accel_mps2, q.accel_mps2 + 1e-6) << "t=" << t;
        EXPECT_GE(s.accel_mps2, -q.brake_mps2 - 1e-6) << "t=" << t;
        // Lateral acceleration v * yaw rate stays under the limit (unless the curve-speed floor
        // binds, which these synthetic routes never need).
        const double lat = s.speed_mps * std::abs(s.yaw_rate_dps) * std::numbers::pi / 180.0;
        EXPECT_LE(lat, q.lateral_accel_mps2 + 1e-6) << "t=" << t;
        // The speed difference between samples matches the acceleration bounds too.
        EXPECT_LE((s.speed_mps - prev.speed_mps) / kDt, q.accel_mps2 + 1e-3) << "t=" << t;
        EXPECT_GE((s.speed_mps - prev.speed_mps) / kDt, -q.brake_mps2 - 1e-3) << "t=" << t;
        vmax = std::max(vmax, s.speed_mps);
        prev = s;
    }
    const VehicleState end = p.stateAt(p.duration());
    EXPECT_DOUBLE_EQ(end.speed_mps, 0.0);
    EXPECT_NEAR(end.measure_m, p.length(), 1e-9);
    return vmax;
}

TEST(SpeedProfile, StraightRoadReachesTargetAndStopsAtTheEnd) {
    const DriveRoute r = driveRouteFromPolyline(test::straight(2000.0), 90.0f);
    const DriveParams q;
    const SpeedProfile p = SpeedProfile::build(r, q);
    const double vmax = checkInvariants(p, q);
    EXPECT_NEAR(vmax, 25.0, 1e-6);
    // Closed form: accelerate to 25 m/s at 1.5, cruise, brake at 2.5.
    const double v = 25.0;
    const double expected =
        v / q.accel_mps2 + v / q.brake_mps2 + (2000.0 - v * v / (2 * q.accel_mps2) - v * v / (2 * q.brake_mps2)) / v;
    EXPECT_NEAR(p.duration(), expected, 0.01 * expected);
    EXPECT_NEAR(p.stateAt(1.0).accel_mps2, q.accel_mps2, 1e-9);
    EXPECT_NEAR(p.stateAt(p.duration() - 1.0).accel_mps2, -q.brake_mps2, 1e-9);
}

TEST(SpeedProfile, DriverFactorScalesTheTarget) {
    const DriveRoute r = driveRouteFromPolyline(test::straight(2000.0), 90.0f);
    DriveParams q;
    q.speed_factor = 0.8;
    const SpeedProfile p = SpeedProfile::build(r, q);
    EXPECT_NEAR(checkInvariants(p, q), 20.0, 1e-6);
}

TEST(SpeedProfile, SlowsForACornerAndBrakesBeforeIt) {
    const DriveRoute r = driveRouteFromPolyline(test::corner(400.0), 50.0f);
    const DriveParams q;
    const SpeedProfile p = SpeedProfile::build(r, q);
    checkInvariants(p, q);
    // At the corner (measure 400) the chord heading p(s + w) - p(s - w) turns fastest: 1 / w.
    const double kappa = p.curvatureAt(400.0);
    EXPECT_NEAR(kappa, 1.0 / q.heading_window_m, 0.01);
    const double curve_v = std::sqrt(q.lateral_accel_mps2 / kappa);
    EXPECT_NEAR(p.limitAt(400.0), curve_v, 1e-6);
    EXPECT_LT(curve_v, 50.0 / 3.6 * 0.5);
    EXPECT_NEAR(p.limitAt(300.0), 50.0 / 3.6, 1e-9);  // straight: the target speed
    auto time_at = [&](double measure) {
        for (double t = 0; t < p.duration(); t += kDt) {
            if (p.stateAt(t).measure_m >= measure) return t;
        }
        return p.duration();
    };
    // Slowest at the corner: the curve speed; cruising at 300 m; braking hard at 380 m.
    EXPECT_LE(p.stateAt(time_at(400.0)).speed_mps, curve_v + 1e-6);
    const VehicleState cruise = p.stateAt(time_at(300.0));
    EXPECT_NEAR(cruise.speed_mps, 50.0 / 3.6, 1e-6);
    EXPECT_EQ(cruise.accel_mps2, 0.0);
    const VehicleState braking = p.stateAt(time_at(380.0));
    EXPECT_NEAR(braking.accel_mps2, -q.brake_mps2, 1e-9);
    EXPECT_LT(braking.speed_mps, 50.0 / 3.6 - 1.0);
    EXPECT_GT(braking.speed_mps, curve_v);
}

TEST(SpeedProfile, CircleGivesSteadyCurveSpeedAndYawRate) {
    const double radius = 50.0;
    const DriveRoute r = driveRouteFromPolyline(test::circle(radius, 1.5), 90.0f);
    const DriveParams q;
    const SpeedProfile p = SpeedProfile::build(r, q);
    checkInvariants(p, q);
    const double v = std::sqrt(q.lateral_accel_mps2 * radius);
    const VehicleState mid = p.stateAt(p.duration() / 2);
    EXPECT_NEAR(mid.speed_mps, v, 0.02 * v);
    // Counter-clockwise circle: positive yaw rate (DBC/VSS convention), v / r.
    EXPECT_NEAR(mid.yaw_rate_dps, mid.speed_mps / radius * 180.0 / std::numbers::pi,
                0.02 * 180.0 / std::numbers::pi * v / radius);
    // Integrated yaw rate equals the heading change (heading clockwise => opposite sign).
    double integrated = 0.0;
    double heading_change = 0.0;
    VehicleState prev = p.stateAt(10.0);
    for (double t = 10.0 + kDt; t <= 30.0; t += kDt) {
        const VehicleState s = p.stateAt(t);
        integrated += 0.5 * (s.yaw_rate_dps + prev.yaw_rate_dps) * kDt;
        double d = s.heading_deg - prev.heading_deg;
        if (d > 180) d -= 360;
        if (d < -180) d += 360;
        heading_change += d;
        prev = s;
    }
    EXPECT_NEAR(integrated, -heading_change, 0.01 * std::abs(heading_change));
}

TEST(SpeedProfile, BrakesBeforeALowerSpeedLimit) {
    DriveRoute r = driveRouteFromPolyline(test::straight(2000.0, 100.0), 80.0f);
    for (std::size_t i = 0; i < r.segment_speed_kmh.size(); ++i) {
        if (r.line[i].measure_m >= 1000.0) r.segment_speed_kmh[i] = 30.0f;
    }
    const DriveParams q;
    const SpeedProfile p = SpeedProfile::build(r, q);
    checkInvariants(p, q);
    for (double t = 0; t < p.duration(); t += 0.05) {
        const VehicleState s = p.stateAt(t);
        if (s.measure_m >= 1000.0 + 1e-6) {
            EXPECT_LE(s.speed_mps, 30.0 / 3.6 + 1e-6) << "t=" << t;
        }
    }
    EXPECT_NEAR(p.limitAt(500.0), 80.0 / 3.6, 1e-9);
}

TEST(SpeedProfile, DegenerateRoutesDoNotCrash) {
    const SpeedProfile empty = SpeedProfile::build(DriveRoute{});
    EXPECT_EQ(empty.duration(), 0.0);
    EXPECT_EQ(empty.stateAt(5.0).speed_mps, 0.0);
    const SpeedProfile tiny = SpeedProfile::build(driveRouteFromPolyline({{0, 0}, {0.5, 0}}, 50.0f));
    EXPECT_GT(tiny.duration(), 0.0);
    EXPECT_NEAR(tiny.stateAt(tiny.duration()).measure_m, 0.5, 1e-9);
    // A hairpin that reverses exactly on itself.
    const SpeedProfile back = SpeedProfile::build(driveRouteFromPolyline({{0, 0}, {100, 0}, {0, 0.001}}, 50.0f));
    EXPECT_GT(back.duration(), 0.0);
    EXPECT_TRUE(std::isfinite(back.stateAt(back.duration() / 2).yaw_rate_dps));
}

}  // namespace
}  // namespace navmap::sim
