// SPDX-License-Identifier: Apache-2.0
// GNSS + odometry fusion (docs/architecture.md "Data flow": "interpolate/extrapolate between fixes (dead
// reckoning with speed + yaw rate), snap to route/road graph"). A complementary filter: between
// fixes the track is integrated from speed and yaw rate; at a fix, a share of the innovation is
// taken (the GNSS is noisy but unbiased, the odometry smooth but drifting). A fix too far from
// the prediction is a jump and is rejected; several in a row mean the prediction is wrong, and
// the estimator re-initialises there.

#include "navmap/daemon/vehicle/vehicle_state_estimator.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace navmap::daemon {

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kDegToRad = kPi / 180.0;

double seconds(ipc::CanTime a, ipc::CanTime b) { return std::chrono::duration<double>(b - a).count(); }

double wrapPi(double a) {
    a = std::fmod(a + kPi, 2.0 * kPi);
    if (a < 0) a += 2.0 * kPi;
    return a - kPi;
}

std::string fmt(const char* f, double a, double b = 0.0) {
    char buf[160];
    std::snprintf(buf, sizeof buf, f, a, b);
    return buf;
}

// Pairing window for quantities of one GNSS epoch sent in separate frames.
constexpr double kPairS = 0.1;
constexpr double kEpochS = 0.5;

}  // namespace

VehicleStateEstimator::VehicleStateEstimator(map::Projection projection, std::shared_ptr<const MapMatcher> matcher,
                                             VehicleStateConfig config)
    : m_projection(projection) {
    m_state.config = config;
    m_state.matcher = std::move(matcher);
}

void VehicleStateEstimator::reject(std::uint64_t& counter, std::string why) {
    ++counter;
    m_counters.last_rejection = std::move(why);
}

void VehicleStateEstimator::setRoute(std::shared_ptr<const RouteLine> route) {
    m_state.route = std::move(route);
    m_state.route_measure.reset();
    changed();
}

void VehicleStateEstimator::rebase(const map::Projection& frame, const map::FrameTransform& to_frame,
                                   std::shared_ptr<const MapMatcher> matcher, double max_distance_from_origin_m,
                                   std::uint32_t epoch) {
    m_projection = frame;
    for (PoseAnchor& a : m_state.anchors) {
        a.x = to_frame.scale * a.x + to_frame.offset_x;
        a.y = to_frame.scale * a.y + to_frame.offset_y;
        a.jump_x *= to_frame.scale;
        a.jump_y *= to_frame.scale;
    }
    m_state.matcher = std::move(matcher);
    m_state.config.max_distance_from_origin_m = max_distance_from_origin_m;
    m_state.frame_epoch = epoch;
    setRoute(nullptr);
}

std::shared_ptr<const VehicleState> VehicleStateEstimator::snapshot() const {
    if (!m_snapshot) {
        m_snapshot = std::make_shared<const VehicleState>(m_state);
    }
    return m_snapshot;
}

void VehicleStateEstimator::addSample(const ipc::VehicleSample& u) {
    using ipc::VssSignal;
    if (u.get(VssSignal::Speed) || u.get(VssSignal::YawRate)) {
        addMotion(u);
    }
    if (const auto h = u.get(VssSignal::Heading)) {
        m_heading = {{*h, u.timeOf(VssSignal::Heading)}};
    }
    if (const auto f = u.get(VssSignal::FixType)) {
        m_fix_type = {{*f, u.timeOf(VssSignal::FixType)}};
    }
    if (const auto lat = u.get(VssSignal::Latitude)) {
        m_lat = {{*lat, u.timeOf(VssSignal::Latitude)}};
    }
    if (const auto lon = u.get(VssSignal::Longitude)) {
        m_lon = {{*lon, u.timeOf(VssSignal::Longitude)}};
    }
    if (m_lat && m_lon && std::abs(seconds(m_lat->second, m_lon->second)) <= kPairS) {
        const auto t = std::max(m_lat->second, m_lon->second);
        std::optional<double> heading, fix_type;
        if (m_heading && std::abs(seconds(m_heading->second, t)) <= kEpochS) heading = m_heading->first;
        if (m_fix_type && std::abs(seconds(m_fix_type->second, t)) <= kEpochS) fix_type = m_fix_type->first;
        const double lat = m_lat->first, lon = m_lon->first;
        m_lat.reset();
        m_lon.reset();
        addFix(t, lat, lon, heading, fix_type);
    }
}

