// SPDX-License-Identifier: Apache-2.0
// VehicleStateEstimator: a synthetic drive on a real route of the Andorra store (GNSS 5 Hz +
// speed/yaw rate 50 Hz, with noise) stays within an error bound; dead reckoning between fixes;
// stale after the timeout; NaN/out-of-range/jump/out-of-order rejection counted; snapping onto
// the road with a confidence; route progress; determinism.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <random>

#include "navmap/daemon/vehicle/vehicle_state_estimator.h"
#include "navmap/map/routing.h"
#include "navmap/map/tile_store.h"
#include "test_paths.h"

using namespace navmap;
using namespace navmap::daemon;
using ipc::CanTime;
using ipc::VssSignal;

namespace {

constexpr double kPi = 3.14159265358979323846;

CanTime at(double s) {
    return CanTime{} + std::chrono::duration_cast<CanTime::duration>(std::chrono::duration<double>(1.7e9 + s));
}

ipc::VehicleSample fix(const map::Projection& proj, double x, double y, double t, std::optional<double> heading = {},
                       double fix_type = 5) {
    double lat = 0, lon = 0;
    proj.reverse({x, y}, lat, lon);
    ipc::VehicleSample u;
    u.set(VssSignal::Latitude, lat, at(t));
    u.set(VssSignal::Longitude, lon, at(t));
    if (heading) {
        u.set(VssSignal::Heading, *heading, at(t));
    }
    u.set(VssSignal::FixType, fix_type, at(t));
    return u;
}

ipc::VehicleSample motion(double speed_mps, double yaw_deg_s, double t) {
    ipc::VehicleSample u;
    u.set(VssSignal::Speed, speed_mps * 3.6, at(t));
    u.set(VssSignal::YawRate, yaw_deg_s, at(t));
    return u;
}

struct Store {
    std::shared_ptr<map::TileStore> store;
    std::shared_ptr<const map::RoadGraph> graph;
    std::shared_ptr<const MapMatcher> matcher;
};

const Store* andorra() {
    static const Store kS = [] {
        Store r;
        const auto path = test::binaryDir() / "andorra.navmap";
        if (!std::filesystem::exists(path)) {
            return r;
        }
        r.store = map::TileStore::open(path);
        r.graph = std::make_shared<const map::RoadGraph>(r.store->loadGraph());
        r.matcher = std::make_shared<const MapMatcher>(r.graph);
        return r;
    }();
    return kS.store ? &kS : nullptr;
}

#define REQUIRE_STORE()                                                                   \
    const Store* st = andorra();                                                          \
    if (st == nullptr) {                                                                  \
        GTEST_SKIP() << "no compiled store at " << (test::binaryDir() / "andorra.navmap") \
                     << " (build the navmap_default_store target)";                       \
    }

// A drive along a real route: smoothed so that heading and yaw rate are continuous (a real car
// does not turn in steps at polyline vertices).
struct Truth {
    std::vector<map::RoutePoint> line;
    double length = 0;
    map::PlanarPoint pos(double s) const {
        map::PlanarPoint p{};
        for (int k = -5; k <= 5; ++k) {
            const auto q = map::sampleRoute(line, std::clamp(s + k * 1.5, 0.0, length)).position;
            p.x += q.x / 11.0;
            p.y += q.y / 11.0;
        }
        return p;
    }
    double heading(double s) const {  // radians clockwise from north
        const auto a = pos(s - 0.5), b = pos(s + 0.5);
        return std::atan2(b.x - a.x, b.y - a.y);
    }
};

double speedAt(double t) { return 12.0 + 3.0 * std::sin(t / 9.0); }

struct DriveResult {
    std::vector<EstimatedPose> poses;
    std::vector<map::PlanarPoint> truth;
    std::vector<map::RoutePoint> road;  // the route's centreline
    VehicleStateCounters counters;
    double length = 0;
};

DriveResult drive(const Store& st, double seconds, bool with_route, std::uint32_t seed = 1) {
    const auto proj = st.store->projection();
    const auto from = map::nearestDrivableNode(*st.graph, proj.forward(42.5075, 1.5218));
    const auto to = map::nearestDrivableNode(*st.graph, proj.forward(42.5347, 1.5801));
    const auto route = map::fastestRoute(*st.graph, *from, *to);
    Truth truth{map::routePolyline(*st.graph, *route), 0};
    truth.length = truth.line.back().measure_m;
    VehicleStateEstimator est(proj, st.matcher);
    if (with_route) {
        std::vector<map::PlanarPoint> pts;
        for (const auto& p : truth.line) pts.push_back(p.position);
        est.setRoute(std::make_shared<RouteLine>("r1", pts));
    }
    std::mt19937 rng(seed);
    std::normal_distribution<double> n01(0.0, 1.0);
    DriveResult out;
    out.length = truth.length;
    out.road = truth.line;
    double s = 30.0;
    const double dt = 0.02;
    const double yaw_bias = 0.2;
    for (int i = 0; i * dt < seconds && s < truth.length - 30; ++i) {
        const double t = i * dt;
        const double v = speedAt(t);
        // Heading rate from the truth track (clockwise), reported as VSS yaw (counter-clockwise).
        const double h0 = truth.heading(s - v * 0.01), h1 = truth.heading(s + v * 0.01);
        double dh = h1 - h0;
        dh = std::remainder(dh, 2 * kPi);
        const double yaw_deg_s = -(dh / 0.02) * 180.0 / kPi;
        est.addSample(motion(v + 0.1 * n01(rng), yaw_deg_s + yaw_bias + 0.3 * n01(rng), t));
        if (i % 10 == 0) {  // 5 Hz GNSS, sigma 2.5 m, course sigma 2 deg
            const auto p = truth.pos(s);
            double hdeg = truth.heading(s) * 180.0 / kPi + 2.0 * n01(rng);
            hdeg = std::fmod(hdeg + 720.0, 360.0);
            est.addSample(fix(proj, p.x + 2.5 * n01(rng), p.y + 2.5 * n01(rng), t + 0.001, hdeg));
        }
        // Frames at ~60 Hz: 3 per input step, 10-25 ms ahead of the newest input.
        for (const double ahead : {0.004, 0.011, 0.018}) {
            const double s_ahead = s + v * ahead;
            out.poses.push_back(est.poseAt(at(t + ahead)));
            out.truth.push_back(truth.pos(s_ahead));
        }
        s += v * dt;
    }
    out.counters = est.counters();
    return out;
}

}  // namespace

