// SPDX-License-Identifier: Apache-2.0
// Pose evaluation over an immutable snapshot: dead reckoning from the newest fused anchor (or
// interpolation between two anchors for a past time), the fix correction faded in over blend_s so
// the marker never jumps, then map matching with a confidence-weighted snap.

#include "navmap/daemon/vehicle/vehicle_state.h"

#include <algorithm>
#include <cmath>

#include "graph_walk.h"

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
void motionAt(const std::vector<MotionSample>& m, ipc::CanTime tau, double hold_s, double fallback_speed,
              std::size_t& hint, double& v, double& w) {
    if (m.empty() || tau < m.front().time) {
        v = fallback_speed;
        w = 0.0;
        return;
    }
    if (tau >= m.back().time) {
        const bool held = seconds(m.back().time, tau) <= hold_s;
        v = held ? m.back().speed_mps : 0.0;
        w = held ? m.back().heading_rate_rad_s : 0.0;
        return;
    }
    hint = std::min(hint, m.size() - 1);
    if (m[hint].time > tau) hint = 0;
    while (hint + 1 < m.size() && m[hint + 1].time <= tau) ++hint;
    const auto& a = m[hint];
    const auto& b = m[hint + 1];
    const double span = seconds(a.time, b.time);
    const double f = span > 0 ? seconds(a.time, tau) / span : 0.0;
    v = a.speed_mps + f * (b.speed_mps - a.speed_mps);
    w = a.heading_rate_rad_s + f * (b.heading_rate_rad_s - a.heading_rate_rad_s);
}

ipc::CanTime newestMotionAtOrBefore(const std::vector<MotionSample>& m, ipc::CanTime t) {
    const auto it =
        std::upper_bound(m.begin(), m.end(), t, [](ipc::CanTime tt, const MotionSample& s) { return tt < s.time; });
    return it == m.begin() ? ipc::CanTime{} : std::prev(it)->time;
}

/// Whether the speed limit of `edge` holds whichever way the vehicle faces on its road: a one-way
/// road, or a two-way road whose twin edge (the same way and shape, the other way round) has the
/// same limit. Without a heading the matcher cannot tell the twins apart.
bool limitHoldsBothWays(const map::RoadGraph& g, std::uint32_t edge) {
    const map::GraphEdge& e = g.edges[edge];
    for (const map::GraphEdge& t : g.outEdges(e.to)) {
        if (t.to == e.from && t.way_id == e.way_id && t.shape_begin == e.shape_begin && t.shape_end == e.shape_end &&
            (t.flags & map::edge_flags::kReversed) != (e.flags & map::edge_flags::kReversed))
            return t.speed_limit_kmh == e.speed_limit_kmh;
    }
    return true;  // no twin: one-way
}

ipc::CanTime after(ipc::CanTime t, double s) {
    return t + std::chrono::duration_cast<ipc::CanTime::duration>(std::chrono::duration<double>(s));
}

// Dead reckoning along the road graph (docs/vehicle-state.md "Tunnels"): after
// graph_follow_after_s without a fix, from the road edge matched at the newest anchor, the
// distance driven since is walked along the graph; used when the walk passes a tunnel.
std::optional<GraphWalk> tunnelWalk(const VehicleState::Parts& p, ipc::CanTime t) {
    const auto& cfg = p.config;
    if (p.anchors.empty() || !p.matcher) return std::nullopt;
    const PoseAnchor& last = p.anchors.back();
    if (!last.edge || seconds(last.time, t) <= cfg.graph_follow_after_s) return std::nullopt;
    const ipc::CanTime to = std::min(t, after(last.time, cfg.tunnel_dead_reckoning_s));
    ipc::CanTime from = last.time;
    double driven = 0.0;
    if (p.odometer_time > from && p.odometer_time <= to) {
        driven = p.odometer_m;
        from = p.odometer_time;
    }
    driven += distanceDriven(p.motion, from, to, cfg.motion_timeout_s, last.speed_mps);
    auto walk =
        walkGraph(p.matcher->graph(), *last.edge, {last.x, last.y}, driven, p.route.get(), p.route_measure, cfg);
    if (!walk || !walk->tunnel) return std::nullopt;
    return walk;
}

}  // namespace