void VehicleStateEstimator::addMotion(const ipc::VehicleSample& u) {
    using ipc::VssSignal;
    MotionSample s = m_state.motion.empty() ? MotionSample{} : m_state.motion.back();
    ipc::CanTime t{};
    for (const auto sig : {VssSignal::Speed, VssSignal::YawRate}) {
        const auto v = u.get(sig);
        if (!v) continue;
        if (!std::isfinite(*v)) {
            reject(m_counters.rejected_nan, std::string(ipc::vssName(sig)) + ": not a finite number");
            return;
        }
        if (*v < ipc::vssMinimum(sig) || *v > ipc::vssMaximum(sig)) {
            reject(m_counters.rejected_range, std::string(ipc::vssName(sig)) + ": " +
                                                  fmt("%g out of range [%g, ", *v, ipc::vssMinimum(sig)) +
                                                  fmt("%g]", ipc::vssMaximum(sig)));
            return;
        }
        t = std::max(t, u.timeOf(sig));
    }
    if (!m_state.motion.empty() && t < m_state.motion.back().time) {
        reject(m_counters.rejected_order, "motion sample older than the previous one");
        return;
    }
    if (const auto v = u.get(VssSignal::Speed)) {
        s.speed_mps = *v / 3.6;
    }
    if (const auto w = u.get(VssSignal::YawRate)) {
        // VSS/ISO 8855: positive yaw = counter-clockwise; our heading turns clockwise.
        s.heading_rate_rad_s = (m_state.config.yaw_rate_positive_left ? -*w : *w) * kDegToRad;
        m_last_yaw_time = u.timeOf(VssSignal::YawRate);
    }
    s.time = t;
    if (!m_state.motion.empty() && m_state.motion.back().time == t) {
        m_state.motion.back() = s;
    } else {
        m_state.motion.push_back(s);
    }
    ++m_counters.motion_samples;
    prune();
    if (m_state.motion.size() % 5 == 0) {
        updateMatch(t);  // hysteresis state follows the vehicle between fixes (10 Hz at 50 Hz input)
    }
    changed();
}

void VehicleStateEstimator::relocate(ipc::CanTime t, map::PlanarPoint p, std::optional<double> heading_deg) {
    PoseAnchor a;
    a.time = t;
    a.x = p.x;
    a.y = p.y;
    if (heading_deg) {
        a.heading_rad = *heading_deg * kDegToRad;
        m_state.heading_known = true;
    } else if (!m_state.anchors.empty()) {
        a.heading_rad = m_state.anchors.back().heading_rad;
    }
    double x = 0, y = 0, h = 0, v = 0;
    deadReckon(m_state.motion, t, t, m_state.config.motion_timeout_s, 0.0, x, y, h, v);
    a.speed_mps = v;
    if (!m_state.anchors.empty()) {
        ++m_counters.relocations;
    }
    m_state.anchors.clear();
    m_state.anchors.push_back(a);
    m_state.matched_edge.reset();
    m_state.route_measure.reset();
    m_consecutive_jumps = 0;
}