TEST(VehicleState, SyntheticDriveStaysOnTheRoad) {
    REQUIRE_STORE();
    const auto r = drive(*st, 150.0, false);
    ASSERT_GT(r.poses.size(), 10000U);
    double sum_raw2 = 0, max_raw = 0, sum_snap2 = 0, max_snap = 0, conf = 0, max_step = 0;
    std::vector<double> snap_errors;
    std::size_t n = 0;
    for (std::size_t i = 0; i < r.poses.size(); ++i) {
        const auto& p = r.poses[i];
        ASSERT_TRUE(p.valid);
        EXPECT_FALSE(p.stale);
        if (i < 150) continue;  // settling after the first fix
        const double e_raw = std::hypot(p.raw_x - r.truth[i].x, p.raw_y - r.truth[i].y);
        const double e_snap = std::hypot(p.x - r.truth[i].x, p.y - r.truth[i].y);
        sum_raw2 += e_raw * e_raw;
        sum_snap2 += e_snap * e_snap;
        max_raw = std::max(max_raw, e_raw);
        max_snap = std::max(max_snap, e_snap);
        // Distance of the snapped pose from the road actually driven (the route centreline).
        double off_road = 1e9;
        for (std::size_t k = 0; k + 1 < r.road.size(); ++k) {
            const auto a = r.road[k].position, b = r.road[k + 1].position;
            const double dx = b.x - a.x, dy = b.y - a.y, l2 = dx * dx + dy * dy;
            const double t = l2 > 0 ? std::clamp(((p.x - a.x) * dx + (p.y - a.y) * dy) / l2, 0.0, 1.0) : 0.0;
            off_road = std::min(off_road, std::hypot(p.x - a.x - t * dx, p.y - a.y - t * dy));
        }
        snap_errors.push_back(off_road);
        conf += p.match_confidence;
        if (i > 0) {
            // Smoothness: between consecutive frames the marker moves at most speed * dt + 0.5 m.
            max_step = std::max(max_step, std::hypot(p.raw_x - r.poses[i - 1].raw_x, p.raw_y - r.poses[i - 1].raw_y));
        }
        ++n;
    }
    const double rms_raw = std::sqrt(sum_raw2 / n), rms_snap = std::sqrt(sum_snap2 / n);
    std::sort(snap_errors.begin(), snap_errors.end());
    const double p99_off = snap_errors[snap_errors.size() * 99 / 100];
    const double p95_off = snap_errors[snap_errors.size() * 95 / 100];
    std::printf(
        "[ measured ] %zu poses over %.0f m: fused rms %.2f m max %.2f m; snapped rms %.2f m max %.2f m, off the "
        "driven road p95 %.2f m p99 %.2f m; "
        "mean confidence %.2f; max frame step %.2f m; fixes %llu jumps %llu\n",
        n, r.length, rms_raw, max_raw, rms_snap, max_snap, p95_off, p99_off, conf / n, max_step,
        static_cast<unsigned long long>(r.counters.fixes), static_cast<unsigned long long>(r.counters.rejected_jump));
    EXPECT_LT(rms_raw, 2.0);
    EXPECT_LT(max_raw, 6.0);
    EXPECT_LT(rms_snap, 2.0);
    EXPECT_LT(p95_off, 0.5);  // snapped onto the road that is driven
    EXPECT_LT(p99_off, 3.0);
    EXPECT_LT(max_snap, 12.0);  // the smoothed truth cuts hairpin corners; snapping does not
    EXPECT_GT(conf / n, 0.6);
    EXPECT_LT(max_step, 15.0 * 0.007 + 0.5);
    EXPECT_EQ(r.counters.rejected_jump, 0U);
}

