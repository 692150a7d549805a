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
    : m_projection(std::move(projection)) {
    m_state.config = config;
    m_state.matcher = std::move(matcher);
}

void VehicleStateEstimator::reject(std::uint64_t& counter, std::string why) {
    ++counter;
    m_counters.lastRejection = std::move(why);
}

void VehicleStateEstimator::setRoute(std::shared_ptr<const RouteLine> route) {
    m_state.route = std::move(route);
    m_state.routeMeasure.reset();
    changed();
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
        m_fixType = {{*f, u.timeOf(VssSignal::FixType)}};
    }
    if (const auto lat = u.get(VssSignal::Latitude)) {
        m_lat = {{*lat, u.timeOf(VssSignal::Latitude)}};
    }
    if (const auto lon = u.get(VssSignal::Longitude)) {
        m_lon = {{*lon, u.timeOf(VssSignal::Longitude)}};
    }
    if (m_lat && m_lon && std::abs(seconds(m_lat->second, m_lon->second)) <= kPairS) {
        const auto t = std::max(m_lat->second, m_lon->second);
        std::optional<double> heading, fixType;
        if (m_heading && std::abs(seconds(m_heading->second, t)) <= kEpochS) heading = m_heading->first;
        if (m_fixType && std::abs(seconds(m_fixType->second, t)) <= kEpochS) fixType = m_fixType->first;
        const double lat = m_lat->first, lon = m_lon->first;
        m_lat.reset();
        m_lon.reset();
        addFix(t, lat, lon, heading, fixType);
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
            reject(m_counters.rejectedNaN, std::string(ipc::vssName(sig)) + ": not a finite number");
            return;
        }
        if (*v < ipc::vssMinimum(sig) || *v > ipc::vssMaximum(sig)) {
            reject(m_counters.rejectedRange, std::string(ipc::vssName(sig)) + ": " +
                                                 fmt("%g out of range [%g, ", *v, ipc::vssMinimum(sig)) +
                                                 fmt("%g]", ipc::vssMaximum(sig)));
            return;
        }
        t = std::max(t, u.timeOf(sig));
    }
    if (!m_state.motion.empty() && t < m_state.motion.back().time) {
        reject(m_counters.rejectedOrder, "motion sample older than the previous one");
        return;
    }
    if (const auto v = u.get(VssSignal::Speed)) {
        s.speedMps = *v / 3.6;
    }
    if (const auto w = u.get(VssSignal::YawRate)) {
        // VSS/ISO 8855: positive yaw = counter-clockwise; our heading turns clockwise.
        s.headingRateRadS = (m_state.config.yawRatePositiveLeft ? -*w : *w) * kDegToRad;
        m_lastYawTime = u.timeOf(VssSignal::YawRate);
    }
    s.time = t;
    if (!m_state.motion.empty() && m_state.motion.back().time == t) {
        m_state.motion.back() = s;
    } else {
        m_state.motion.push_back(s);
    }
    ++m_counters.motionSamples;
    prune();
    if (m_state.motion.size() % 5 == 0) {
        updateMatch(t);  // hysteresis state follows the vehicle between fixes (10 Hz at 50 Hz input)
    }
    changed();
}

void VehicleStateEstimator::relocate(ipc::CanTime t, map::PlanarPoint p, std::optional<double> headingDeg) {
    PoseAnchor a;
    a.time = t;
    a.x = p.x;
    a.y = p.y;
    if (headingDeg) {
        a.headingRad = *headingDeg * kDegToRad;
        m_state.headingKnown = true;
    } else if (!m_state.anchors.empty()) {
        a.headingRad = m_state.anchors.back().headingRad;
    }
    double x = 0, y = 0, h = 0, v = 0;
    deadReckon(m_state.motion, t, t, m_state.config.motionTimeoutS, 0.0, x, y, h, v);
    a.speedMps = v;
    if (!m_state.anchors.empty()) {
        ++m_counters.relocations;
    }
    m_state.anchors.clear();
    m_state.anchors.push_back(a);
    m_state.matchedEdge.reset();
    m_state.routeMeasure.reset();
    m_consecutiveJumps = 0;
}