void VehicleStateEstimator::addFix(ipc::CanTime t, double lat, double lon, std::optional<double> heading_deg,
                                   std::optional<double> fix_type) {
    const auto& cfg = m_state.config;
    if (!std::isfinite(lat) || !std::isfinite(lon)) {
        reject(m_counters.rejected_nan, "GNSS fix: latitude/longitude not finite");
        return;
    }
    if (lat < -90.0 || lat > 90.0 || lon < -180.0 || lon > 180.0) {
        reject(m_counters.rejected_range, fmt("GNSS fix: latitude %g / longitude %g out of range", lat, lon));
        return;
    }
    if (fix_type && *fix_type < 0.5) {
        reject(m_counters.rejected_no_fix, "GNSS fix: fix type NONE");
        return;
    }
    if (heading_deg && (!std::isfinite(*heading_deg) || *heading_deg < 0.0 || *heading_deg > 360.0)) {
        heading_deg.reset();  // position still usable; the course is not
    }
    const map::PlanarPoint p = m_projection.forward(lat, lon);
    const double from_origin = std::hypot(p.x, p.y);
    if (!std::isfinite(from_origin) || from_origin > cfg.max_distance_from_origin_m) {
        reject(m_counters.rejected_range, fmt("GNSS fix: %.0f km from the map origin (limit %.0f km)",
                                              from_origin / 1000.0, cfg.max_distance_from_origin_m / 1000.0));
        return;
    }
    auto& anchors = m_state.anchors;
    if (!anchors.empty() && t <= anchors.back().time) {
        reject(m_counters.rejected_order, "GNSS fix older than the previous fix");
        return;
    }
    if (!m_state.motion.empty() && seconds(t, m_state.motion.back().time) > cfg.max_fix_age_s) {
        reject(m_counters.rejected_order, "GNSS fix older than the motion data by more than maxFixAgeS");
        return;
    }
    ++m_counters.fixes;
    if (anchors.empty() || seconds(anchors.back().time, t) > cfg.gnss_timeout_s) {
        // First fix, or position regained after a stale period: start over here.
        relocate(t, p, heading_deg);
        prune();
        updateMatch(t);
        changed();
        return;
    }
    const PoseAnchor& last = anchors.back();
    double px = last.x, py = last.y, ph = last.heading_rad, pv = 0;
    deadReckon(m_state.motion, last.time, t, cfg.motion_timeout_s, last.speed_mps, px, py, ph, pv);
    const double dt_fix = seconds(last.time, t);
    const double innovation = std::hypot(p.x - px, p.y - py);
    if (innovation > cfg.jump_gate_m + cfg.jump_gate_growth_mps * dt_fix) {
        if (++m_consecutive_jumps < cfg.jumps_to_relocate) {
            --m_counters.fixes;
            reject(m_counters.rejected_jump, fmt("GNSS fix: jump of %.1f m from the prediction (gate %.1f m)",
                                                 innovation, cfg.jump_gate_m + cfg.jump_gate_growth_mps * dt_fix));
            return;
        }
        relocate(t, p, heading_deg);  // the prediction was wrong, not the receiver
        prune();
        updateMatch(t);
        changed();
        return;
    }
    m_consecutive_jumps = 0;
    // The displayed pose just before this fix, to fade the correction in (VehicleState::compute).
    const double fade = cfg.blend_s > 0 ? std::max(0.0, 1.0 - dt_fix / cfg.blend_s) : 0.0;
    const double shown_x = px + last.jump_x * fade;
    const double shown_y = py + last.jump_y * fade;
    const double shown_h = ph + last.jump_heading_rad * fade;

    const bool have_motion = !m_state.motion.empty() && seconds(m_state.motion.back().time, t) <= cfg.motion_timeout_s;
    const bool have_yaw = m_last_yaw_time && std::abs(seconds(*m_last_yaw_time, t)) <= cfg.motion_timeout_s;
    const double k = have_motion ? cfg.position_gain : 1.0;
    PoseAnchor a;
    a.time = t;
    a.x = px + k * (p.x - px);
    a.y = py + k * (p.y - py);
    a.speed_mps = pv;
    a.heading_rad = ph;
    if (heading_deg && std::abs(pv) >= cfg.course_min_speed_mps) {
        const double kh = have_yaw ? cfg.heading_gain : 1.0;
        a.heading_rad = ph + kh * wrapPi(*heading_deg * kDegToRad - ph);
        m_state.heading_known = true;
    } else if (!have_yaw) {
        // No gyro and no usable course: the direction between fixes.
        const double dx = p.x - last.x, dy = p.y - last.y;
        if (std::hypot(dx, dy) > 2.0) {
            a.heading_rad = std::atan2(dx, dy);
            m_state.heading_known = true;
        }
    } else if (heading_deg) {
        m_state.heading_known = true;
    }
    a.heading_rad = wrapPi(a.heading_rad);
    a.jump_x = shown_x - a.x;
    a.jump_y = shown_y - a.y;
    a.jump_heading_rad = wrapPi(shown_h - a.heading_rad);
    anchors.push_back(a);
    prune();
    updateMatch(t);
    changed();
}