TEST(VehicleState, RouteProgressAndDeterminism) {
    REQUIRE_STORE();
    const auto a = drive(*st, 40.0, true, 3);
    const auto b = drive(*st, 40.0, true, 3);
    ASSERT_EQ(a.poses.size(), b.poses.size());
    for (std::size_t i = 0; i < a.poses.size(); ++i) {
        ASSERT_EQ(a.poses[i].x, b.poses[i].x) << i;
        ASSERT_EQ(a.poses[i].heading_deg, b.poses[i].heading_deg) << i;
    }
    double prev = -1;
    std::size_t on_route = 0, backwards = 0;
    for (std::size_t i = 150; i < a.poses.size(); ++i) {
        const auto& p = a.poses[i];
        if (!p.on_route) continue;
        ++on_route;
        EXPECT_NEAR(p.route_driven_m + p.route_remaining_m, a.length, 1e-6);
        // Inside a sharp corner the nearest route point sits on the vertex; position noise
        // there moves the measure back by a few metres at most.
        backwards += p.route_driven_m < prev - 15.0;
        prev = p.route_driven_m;
    }
    EXPECT_GT(on_route, (a.poses.size() - 150) * 95 / 100);
    EXPECT_EQ(backwards, 0U);
    EXPECT_GT(prev, 400.0);  // 40 s at ~12 m/s from measure 30
}

TEST(VehicleState, DeadReckoningBetweenFixes) {
    const map::Projection proj(42.5, 1.5);
    VehicleStateEstimator est(proj, nullptr);
    // Eastwards at 10 m/s, fixes at 1 Hz exactly on the track, motion at 50 Hz.
    for (int i = 0; i <= 150; ++i) {
        const double t = i * 0.02;
        est.addSample(motion(10.0, 0.0, t));
        if (i % 50 == 0) est.addSample(fix(proj, 10.0 * t, 0.0, t, 90.0));
    }
    // Last fix at t = 3.0 (x = 30); at t = 3.5 dead reckoning gives x = 35.
    auto p = est.poseAt(at(3.5));
    ASSERT_TRUE(p.valid);
    EXPECT_NEAR(p.x, 35.0, 0.05);
    EXPECT_NEAR(p.y, 0.0, 0.05);
    EXPECT_NEAR(p.heading_deg, 90.0, 0.01);
    EXPECT_NEAR(p.speed_mps, 10.0, 1e-9);
    EXPECT_EQ(p.source_time, at(3.0));  // newest data behind it: the motion sample at 3.0
    // The motion hold ends 0.5 s after the last sample: the pose stops there.
    p = est.poseAt(at(4.0));
    EXPECT_NEAR(p.x, 35.0, 0.05);
    EXPECT_NEAR(p.speed_mps, 0.0, 1e-9);

    // Turning: 90 deg/s to the left (VSS positive) for 1 s from heading east -> heading north.
    VehicleStateEstimator turn(proj, nullptr);
    turn.addSample(motion(10.0, 90.0, 0.0));
    turn.addSample(fix(proj, 0.0, 0.0, 0.0, 90.0));
    for (int i = 1; i <= 50; ++i) turn.addSample(motion(10.0, 90.0, i * 0.02));
    p = turn.poseAt(at(1.0));
    EXPECT_NEAR(std::remainder(p.heading_deg, 360.0), 0.0, 0.5);
    // Quarter circle of radius v/w = 10 / (pi/2): ends at (r, r).
    const double radius = 10.0 / (kPi / 2);
    EXPECT_NEAR(p.x, radius, 0.05);
    EXPECT_NEAR(p.y, radius, 0.05);

    // Interpolation into the past passes through the anchors.
    const auto mid = est.poseAt(at(1.5));
    EXPECT_NEAR(mid.x, 15.0, 0.05);
    EXPECT_EQ(est.poseAt(at(2.0)).x, est.snapshot()->parts().anchors[est.snapshot()->parts().anchors.size() - 2].x);
}

