// SPDX-License-Identifier: Apache-2.0
// Pose evaluation over an immutable snapshot: dead reckoning from the newest fused anchor (or
// interpolation between two anchors for a past time), the fix correction faded in over blendS so
// the marker never jumps, then map matching with a confidence-weighted snap.

#include "navmap/daemon/vehicle/vehicle_state.h"

#include <algorithm>
#include <cmath>

namespace navmap::daemon {

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kRadToDeg = 180.0 / kPi;

double seconds(ipc::CanTime a, ipc::CanTime b) {  // b - a
    return std::chrono::duration<double>(b - a).count();
}

double wrapPi(double a) {
    a = std::fmod(a + kPi, 2.0 * kPi);
    if (a < 0) a += 2.0 * kPi;
    return a - kPi;
}

double wrapDeg360(double d) {
    d = std::fmod(d, 360.0);
    return d < 0 ? d + 360.0 : d;
}

// Motion at time `tau`: linear between samples, held for holdS after the last, fallback before
// the first. `hint` speeds up the sequential lookups of one integration.
void motionAt(const std::vector<MotionSample>& m, ipc::CanTime tau, double holdS, double fallbackSpeed,
              std::size_t& hint, double& v, double& w) {
    if (m.empty() || tau < m.front().time) {
        v = fallbackSpeed;
        w = 0.0;
        return;
    }
    if (tau >= m.back().time) {
        const bool held = seconds(m.back().time, tau) <= holdS;
        v = held ? m.back().speedMps : 0.0;
        w = held ? m.back().headingRateRadS : 0.0;
        return;
    }
    hint = std::min(hint, m.size() - 1);
    if (m[hint].time > tau) hint = 0;
    while (hint + 1 < m.size() && m[hint + 1].time <= tau) ++hint;
    const auto& a = m[hint];
    const auto& b = m[hint + 1];
    const double span = seconds(a.time, b.time);
    const double f = span > 0 ? seconds(a.time, tau) / span : 0.0;
    v = a.speedMps + f * (b.speedMps - a.speedMps);
    w = a.headingRateRadS + f * (b.headingRateRadS - a.headingRateRadS);
}

ipc::CanTime newestMotionAtOrBefore(const std::vector<MotionSample>& m, ipc::CanTime t) {
    const auto it =
        std::upper_bound(m.begin(), m.end(), t, [](ipc::CanTime tt, const MotionSample& s) { return tt < s.time; });
    return it == m.begin() ? ipc::CanTime{} : std::prev(it)->time;
}

}  // namespace

void deadReckon(const std::vector<MotionSample>& motion, ipc::CanTime from, ipc::CanTime to, double holdS,
                double fallbackSpeed, double& x, double& y, double& headingRad, double& speedMps) {
    const double total = seconds(from, to);
    std::size_t hint = 0;
    double v = 0.0, w = 0.0;
    if (total <= 0.0) {
        motionAt(motion, from, holdS, fallbackSpeed, hint, v, w);
        speedMps = v;
        return;
    }
    const int steps = std::max(1, static_cast<int>(std::ceil(total / 0.02)));
    const double dt = total / steps;
    for (int i = 0; i < steps; ++i) {
        // Midpoint rule: motion and heading at the middle of the step.
        const auto mid =
            from + std::chrono::duration_cast<ipc::CanTime::duration>(std::chrono::duration<double>((i + 0.5) * dt));
        motionAt(motion, mid, holdS, fallbackSpeed, hint, v, w);
        const double hMid = headingRad + 0.5 * w * dt;
        x += v * dt * std::sin(hMid);
        y += v * dt * std::cos(hMid);
        headingRad += w * dt;
    }
    motionAt(motion, to, holdS, fallbackSpeed, hint, v, w);
    speedMps = v;
}

