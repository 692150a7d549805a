// SPDX-License-Identifier: Apache-2.0
// Route progress (projection within a window, monotone on a route that crosses itself or
// comes back the same way, passed manoeuvres, distance and time left) and off-route detection
// with hysteresis.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <random>

#include "navmap/map/guidance/off_route_detector.h"
#include "navmap/map/guidance/route_progress_tracker.h"
#include "navmap/map/routing.h"

namespace navmap::map::guidance {
namespace {

std::vector<RoutePoint> withMeasures(const std::vector<PlanarPoint>& pts) {
    std::vector<RoutePoint> line;
    for (const auto& p : pts) {
        const double m = line.empty() ? 0.0
                                      : line.back().measure_m +
                                            std::hypot(p.x - line.back().position.x, p.y - line.back().position.y);
        line.push_back({p, m, 0});
    }
    return line;
}

// Drives along `pts` in 5 m steps with a lateral offset and noise, checking every progress.
void driveAlong(const std::vector<PlanarPoint>& pts, double offset_m, double noise_m) {
    auto route = std::make_shared<const GuidanceRoute>(pts, std::vector<Maneuver>{});
    RouteProgressTracker tracker(route);
    const auto line = withMeasures(pts);
    std::mt19937 rng(7);
    std::normal_distribution<double> noise(0.0, noise_m);
    double previous = 0.0;
    for (double m = 0.0; m <= route->lengthM(); m += 5.0) {
        const RouteSample s = sampleRoute(line, m);
        const double right = (s.heading_deg + 90.0) * std::numbers::pi / 180.0;
        const PlanarPoint pose{s.position.x + offset_m * std::sin(right) + noise(rng),
                               s.position.y + offset_m * std::cos(right) + noise(rng)};
        const RouteProgress& p = tracker.update(pose);
        // A pose beside a corner projects onto the corner's other leg: |offset| of slack.
        EXPECT_NEAR(p.measure_m, m, 3.0 + std::abs(offset_m) + 4.0 * noise_m) << "at " << m;
        EXPECT_GE(p.measure_m, previous);
        EXPECT_NEAR(p.remaining_m, route->lengthM() - p.measure_m, 1e-6);
        previous = p.measure_m;
    }
    EXPECT_EQ(tracker.reacquisitions(), 0U);
}

TEST(GuidanceProgress, FollowsARouteThatCrossesItself) {
    // East 400 m, north, west, then south across the first leg at (200, 0), then east.
    driveAlong({{0, 0}, {400, 0}, {400, 100}, {200, 100}, {200, -100}, {600, -100}}, 2.0, 0.0);
    driveAlong({{0, 0}, {400, 0}, {400, 100}, {200, 100}, {200, -100}, {600, -100}}, 0.0, 1.5);
}

TEST(GuidanceProgress, FollowsARouteThatComesBackTheSameWay) {
    // Out and back on one road (the two directions 8 m apart), driven down its middle: every
    // pose is as close to the way back as to the way out.
    driveAlong({{0, 0}, {300, 0}, {300, 8}, {0, 8}}, -4.0, 0.0);
}

TEST(GuidanceProgress, ManeuversArePassedInOrderAndTheRoundaboutUntilItsExit) {
    const std::vector<PlanarPoint> pts{{0, 0}, {100, 0}, {200, 0}, {300, 0}, {400, 0}, {500, 0}};
    std::vector<Maneuver> ms{
        {ManeuverType::Depart, 0, 0, 0, 0, 0, 0, ""},
        {ManeuverType::TurnLeft, 1, 1, 0, 0, -90, 0, "A"},
        {ManeuverType::Roundabout, 2, 3, 0, 0, 0, 2, "B"},
        {ManeuverType::Arrive, 5, 5, 0, 0, 0, 0, ""},
    };
    auto route = std::make_shared<const GuidanceRoute>(pts, ms);
    EXPECT_TRUE(route->problems().empty());
    EXPECT_DOUBLE_EQ(route->maneuvers()[2].measure_m, 200.0);  // measures come from the points
    EXPECT_DOUBLE_EQ(route->maneuvers()[2].end_measure_m, 300.0);
    RouteProgressTracker t(route);
    struct Step {
        double x;
        std::size_t passed;
        std::size_t next;
        double to_next;
    };
    for (const Step& s : std::vector<Step>{{0, 0, 1, 100},   // Depart is never "next"
                                           {50, 1, 1, 50},   // Depart passed after 10 m
                                           {105, 1, 1, 0},   // at the turn: "now"
                                           {111, 2, 2, 89},  // 10 m beyond it: passed
                                           {250, 2, 2, 0},   // in the roundabout
                                           {305, 2, 2, 0},
                                           {311, 3, 3, 189},  // out of it: arrive is next
                                           {490, 3, 3, 10}}) {
        const RouteProgress& p = t.update({s.x, 1.0});
        EXPECT_EQ(p.passed, s.passed) << s.x;
        ASSERT_TRUE(p.next.has_value()) << s.x;
        EXPECT_EQ(*p.next, s.next) << s.x;
        EXPECT_NEAR(p.to_next_m, s.to_next, 1e-6) << s.x;
        EXPECT_NEAR(p.offset_m, 1.0, 1e-9);
        EXPECT_EQ(p.arrived, s.x >= 480.0);
    }
}

TEST(GuidanceProgress, TimeLeftFromTheSegmentSpeedsElseTheDefault) {
    const std::vector<PlanarPoint> pts{{0, 0}, {1000, 0}, {2000, 0}};
    auto timed = std::make_shared<const GuidanceRoute>(pts, std::vector<Maneuver>{}, std::vector<float>{36.0F, 72.0F});
    EXPECT_NEAR(timed->durationS(), 150.0, 1e-9);
    RouteProgressTracker t(timed);
    EXPECT_NEAR(t.update({500, 0}).remaining_s, 100.0, 1e-9);
    EXPECT_NEAR(t.update({1500, 0}).remaining_s, 25.0, 1e-9);
    EXPECT_NEAR(t.progress().remaining_m, 500.0, 1e-9);

    auto untimed = std::make_shared<const GuidanceRoute>(pts, std::vector<Maneuver>{});
    EXPECT_NEAR(untimed->durationS(), 2000.0 / (kDefaultRouteSpeedKmh / 3.6), 1e-9);
    // A wrong number of speeds is named, and the default used.
    GuidanceRoute wrong(pts, {}, std::vector<float>{50.0F});
    ASSERT_EQ(wrong.problems().size(), 1U);
    EXPECT_EQ(wrong.problems()[0], "segment speeds: 1 for 2 segments; all segments at the default speed");
}

TEST(GuidanceProgress, BadManeuversAreDroppedAndNamed) {
    GuidanceRoute r({{0, 0}, {10, 0}, {20, 0}}, {{ManeuverType::TurnLeft, 2, 2, 0, 0, 0, 0, ""},
                                                 {ManeuverType::TurnRight, 1, 0, 0, 0, 0, 0, ""},
                                                 {ManeuverType::Arrive, 9, 9, 0, 0, 0, 0, ""}});
    ASSERT_EQ(r.maneuvers().size(), 1U);
    ASSERT_EQ(r.problems().size(), 2U);
    EXPECT_EQ(r.problems()[0], "maneuver 1: point 1 before the previous maneuver's point 2");
    EXPECT_EQ(r.problems()[1], "maneuver 2: point 9 beyond the last route point 2");
}

TEST(GuidanceProgress, NeverGoesBackAndReacquiresAheadAfterAGap) {
    auto route =
        std::make_shared<const GuidanceRoute>(std::vector<PlanarPoint>{{0, 0}, {3000, 0}}, std::vector<Maneuver>{});
    RouteProgressTracker t(route);
    EXPECT_NEAR(t.update({100, 0}).measure_m, 100.0, 1e-9);
    // Backing up a little: the match goes back, the progress does not.
    const RouteProgress& back = t.update({90, 0});
    EXPECT_NEAR(back.match_measure_m, 90.0, 1e-9);
    EXPECT_NEAR(back.measure_m, 100.0, 1e-9);
    // A GNSS gap: the next pose is 2 km ahead, beyond the window.
    EXPECT_NEAR(t.update({2100, 3}).measure_m, 2100.0, 1e-9);
    EXPECT_EQ(t.reacquisitions(), 1U);
    // A pose far back on the route is not taken: the match stays at the window's start.
    EXPECT_NEAR(t.update({100, 0}).match_measure_m, 2050.0, 1e-9);
    EXPECT_NEAR(t.progress().measure_m, 2100.0, 1e-9);
    // Non-finite poses are ignored and counted.
    t.update({std::nan(""), 0});
    EXPECT_EQ(t.ignoredPoses(), 1U);
    t.reset();
    EXPECT_NEAR(t.update({100, 0}).measure_m, 100.0, 1e-9);
}

TEST(GuidanceOffRoute, EntersStaysAndLeavesWithHysteresis) {
    OffRouteDetector d;  // 40 m for 3 s off, 20 m for 2 s back
    double t = 0.0;
    auto feed = [&](double distance, double seconds) {
        bool off = d.offRoute();
        for (double end = t + seconds; t < end - 1e-9; t += 0.5) off = d.update(t, distance);
        return off;
    };
    EXPECT_FALSE(feed(5.0, 5.0));
    EXPECT_FALSE(feed(60.0, 3.0));     // t = 5.0 .. 7.5: not yet 3 s
    EXPECT_TRUE(d.update(8.0, 60.0));  // 3 s since 5.0
    t = 8.5;
    EXPECT_TRUE(feed(30.0, 10.0));  // between the thresholds: stays off
    EXPECT_TRUE(feed(10.0, 2.0));   // t = 18.5 .. 20.0 within 20 m: not yet 2 s
    EXPECT_FALSE(d.update(20.5, 10.0));
    EXPECT_EQ(d.ignoredSamples(), 0U);
}

TEST(GuidanceOffRoute, FlappingNearAThresholdDoesNotToggle) {
    OffRouteDetector d;
    for (int i = 0; i < 200; ++i) EXPECT_FALSE(d.update(i * 0.5, i % 4 == 3 ? 39.0 : 41.0)) << i;
    for (int i = 0; i < 7; ++i) d.update(100.0 + i * 0.5, 80.0);
    ASSERT_TRUE(d.offRoute());
    for (int i = 0; i < 200; ++i) EXPECT_TRUE(d.update(104.0 + i * 0.5, i % 4 == 3 ? 21.0 : 19.0)) << i;
}

TEST(GuidanceOffRoute, BadSamplesAreIgnoredAndBadConfigsNamed) {
    OffRouteDetector d;
    d.update(10.0, 60.0);
    d.update(9.0, 60.0);           // older: ignored
    d.update(11.0, std::nan(""));  // ignored
    d.update(std::nan(""), 60.0);  // ignored
    EXPECT_EQ(d.ignoredSamples(), 3U);
    EXPECT_TRUE(d.update(13.0, 60.0));
    d.reset();
    EXPECT_FALSE(d.offRoute());

    OffRouteConfig c;
    c.return_distance_m = 50.0;
    EXPECT_EQ(c.problem(), "return_distance_m 50 must be below leave_distance_m 40");
    EXPECT_THROW(OffRouteDetector{c}, std::runtime_error);
    c = {};
    c.leave_time_s = -1.0;
    EXPECT_EQ(c.problem(), "leave_time_s -1 must be a time >= 0");
    EXPECT_EQ(OffRouteConfig{}.problem(), "");
}

}  // namespace
}  // namespace navmap::map::guidance