TEST(VehicleState, CorrectionsAreFadedInNotJumped) {
    const map::Projection proj(42.5, 1.5);
    VehicleStateEstimator est(proj, nullptr);
    est.addSample(motion(10.0, 0.0, 0.0));
    est.addSample(fix(proj, 0.0, 0.0, 0.0, 90.0));
    for (int i = 1; i <= 10; ++i) est.addSample(motion(10.0, 0.0, i * 0.02));
    const auto before = est.poseAt(at(0.2));
    est.addSample(fix(proj, 2.0 + 6.0, 0.0, 0.2, 90.0));  // 6 m ahead of the prediction (x = 2)
    const auto after = est.poseAt(at(0.2));
    EXPECT_NEAR(after.x, before.x, 1e-6);          // no visible step at the fix
    const auto later = est.poseAt(at(0.2 + 0.5));  // after blend_s: prediction + gain * innovation
    EXPECT_NEAR(later.x, 2.0 + 0.3 * 6.0 + 5.0, 0.05);
}

TEST(VehicleState, StaleAfterTimeoutAndRegained) {
    const map::Projection proj(42.5, 1.5);
    VehicleStateEstimator est(proj, nullptr);
    EXPECT_FALSE(est.poseAt(at(0)).valid);
    EXPECT_TRUE(est.poseAt(at(0)).stale);
    est.addSample(fix(proj, 0, 0, 0.0));
    est.addSample(fix(proj, 1, 0, 1.0));
    EXPECT_FALSE(est.poseAt(at(2.9)).stale);
    const auto lost = est.poseAt(at(3.1));
    EXPECT_TRUE(lost.stale);
    EXPECT_NEAR(lost.since_fix_s, 2.1, 1e-6);
    est.addSample(fix(proj, 50, 0, 10.0));  // regained far away: no jump rejection after a stale period
    const auto back = est.poseAt(at(10.0));
    EXPECT_FALSE(back.stale);
    EXPECT_NEAR(back.x, 50.0, 1e-6);
    EXPECT_EQ(est.counters().relocations, 1U);
    EXPECT_EQ(est.counters().rejected_jump, 0U);
}

TEST(VehicleState, BadInputIsRejectedAndCounted) {
    const map::Projection proj(42.5, 1.5);
    VehicleStateEstimator est(proj, nullptr);
    est.addSample(fix(proj, 0, 0, 0.0));
    est.addSample(fix(proj, 0, 0, 0.2));
    ipc::VehicleSample u;
    u.set(VssSignal::Latitude, std::numeric_limits<double>::quiet_NaN(), at(0.4));
    u.set(VssSignal::Longitude, 1.5, at(0.4));
    est.addSample(u);
    EXPECT_EQ(est.counters().rejected_nan, 1U);
    u = {};
    u.set(VssSignal::Latitude, 95.0, at(0.6));
    u.set(VssSignal::Longitude, 1.5, at(0.6));
    est.addSample(u);
    EXPECT_EQ(est.counters().rejected_range, 1U);
    EXPECT_EQ(est.counters().last_rejection, "GNSS fix: latitude 95 / longitude 1.5 out of range");
    u = {};
    u.set(VssSignal::Latitude, 10.0, at(0.8));  // valid WGS84, 3600 km from the map
    u.set(VssSignal::Longitude, 1.5, at(0.8));
    est.addSample(u);
    EXPECT_EQ(est.counters().rejected_range, 2U);
    est.addSample(fix(proj, 0, 0, 0.9, {}, 0));
    EXPECT_EQ(est.counters().rejected_no_fix, 1U);
    est.addSample(fix(proj, 0, 0, 0.1));  // older than the newest fix
    EXPECT_EQ(est.counters().rejected_order, 1U);
    est.addSample(motion(std::numeric_limits<double>::infinity(), 0, 1.0));
    EXPECT_EQ(est.counters().rejected_nan, 2U);
    est.addSample(motion(10, 5000.0, 1.0));
    EXPECT_EQ(est.counters().rejected_range, 3U);
    EXPECT_EQ(est.counters().motion_samples, 0U);

    // A single spike 500 m away is rejected and the pose does not move; three in a row relocate.
    est.addSample(fix(proj, 500, 0, 1.0));
    EXPECT_EQ(est.counters().rejected_jump, 1U);
    EXPECT_NEAR(est.poseAt(at(1.0)).x, 0.0, 1e-6);
    est.addSample(fix(proj, 0.5, 0, 1.2));
    EXPECT_EQ(est.counters().fixes, 3U);
    for (int k = 0; k < 3; ++k) est.addSample(fix(proj, 800, 0, 1.4 + 0.2 * k));
    EXPECT_EQ(est.counters().rejected_jump, 3U);
    EXPECT_EQ(est.counters().relocations, 1U);
    EXPECT_NEAR(est.poseAt(at(1.8)).x, 800.0, 1e-6);
}