EstimatedPose VehicleState::compute(const Parts& p, ipc::CanTime t) {
    EstimatedPose pose;
    pose.time = t;
    const auto& cfg = p.config;
    if (p.anchors.empty()) {
        pose.stale = true;
        return pose;
    }
    const PoseAnchor& last = p.anchors.back();
    double x = 0, y = 0, h = 0, v = 0;
    ipc::CanTime anchorTime = last.time;
    if (t >= last.time || p.anchors.size() == 1) {
        // Present: dead reckoning from the newest anchor, the correction faded in.
        const auto limit = last.time + std::chrono::duration_cast<ipc::CanTime::duration>(
                                           std::chrono::duration<double>(cfg.maxDeadReckoningS));
        const auto tEff = std::clamp(t, last.time, limit);
        x = last.x;
        y = last.y;
        h = last.headingRad;
        deadReckon(p.motion, last.time, tEff, cfg.motionTimeoutS, last.speedMps, x, y, h, v);
        const double fade = cfg.blendS > 0 ? std::max(0.0, 1.0 - seconds(last.time, tEff) / cfg.blendS) : 0.0;
        x += last.jumpX * fade;
        y += last.jumpY * fade;
        h += last.jumpHeadingRad * fade;
    } else if (t <= p.anchors.front().time) {
        const auto& a = p.anchors.front();
        x = a.x, y = a.y, h = a.headingRad, v = a.speedMps;
        anchorTime = a.time;
    } else {
        // Past: dead reckoning from the anchor before t, the closure error to the next anchor
        // distributed linearly, so the track passes through both anchors.
        const auto it = std::upper_bound(p.anchors.begin(), p.anchors.end(), t,
                                         [](ipc::CanTime tt, const PoseAnchor& a) { return tt < a.time; });
        const PoseAnchor& a = *std::prev(it);
        const PoseAnchor& b = *it;
        anchorTime = a.time;
        x = a.x, y = a.y, h = a.headingRad;
        deadReckon(p.motion, a.time, t, cfg.motionTimeoutS, a.speedMps, x, y, h, v);
        double qx = a.x, qy = a.y, qh = a.headingRad, qv = 0;
        deadReckon(p.motion, a.time, b.time, cfg.motionTimeoutS, a.speedMps, qx, qy, qh, qv);
        const double f = seconds(a.time, t) / seconds(a.time, b.time);
        x += f * (b.x - qx);
        y += f * (b.y - qy);
        h += f * wrapPi(b.headingRad - qh);
    }
    pose.valid = true;
    pose.rawX = x;
    pose.rawY = y;
    pose.x = x;
    pose.y = y;
    pose.headingDeg = wrapDeg360(h * kRadToDeg);
    pose.speedMps = v;
    pose.sinceFixS = std::max(0.0, seconds(last.time, t));
    pose.stale = pose.sinceFixS > cfg.gnssTimeoutS;
    pose.sourceTime = std::max(std::min(anchorTime, t), newestMotionAtOrBefore(p.motion, t));

    // Map matching: the route first, the road graph otherwise (not from the seed; docs/vehicle-state.md "Map
    // matching").
    const std::optional<double> heading =
        p.headingKnown && std::abs(v) >= cfg.headingMinSpeedMps ? std::optional<double>(pose.headingDeg) : std::nullopt;
    const map::PlanarPoint raw{x, y};
    std::optional<RouteMatch> rm;
    if (p.route) {
        rm = p.route->match(raw, heading, p.routeMeasure, cfg);
    }
    std::optional<RoadMatch> road;
    if (p.matcher) {
        road = p.matcher->match(raw, heading, p.matchedEdge, cfg);
    }
    map::PlanarPoint target{};
    double targetHeading = 0.0;
    double conf = 0.0;
    if (rm && (!road || rm->confidence * std::exp(0.5 * cfg.routeBonus) >= road->confidence)) {
        target = rm->point;
        targetHeading = rm->headingDeg;
        conf = rm->confidence;
    } else if (road) {
        target = road->point;
        targetHeading = road->headingDeg;
        conf = road->confidence;
    }
    if (road) {
        pose.edge = road->edge;
    }
    if (rm && rm->confidence >= cfg.snapMinConfidence) {
        pose.onRoute = true;
        pose.routeDrivenM = rm->measureM;
        pose.routeRemainingM = std::max(0.0, p.route->lengthM() - rm->measureM);
    }
    pose.matchConfidence = conf;
    const double span = cfg.snapFullConfidence - cfg.snapMinConfidence;
    const double wSnap =
        span > 0 ? std::clamp((conf - cfg.snapMinConfidence) / span, 0.0, 1.0) : (conf > 0 ? 1.0 : 0.0);
    pose.snapWeight = wSnap;
    if (wSnap > 0) {
        pose.x = x + wSnap * (target.x - x);
        pose.y = y + wSnap * (target.y - y);
        // The heading stays the fused one: road polylines turn in steps at their vertices,
        // the gyro-driven heading does not.
    }
    pose.roadHeadingDeg = conf > 0 ? std::optional<double>(targetHeading) : std::nullopt;
    return pose;
}

}  // namespace navmap::daemon