void VehicleStateEstimator::prune() {
    auto& anchors = m_state.anchors;
    const double keep = m_state.config.history_s;
    if (anchors.size() > 1) {
        const auto newest = anchors.back().time;
        const auto it = std::find_if(anchors.begin(), anchors.end() - 1,
                                     [&](const PoseAnchor& a) { return seconds(a.time, newest) <= keep; });
        anchors.erase(anchors.begin(), it);
    }
    auto& motion = m_state.motion;
    // Keep one sample before the oldest anchor (interpolation), and at most ~20 s of samples
    // when fixes stop (dead reckoning is capped anyway).
    ipc::CanTime cutoff =
        anchors.empty() ? (motion.empty() ? ipc::CanTime{} : motion.back().time) : anchors.front().time;
    if (!motion.empty()) {
        cutoff = std::max(cutoff, motion.back().time - std::chrono::seconds(20));
    }
    const auto it = std::upper_bound(motion.begin(), motion.end(), cutoff,
                                     [](ipc::CanTime tt, const MotionSample& s) { return tt < s.time; });
    if (it != motion.begin() && std::prev(it) != motion.begin()) {
        // The distance driven since the newest anchor over the samples that go (VehicleState::Parts::odometer_m).
        if (!anchors.empty()) {
            const ipc::CanTime anchor = anchors.back().time, kept = std::prev(it)->time;
            if (m_state.odometer_time < anchor) {
                m_state.odometer_m = 0.0;
                m_state.odometer_time = anchor;
            }
            if (kept > m_state.odometer_time) {
                m_state.odometer_m += distanceDriven(motion, m_state.odometer_time, kept,
                                                     m_state.config.motion_timeout_s, anchors.back().speed_mps);
                m_state.odometer_time = kept;
            }
        }
        motion.erase(motion.begin(), std::prev(it));
    }
}

void VehicleStateEstimator::updateMatch(ipc::CanTime t) {
    if (m_state.anchors.empty() || (!m_state.matcher && !m_state.route)) {
        return;
    }
    const EstimatedPose pose = VehicleState::compute(m_state, t);
    m_state.matched_edge = pose.match_confidence >= m_state.config.snap_min_confidence ? pose.edge : std::nullopt;
    // At a fix: where dead reckoning along the road graph would start (docs/vehicle-state.md
    // "Tunnels"). On the route, the road under the route's point in the route's direction: near
    // junctions the road match may still hold a neighbouring road.
    if (t == m_state.anchors.back().time) {
        const auto& cfg = m_state.config;
        std::optional<std::uint32_t> edge = pose.road_confidence >= cfg.snap_full_confidence ? pose.edge : std::nullopt;
        if (pose.on_route && m_state.matcher) {
            const auto on = m_state.route->match({pose.raw_x, pose.raw_y}, std::nullopt, m_state.route_measure, cfg);
            const auto road = on ? m_state.matcher->match(on->point, on->heading_deg, edge, cfg) : std::nullopt;
            if (road && road->confidence >= cfg.snap_full_confidence) edge = road->edge;
        }
        m_state.anchors.back().edge = edge;
    }
    m_state.route_measure = pose.on_route ? std::optional<double>(pose.route_driven_m) : std::nullopt;
}

}  // namespace navmap::daemon