TEST(VehicleState, SnapsOntoTheNearestRoadWithConfidence) {
    REQUIRE_STORE();
    const auto proj = st->store->projection();
    // A primary road edge with a long first segment.
    const auto& g = *st->graph;
    std::optional<std::uint32_t> chosen;
    for (std::uint32_t e = 0; e < g.edges.size() && !chosen; ++e) {
        const auto& ed = g.edges[e];
        if (ed.cls != map::RoadClass::Primary || (ed.flags & map::edge_flags::kReversed) ||
            ed.shape_end - ed.shape_begin < 2)
            continue;
        const auto a = g.shape[ed.shape_begin], b = g.shape[ed.shape_begin + 1];
        if (std::hypot(b.x - a.x, b.y - a.y) > 80.0) chosen = e;
    }
    ASSERT_TRUE(chosen);
    const auto& ed = g.edges[*chosen];
    const auto a = g.shape[ed.shape_begin], b = g.shape[ed.shape_begin + 1];
    const double len = std::hypot(b.x - a.x, b.y - a.y);
    const double ux = (b.x - a.x) / len, uy = (b.y - a.y) / len;
    const double mx = a.x + ux * len / 2, my = a.y + uy * len / 2;
    const double heading = std::fmod(std::atan2(ux, uy) * 180.0 / kPi + 360.0, 360.0);

    VehicleStateEstimator est(proj, st->matcher);
    // 5 m to the side of the road, parked: snapped onto the centreline.
    est.addSample(fix(proj, mx + 5 * uy, my - 5 * ux, 0.0, heading));
    auto p = est.poseAt(at(0.0));
    EXPECT_GT(p.match_confidence, 0.5);
    EXPECT_EQ(p.snap_weight, 1.0);
    const double off = std::abs((p.x - a.x) * uy - (p.y - a.y) * ux);  // distance from the line
    EXPECT_LT(off, 0.01);
    EXPECT_NEAR(p.raw_x, mx + 5 * uy, 1e-6);
    ASSERT_TRUE(p.edge);
    const auto& m = g.edges[*p.edge];
    EXPECT_EQ(m.way_id, ed.way_id);

    // 200 m from any road in the middle of nowhere: not snapped, confidence 0.
    VehicleStateEstimator far(proj, st->matcher);
    const auto summit = proj.forward(42.6, 1.72);
    far.addSample(fix(proj, summit.x, summit.y, 0.0));
    p = far.poseAt(at(0.0));
    if (!p.edge) {
        EXPECT_EQ(p.match_confidence, 0.0);
        EXPECT_EQ(p.x, p.raw_x);
        EXPECT_EQ(p.y, p.raw_y);
    }
    // A point exactly on the road matches with confidence 1 (heading unknown at standstill).
    const auto on_road = st->matcher->match({mx, my}, heading, std::nullopt, VehicleStateConfig{});
    ASSERT_TRUE(on_road);
    EXPECT_NEAR(on_road->confidence, 1.0, 1e-6);
    // The reversed heading picks the twin edge (two-way road) or loses confidence (one-way).
    const auto back =
        st->matcher->match({mx, my}, std::fmod(heading + 180.0, 360.0), std::nullopt, VehicleStateConfig{});
    ASSERT_TRUE(back);
    if ((ed.flags & map::road_flags::kOneway) == 0) {
        EXPECT_NE(back->edge, *chosen);
        EXPECT_NEAR(back->confidence, 1.0, 1e-6);
    } else {
        EXPECT_LT(back->confidence, 0.01);
    }
}