void VehicleStateEstimator::addFix(ipc::CanTime t, double lat, double lon, std::optional<double> headingDeg,
                                   std::optional<double> fixType) {
    const auto& cfg = m_state.config;
    if (!std::isfinite(lat) || !std::isfinite(lon)) {
        reject(m_counters.rejectedNaN, "GNSS fix: latitude/longitude not finite");
        return;
    }
    if (lat < -90.0 || lat > 90.0 || lon < -180.0 || lon > 180.0) {
        reject(m_counters.rejectedRange, fmt("GNSS fix: latitude %g / longitude %g out of range", lat, lon));
        return;
    }
    if (fixType && *fixType < 0.5) {
        reject(m_counters.rejectedNoFix, "GNSS fix: fix type NONE");
        return;
    }
    if (headingDeg && (!std::isfinite(*headingDeg) || *headingDeg < 0.0 || *headingDeg > 360.0)) {
        headingDeg.reset();  // position still usable; the course is not
    }
    const map::PlanarPoint p = m_projection.forward(lat, lon);
    const double fromOrigin = std::hypot(p.x, p.y);
    if (!std::isfinite(fromOrigin) || fromOrigin > cfg.maxDistanceFromOriginM) {
        reject(m_counters.rejectedRange, fmt("GNSS fix: %.0f km from the map origin (limit %.0f km)",
                                             fromOrigin / 1000.0, cfg.maxDistanceFromOriginM / 1000.0));
        return;
    }
    auto& anchors = m_state.anchors;
    if (!anchors.empty() && t <= anchors.back().time) {
        reject(m_counters.rejectedOrder, "GNSS fix older than the previous fix");
        return;
    }
    if (!m_state.motion.empty() && seconds(t, m_state.motion.back().time) > cfg.maxFixAgeS) {
        reject(m_counters.rejectedOrder, "GNSS fix older than the motion data by more than maxFixAgeS");
        return;
    }
    ++m_counters.fixes;
    if (anchors.empty() || seconds(anchors.back().time, t) > cfg.gnssTimeoutS) {
        // First fix, or position regained after a stale period: start over here.
        relocate(t, p, headingDeg);
        prune();
        updateMatch(t);
        changed();
        return;
    }
    const PoseAnchor& last = anchors.back();
    double px = last.x, py = last.y, ph = last.headingRad, pv = 0;
    deadReckon(m_state.motion, last.time, t, cfg.motionTimeoutS, last.speedMps, px, py, ph, pv);
    const double dtFix = seconds(last.time, t);
    const double innovation = std::hypot(p.x - px, p.y - py);
    if (innovation > cfg.jumpGateM + cfg.jumpGateGrowthMps * dtFix) {
        if (++m_consecutiveJumps < cfg.jumpsToRelocate) {
            --m_counters.fixes;
            reject(m_counters.rejectedJump, fmt("GNSS fix: jump of %.1f m from the prediction (gate %.1f m)",
                                                innovation, cfg.jumpGateM + cfg.jumpGateGrowthMps * dtFix));
            return;
        }
        relocate(t, p, headingDeg);  // the prediction was wrong, not the receiver
        prune();
        updateMatch(t);
        changed();
        return;
    }
    m_consecutiveJumps = 0;
    // The displayed pose just before this fix, to fade the correction in (VehicleState::compute).
    const double fade = cfg.blendS > 0 ? std::max(0.0, 1.0 - dtFix / cfg.blendS) : 0.0;
    const double shownX = px + last.jumpX * fade;
    const double shownY = py + last.jumpY * fade;
    const double shownH = ph + last.jumpHeadingRad * fade;

    const bool haveMotion = !m_state.motion.empty() && seconds(m_state.motion.back().time, t) <= cfg.motionTimeoutS;
    const bool haveYaw = m_lastYawTime && std::abs(seconds(*m_lastYawTime, t)) <= cfg.motionTimeoutS;
    const double k = haveMotion ? cfg.positionGain : 1.0;
    PoseAnchor a;
    a.time = t;
    a.x = px + k * (p.x - px);
    a.y = py + k * (p.y - py);
    a.speedMps = pv;
    a.headingRad = ph;
    if (headingDeg && std::abs(pv) >= cfg.courseMinSpeedMps) {
        const double kh = haveYaw ? cfg.headingGain : 1.0;
        a.headingRad = ph + kh * wrapPi(*headingDeg * kDegToRad - ph);
        m_state.headingKnown = true;
    } else if (!haveYaw) {
        // No gyro and no usable course: the direction between fixes.
        const double dx = p.x - last.x, dy = p.y - last.y;
        if (std::hypot(dx, dy) > 2.0) {
            a.headingRad = std::atan2(dx, dy);
            m_state.headingKnown = true;
        }
    } else if (headingDeg) {
        m_state.headingKnown = true;
    }
    a.headingRad = wrapPi(a.headingRad);
    a.jumpX = shownX - a.x;
    a.jumpY = shownY - a.y;
    a.jumpHeadingRad = wrapPi(shownH - a.headingRad);
    anchors.push_back(a);
    prune();
    updateMatch(t);
    changed();
}

void VehicleStateEstimator::prune() {
    auto& anchors = m_state.anchors;
    const double keep = m_state.config.historyS;
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
        motion.erase(motion.begin(), std::prev(it));
    }
}

void VehicleStateEstimator::updateMatch(ipc::CanTime t) {
    if (m_state.anchors.empty() || (!m_state.matcher && !m_state.route)) {
        return;
    }
    const EstimatedPose pose = VehicleState::compute(m_state, t);
    m_state.matchedEdge = pose.matchConfidence >= m_state.config.snapMinConfidence ? pose.edge : std::nullopt;
    m_state.routeMeasure = pose.onRoute ? std::optional<double>(pose.routeDrivenM) : std::nullopt;
}

}  // namespace navmap::daemon