double distanceDriven(const std::vector<MotionSample>& motion, ipc::CanTime from, ipc::CanTime to, double hold_s,
                      double fallback_speed) {
    if (!(to > from)) return 0.0;
    // The speed is linear between the breakpoints (the samples' times and the end of the hold):
    // the midpoint rule is exact on each piece.
    std::vector<ipc::CanTime> cuts{from};
    const auto first = std::upper_bound(motion.begin(), motion.end(), from,
                                        [](ipc::CanTime tt, const MotionSample& m) { return tt < m.time; });
    for (auto it = first; it != motion.end() && it->time < to; ++it) cuts.push_back(it->time);
    if (!motion.empty()) {
        const ipc::CanTime hold_end = after(motion.back().time, hold_s);
        if (hold_end > cuts.back() && hold_end < to) cuts.push_back(hold_end);
    }
    cuts.push_back(to);
    std::size_t hint = 0;
    double d = 0.0;
    for (std::size_t i = 0; i + 1 < cuts.size(); ++i) {
        const double span = seconds(cuts[i], cuts[i + 1]);
        double v = 0.0, w = 0.0;
        motionAt(motion, cuts[i] + (cuts[i + 1] - cuts[i]) / 2, hold_s, fallback_speed, hint, v, w);
        d += v * span;
    }
    return d;
}

void deadReckon(const std::vector<MotionSample>& motion, ipc::CanTime from, ipc::CanTime to, double hold_s,
                double fallback_speed, double& x, double& y, double& heading_rad, double& speed_mps) {
    const double total = seconds(from, to);
    std::size_t hint = 0;
    double v = 0.0, w = 0.0;
    if (total <= 0.0) {
        motionAt(motion, from, hold_s, fallback_speed, hint, v, w);
        speed_mps = v;
        return;
    }
    const int steps = std::max(1, static_cast<int>(std::ceil(total / 0.02)));
    const double dt = total / steps;
    for (int i = 0; i < steps; ++i) {
        // Midpoint rule: motion and heading at the middle of the step.
        const auto mid =
            from + std::chrono::duration_cast<ipc::CanTime::duration>(std::chrono::duration<double>((i + 0.5) * dt));
        motionAt(motion, mid, hold_s, fallback_speed, hint, v, w);
        const double h_mid = heading_rad + 0.5 * w * dt;
        x += v * dt * std::sin(h_mid);
        y += v * dt * std::cos(h_mid);
        heading_rad += w * dt;
    }
    motionAt(motion, to, hold_s, fallback_speed, hint, v, w);
    speed_mps = v;
}