// Matching onto a route of 20,000 points (set_route's maximum) searches the segments near the
// previous match first (RouteLine::match): it finds what a search of the whole route finds, also
// where the previous match lies far away along the route.
TEST(RouteLine, MatchingNearThePreviousMatchFindsWhatTheWholeRouteGives) {
    // 100 km north with a point every 5 m, weaving 2 m east and west.
    std::vector<map::PlanarPoint> pts;
    for (int i = 0; i < 20000; ++i) pts.push_back({i % 2 == 0 ? -1.0 : 1.0, 5.0 * i});
    const RouteLine line("r1", pts);
    const VehicleStateConfig cfg;
    const map::PlanarPoint at{0.5, 50003.0};
    const auto whole = line.match(at, 0.0, std::nullopt, cfg);
    ASSERT_TRUE(whole);
    EXPECT_NEAR(whole->point.y, 50003.0, 2.5);
    const auto near = line.match(at, 0.0, whole->measure_m - 3.0, cfg);
    ASSERT_TRUE(near);
    EXPECT_NEAR(near->measure_m, whole->measure_m, 1.0);
    EXPECT_NEAR(near->point.x, whole->point.x, 1.0);
    EXPECT_NEAR(near->point.y, whole->point.y, 1.0);
    // A previous match far away along the route: nothing near it fits, the rest is searched
    // (the jump penalty then prefers the earliest candidate within the radius).
    const auto jumped = line.match(at, 0.0, 10000.0, cfg);
    ASSERT_TRUE(jumped);
    EXPECT_LE(jumped->distance_m, cfg.match_radius_m);
    EXPECT_NEAR(jumped->point.y, 50003.0, cfg.match_radius_m + 3.0);
    // A route passing the same place twice: the pass near the previous match wins, as before.
    std::vector<map::PlanarPoint> loop{{0, 0}, {0, 3000}, {10, 3000}, {10, 0}};
    const RouteLine back("r2", loop);
    const auto out = back.match({5.0, 1500.0}, std::nullopt, 1400.0, cfg);
    const auto in = back.match({5.0, 1500.0}, std::nullopt, 4600.0, cfg);
    ASSERT_TRUE(out && in);
    EXPECT_NEAR(out->measure_m, 1500.0, 1e-6);
    EXPECT_NEAR(in->measure_m, 3010.0 + 1500.0, 1e-6);
}

// The speed limit of the matched road in the driving direction (EstimatedPose::speed_limit_kmh):
// a two-way road with 50 km/h northbound and 30 km/h southbound (maxspeed:forward/backward) and
// a one-way road of 70 km/h beside it; none where the match or its direction is uncertain. And
// whether the matched road itself is certain (EstimatedPose::road_match_certain, the street bar's).
namespace {

std::shared_ptr<const map::RoadGraph> speedLimitGraph() {
    auto g = std::make_shared<map::RoadGraph>();
    // Two-way: node 0 (0, 0) -> node 1 (0, 400); one-way 300 m east, northbound: 2 -> 3.
    g->nodes = {{0, 0, 1}, {0, 400, 2}, {300, 0, 3}, {300, 400, 4}};
    g->shape = {{0, 0}, {0, 400}, {300, 0}, {300, 400}};
    map::GraphEdge fwd{0, 1, 400, 50, map::RoadClass::Secondary, 0, 0, 2, 10, 50};
    map::GraphEdge back = fwd;
    std::swap(back.from, back.to);
    back.flags |= map::edge_flags::kReversed;
    back.speed_limit_kmh = 30;
    map::GraphEdge oneway{2, 3, 400, 70, map::RoadClass::Secondary, map::road_flags::kOneway, 2, 4, 11, 70};
    g->edges = {fwd, back, oneway};
    map::indexEdges(*g);
    return g;
}

/// Drives `seconds` at 12 m/s from (x, y0) with `heading` (0 north, 180 south), fixes at 5 Hz.
EstimatedPose driveAlong(VehicleStateEstimator& est, const map::Projection& proj, double x, double y0, double heading,
                         double seconds) {
    const double dir = heading < 90.0 ? 1.0 : -1.0;
    for (int i = 0; i <= int(seconds * 5); ++i) {
        const double t = i * 0.2;
        est.addSample(motion(12.0, 0.0, t));
        est.addSample(fix(proj, x, y0 + dir * 12.0 * t, t, heading));
    }
    return est.poseAt(at(seconds));
}

}  // namespace

TEST(VehicleState, SpeedLimitOfTheMatchedRoadInTheDrivingDirection) {
    const map::Projection proj(42.5, 1.5);
    const auto matcher = std::make_shared<const MapMatcher>(speedLimitGraph());
    {
        VehicleStateEstimator est(proj, matcher);
        const EstimatedPose p = driveAlong(est, proj, 1.0, 50.0, 0.0, 5.0);
        ASSERT_TRUE(p.edge);
        EXPECT_EQ(matcher->graph().edges[*p.edge].way_id, 10);
        EXPECT_EQ(p.speed_limit_kmh, 50) << "northbound: the way's forward limit";
        EXPECT_TRUE(p.road_match_certain);
    }
    {
        VehicleStateEstimator est(proj, matcher);
        const EstimatedPose p = driveAlong(est, proj, -1.0, 350.0, 180.0, 5.0);
        ASSERT_TRUE(p.edge);
        EXPECT_TRUE(matcher->graph().edges[*p.edge].flags & map::edge_flags::kReversed);
        EXPECT_EQ(p.speed_limit_kmh, 30) << "southbound: the way's backward limit";
    }
    {
        VehicleStateEstimator est(proj, matcher);
        EXPECT_EQ(driveAlong(est, proj, 301.0, 50.0, 0.0, 5.0).speed_limit_kmh, 70) << "the one-way road";
    }
    {
        // Parked: no heading, so the direction is not known, and the two directions differ: no
        // limit, also after more fixes (the edge held is no better than the first guess).
        VehicleStateEstimator est(proj, matcher);
        for (int i = 0; i < 5; ++i) est.addSample(fix(proj, 0.5, 200.0, i * 0.2));
        const EstimatedPose p = est.poseAt(at(0.8));
        EXPECT_TRUE(p.edge);
        EXPECT_EQ(p.speed_limit_kmh, 0);
        EXPECT_TRUE(p.road_match_certain) << "the road is certain, only its direction is not";
    }
    {
        // Parked on the one-way road: its only direction.
        VehicleStateEstimator est(proj, matcher);
        est.addSample(fix(proj, 300.5, 200.0, 0.0));
        EXPECT_EQ(est.poseAt(at(0.0)).speed_limit_kmh, 70);
    }
    {
        // 20 m beside the road: matched, but with a confidence below snap_full_confidence.
        VehicleStateEstimator est(proj, matcher);
        const EstimatedPose p = driveAlong(est, proj, 20.0, 50.0, 0.0, 3.0);
        EXPECT_LT(p.match_confidence, 0.5);
        EXPECT_EQ(p.speed_limit_kmh, 0);
        EXPECT_TRUE(p.edge);
        EXPECT_FALSE(p.road_match_certain);
    }
    {
        // Stale: no fix for longer than gnss_timeout_s.
        VehicleStateEstimator est(proj, matcher);
        driveAlong(est, proj, 1.0, 50.0, 0.0, 3.0);
        const EstimatedPose p = est.poseAt(at(3.0 + 10.0));
        EXPECT_EQ(p.speed_limit_kmh, 0);
        EXPECT_FALSE(p.road_match_certain);
    }
}

// Dead reckoning along a tunnel (docs/vehicle-state.md "Tunnels"): a road north to a portal at
// (0, 300), a 1063 m tunnel that bends east to (900, 700), and two exits there, east (straight
// on) and north. GNSS stops 60 m before the portal; speed goes on at 15 m/s, the gyro says
// straight on. The marker follows the tunnel's shape at the distance driven, beyond the 10 s of
// plain dead reckoning and the 20 s of motion history, and leaves it by the route's exit.
namespace {

std::shared_ptr<const map::RoadGraph> tunnelGraph(bool tunnel) {
    auto g = std::make_shared<map::RoadGraph>();
    g->nodes = {{0, 0, 1}, {0, 300, 2}, {900, 700, 3}, {1300, 700, 4}, {900, 1100, 5}};
    g->shape = {{0, 0},     {0, 300},   {0, 300},    {100, 500}, {300, 600}, {600, 600},
                {900, 700}, {900, 700}, {1300, 700}, {900, 700}, {900, 1100}};
    const std::uint8_t tf = tunnel ? map::road_flags::kTunnel : 0;
    g->edges = {{0, 1, 300, 50, map::RoadClass::Primary, map::road_flags::kOneway, 0, 2, 1, 50},
                {1, 2, 1063, 50, map::RoadClass::Primary, std::uint8_t(map::road_flags::kOneway | tf), 2, 7, 2, 50},
                {2, 3, 400, 50, map::RoadClass::Primary, map::road_flags::kOneway, 7, 9, 3, 50},
                {2, 4, 400, 50, map::RoadClass::Primary, map::road_flags::kOneway, 9, 11, 4, 50}};
    map::indexEdges(*g);
    return g;
}

// Distance of p from a polyline and how far along it p's nearest point lies.
std::pair<double, double> onPolyline(const std::vector<map::PlanarPoint>& line, map::PlanarPoint p) {
    double best = 1e18, along = 0.0, m = 0.0;
    for (std::size_t i = 0; i + 1 < line.size(); ++i) {
        const double dx = line[i + 1].x - line[i].x, dy = line[i + 1].y - line[i].y, len = std::hypot(dx, dy);
        const double t = std::clamp(((p.x - line[i].x) * dx + (p.y - line[i].y) * dy) / (len * len), 0.0, 1.0);
        const double d = std::hypot(p.x - line[i].x - t * dx, p.y - line[i].y - t * dy);
        if (d < best) best = d, along = m + t * len;
        m += len;
    }
    return {best, along};
}

}  // namespace