EstimatedPose VehicleState::compute(const Parts& p, ipc::CanTime t) {
    EstimatedPose pose;
    pose.time = t;
    pose.frame_epoch = p.frame_epoch;
    const auto& cfg = p.config;
    if (p.anchors.empty()) {
        pose.stale = true;
        return pose;
    }
    const PoseAnchor& last = p.anchors.back();
    double x = 0, y = 0, h = 0, v = 0;
    ipc::CanTime anchor_time = last.time;
    if (t >= last.time || p.anchors.size() == 1) {
        // Present: dead reckoning from the newest anchor, the correction faded in.
        const auto limit = last.time + std::chrono::duration_cast<ipc::CanTime::duration>(
                                           std::chrono::duration<double>(cfg.max_dead_reckoning_s));
        const auto t_eff = std::clamp(t, last.time, limit);
        x = last.x;
        y = last.y;
        h = last.heading_rad;
        deadReckon(p.motion, last.time, t_eff, cfg.motion_timeout_s, last.speed_mps, x, y, h, v);
        const double fade = cfg.blend_s > 0 ? std::max(0.0, 1.0 - seconds(last.time, t_eff) / cfg.blend_s) : 0.0;
        x += last.jump_x * fade;
        y += last.jump_y * fade;
        h += last.jump_heading_rad * fade;
    } else if (t <= p.anchors.front().time) {
        const auto& a = p.anchors.front();
        x = a.x, y = a.y, h = a.heading_rad, v = a.speed_mps;
        anchor_time = a.time;
    } else {
        // Past: dead reckoning from the anchor before t, the closure error to the next anchor
        // distributed linearly, so the track passes through both anchors.
        const auto it = std::upper_bound(p.anchors.begin(), p.anchors.end(), t,
                                         [](ipc::CanTime tt, const PoseAnchor& a) { return tt < a.time; });
        const PoseAnchor& a = *std::prev(it);
        const PoseAnchor& b = *it;
        anchor_time = a.time;
        x = a.x, y = a.y, h = a.heading_rad;
        deadReckon(p.motion, a.time, t, cfg.motion_timeout_s, a.speed_mps, x, y, h, v);
        double qx = a.x, qy = a.y, qh = a.heading_rad, qv = 0;
        deadReckon(p.motion, a.time, b.time, cfg.motion_timeout_s, a.speed_mps, qx, qy, qh, qv);
        const double f = seconds(a.time, t) / seconds(a.time, b.time);
        x += f * (b.x - qx);
        y += f * (b.y - qy);
        h += f * wrapPi(b.heading_rad - qh);
    }
    const std::optional<GraphWalk> walk = t > last.time ? tunnelWalk(p, t) : std::nullopt;
    if (walk) {
        x = walk->point.x;
        y = walk->point.y;
        h = walk->heading_rad;
        std::size_t hint = 0;
        double w = 0.0;
        motionAt(p.motion, t, cfg.motion_timeout_s, last.speed_mps, hint, v, w);
        pose.follows_graph = true;
    }
    pose.valid = true;
    pose.raw_x = x;
    pose.raw_y = y;
    pose.x = x;
    pose.y = y;
    pose.heading_deg = wrapDeg360(h * kRadToDeg);
    pose.speed_mps = v;
    pose.since_fix_s = std::max(0.0, seconds(last.time, t));
    // Following a tunnel the position is known without fixes: inside and until gnss_timeout_s
    // of driving beyond its end.
    const bool tunnel_known =
        walk && (walk->in_tunnel || walk->beyond_tunnel_m <= std::max(std::abs(v), 1.0) * cfg.gnss_timeout_s);
    pose.stale = pose.since_fix_s > cfg.gnss_timeout_s && !tunnel_known;
    pose.source_time = std::max(std::min(anchor_time, t), newestMotionAtOrBefore(p.motion, t));

    // Map matching: the route first, the road graph otherwise (not from the seed; docs/vehicle-state.md "Map
    // matching").
    const std::optional<double> heading = p.heading_known && std::abs(v) >= cfg.heading_min_speed_mps
                                              ? std::optional<double>(pose.heading_deg)
                                              : std::nullopt;
    const map::PlanarPoint raw{x, y};
    std::optional<RouteMatch> rm;
    if (p.route) {
        rm = p.route->match(raw, heading, p.route_measure, cfg);
    }
    std::optional<RoadMatch> road;
    if (walk) {
        road = RoadMatch{walk->edge, raw, pose.heading_deg, 0.0, 1.0, 0.0};  // on the edge walked
    } else if (p.matcher) {
        road = p.matcher->match(raw, heading, p.matched_edge, cfg);
    }
    map::PlanarPoint target{};
    double target_heading = 0.0;
    double conf = 0.0;
    if (rm && (!road || rm->confidence * std::exp(0.5 * cfg.route_bonus) >= road->confidence)) {
        target = rm->point;
        target_heading = rm->heading_deg;
        conf = rm->confidence;
    } else if (road) {
        target = road->point;
        target_heading = road->heading_deg;
        conf = road->confidence;
    }
    if (road) {
        pose.edge = road->edge;
        // The limit is shown only where the road and its direction are certain: a wrong sign is
        // worse than none.
        const bool direction_known = heading.has_value() || limitHoldsBothWays(p.matcher->graph(), road->edge);
        pose.road_match_certain = !pose.stale && road->confidence >= cfg.snap_full_confidence;
        if (pose.road_match_certain && direction_known)
            pose.speed_limit_kmh = p.matcher->graph().edges[road->edge].speed_limit_kmh;
        pose.road_confidence = road->confidence;
        pose.in_tunnel = !pose.stale && road->confidence >= cfg.snap_full_confidence &&
                         (p.matcher->graph().edges[road->edge].flags & map::road_flags::kTunnel) != 0;
    }
    if (rm && rm->confidence >= cfg.snap_min_confidence) {
        pose.on_route = true;
        pose.route_driven_m = rm->measure_m;
        pose.route_remaining_m = std::max(0.0, p.route->lengthM() - rm->measure_m);
    }
    pose.match_confidence = conf;
    const double span = cfg.snap_full_confidence - cfg.snap_min_confidence;
    const double w_snap =
        span > 0 ? std::clamp((conf - cfg.snap_min_confidence) / span, 0.0, 1.0) : (conf > 0 ? 1.0 : 0.0);
    pose.snap_weight = w_snap;
    if (w_snap > 0) {
        pose.x = x + w_snap * (target.x - x);
        pose.y = y + w_snap * (target.y - y);
        // The heading stays the fused one: road polylines turn in steps at their vertices,
        // the gyro-driven heading does not.
    }
    pose.road_heading_deg = conf > 0 ? std::optional<double>(target_heading) : std::nullopt;
    return pose;
}

}  // namespace navmap::daemon