TEST(VehicleState, DeadReckoningFollowsTheTunnelWhenGnssIsLost) {
    const map::Projection proj(42.5, 1.5);
    const std::vector<map::PlanarPoint> path = {{0, 0}, {0, 300}, {100, 500}, {300, 600}, {600, 600}, {900, 700}};
    const double tunnel_from = 300.0, tunnel_to = 300.0 + 1063.4;
    constexpr double kLoss = 16.0, kV = 15.0;  // the last fix at y = 240
    for (const bool with_route : {false, true}) {
        SCOPED_TRACE(with_route ? "with a route out north" : "no route");
        const auto matcher = std::make_shared<const MapMatcher>(tunnelGraph(true));
        VehicleStateEstimator est(proj, matcher);
        if (with_route) {
            std::vector<map::PlanarPoint> r = path;
            r.push_back({900, 1100});
            est.setRoute(std::make_shared<const RouteLine>("r", r));
        }
        double last_along = 0.0;
        for (int i = 0; i <= int(110.0 * 50); ++i) {
            const double t = i * 0.02;
            est.addSample(motion(kV, 0.0, t));
            if (i % 10 == 0 && t <= kLoss) est.addSample(fix(proj, 0.0, kV * t, t, 0.0));
            if (i % 50 != 0 || t < kLoss + 5.0) continue;
            const EstimatedPose p = est.poseAt(at(t));
            const double driven = kV * t;
            ASSERT_TRUE(p.valid);
            if (driven < tunnel_to - 5.0) {
                // In the tunnel: on its shape, at the distance driven, never going back.
                const auto [off, along] = onPolyline(path, {p.x, p.y});
                EXPECT_LT(off, 0.5) << "t " << t << ": " << p.x << ", " << p.y;
                EXPECT_NEAR(along, driven, 1.0) << "t " << t;
                EXPECT_GE(along, last_along) << "t " << t;
                last_along = along;
                EXPECT_TRUE(p.follows_graph) << "t " << t;
                EXPECT_FALSE(p.stale) << "t " << t;
                EXPECT_EQ(p.in_tunnel, driven > tunnel_from + 1.0) << "t " << t;
                EXPECT_GT(p.since_fix_s, 4.0);
            } else if (driven > tunnel_to + 100.0) {
                // Out by the exit the route takes (else straight on), and stale: 2 s of driving
                // beyond the portal without a fix.
                EXPECT_TRUE(p.follows_graph) << "t " << t;
                EXPECT_FALSE(p.in_tunnel) << "t " << t;
                EXPECT_TRUE(p.stale) << "t " << t;
                const double beyond = driven - tunnel_to;
                if (with_route) {
                    EXPECT_NEAR(p.x, 900.0, 0.5) << "t " << t;
                    EXPECT_NEAR(p.y, 700.0 + beyond, 1.0) << "t " << t;
                } else {
                    EXPECT_NEAR(p.x, 900.0 + beyond, 1.0) << "t " << t;
                    EXPECT_NEAR(p.y, 700.0, 0.5) << "t " << t;
                }
            }
        }
        EXPECT_GT(last_along, tunnel_to - 20.0) << "the tunnel was not followed to its end";
    }
    // The same road without the tunnel flag: plain dead reckoning, frozen after 10 s and stale.
    VehicleStateEstimator est(proj, std::make_shared<const MapMatcher>(tunnelGraph(false)));
    for (int i = 0; i <= int(40.0 * 50); ++i) {
        const double t = i * 0.02;
        est.addSample(motion(kV, 0.0, t));
        if (i % 10 == 0 && t <= kLoss) est.addSample(fix(proj, 0.0, kV * t, t, 0.0));
    }
    const EstimatedPose p = est.poseAt(at(40.0));
    EXPECT_FALSE(p.follows_graph);
    EXPECT_TRUE(p.stale);
    EXPECT_FALSE(p.in_tunnel);
}
