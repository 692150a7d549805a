// SPDX-License-Identifier: Apache-2.0
#pragma once
// VehicleState: an immutable snapshot of the estimator (fused anchors at GNSS fix times, the
// speed/yaw-rate samples since, the map-matching state). The input thread publishes it as
// std::shared_ptr<const VehicleState>; the render thread asks it for the pose at frame time
// with poseAt(), which interpolates between anchors or extrapolates by dead reckoning, then
// snaps onto the route or the road. Deterministic: the same snapshot and time give the same pose.

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "navmap/daemon/vehicle/map_matcher.h"
#include "navmap/daemon/vehicle/route_line.h"
#include "navmap/daemon/vehicle/vehicle_state_config.h"
#include "navmap/ipc/can/can_frame.h"

namespace navmap::daemon {

/// The pose at a requested time.
struct EstimatedPose {
    bool valid = false;  ///< false until the first accepted GNSS fix
    double x = 0.0;      ///< store frame, metres east (snapped when matched)
    double y = 0.0;      ///< store frame, metres north
    double raw_x = 0.0;  ///< fused position before map matching
    double raw_y = 0.0;
    double heading_deg = 0.0;  ///< clockwise from north, [0, 360)
    double speed_mps = 0.0;
    ipc::CanTime time{};                     ///< the requested time
    ipc::CanTime source_time{};              ///< CAN receive time of the newest input behind this pose
    bool stale = false;                      ///< no accepted fix for gnss_timeout_s: show "position lost"
    double since_fix_s = 0.0;                ///< seconds since the newest accepted fix
    double match_confidence = 0.0;           ///< 0..1 (0: no road/route candidate)
    double road_confidence = 0.0;            ///< 0..1: the road match's own (0: no road candidate)
    double snap_weight = 0.0;                ///< 0 raw .. 1 fully on the road
    std::optional<std::uint32_t> edge;       ///< matched graph edge
    std::optional<double> road_heading_deg;  ///< direction of the matched route/road segment
    /// The legal speed limit of the matched road in the driving direction, km/h (the matched
    /// edge's map::GraphEdge::speed_limit_kmh); 0 when unknown or when the match is uncertain:
    /// stale, the road match below snap_full_confidence, or no heading on a two-way road whose
    /// directions have different limits. docs/vehicle-state.md "Speed limit".
    int speed_limit_kmh = 0;
    /// The matched road (`edge`) is certain: not stale and the road match's own confidence at
    /// least snap_full_confidence (what the speed limit needs, less the direction). The
    /// cluster's street bar names only such a road. docs/vehicle-state.md "Speed limit".
    bool road_match_certain = false;
    /// On a road in a tunnel: the matched edge has road_flags::kTunnel, the road match is
    /// confident (snap_full_confidence) and the pose is not stale. navmapd dims the view to the
    /// night style and hides the surface's labels then (docs/vehicle-state.md "Tunnels").
    bool in_tunnel = false;
    /// The pose follows the road graph from the last fix (dead reckoning in a tunnel,
    /// docs/vehicle-state.md "Tunnels") rather than integrating speed and yaw rate.
    bool follows_graph = false;
    bool on_route = false;
    double route_driven_m = 0.0;  ///< along the route (when on_route)
    double route_remaining_m = 0.0;
    /// The map frame x, y are in: 0 for the first, one more each time the daemon re-centred it
    /// (VehicleStateEstimator::rebase).
    std::uint32_t frame_epoch = 0;
};

/// A fused state at a GNSS fix (store frame).
struct PoseAnchor {
    ipc::CanTime time{};
    double x = 0.0, y = 0.0;
    double heading_rad = 0.0;  ///< clockwise from north
    double speed_mps = 0.0;
    double jump_x = 0.0, jump_y = 0.0;  ///< prediction minus anchor at `time`: faded out over blend_s
    double jump_heading_rad = 0.0;
    /// The road edge matched at `time` with at least snap_full_confidence: where dead reckoning
    /// along the road graph starts (docs/vehicle-state.md "Tunnels").
    std::optional<std::uint32_t> edge;
};

/// Speed and yaw rate at one time (yaw rate converted to clockwise radians per second).
struct MotionSample {
    ipc::CanTime time{};
    double speed_mps = 0.0;
    double heading_rate_rad_s = 0.0;  ///< d(heading)/dt, clockwise positive
};

class VehicleState {
public:
    struct Parts {
        VehicleStateConfig config;
        std::vector<PoseAnchor> anchors;   ///< ascending time
        std::vector<MotionSample> motion;  ///< ascending time, from before the oldest anchor on
        bool heading_known = false;
        std::shared_ptr<const MapMatcher> matcher;
        std::shared_ptr<const RouteLine> route;
        std::optional<std::uint32_t> matched_edge;  ///< hysteresis state at the newest input
        std::optional<double> route_measure;        ///< previous route match
        std::uint32_t frame_epoch = 0;              ///< EstimatedPose::frame_epoch
        /// The distance driven from the newest anchor up to `odometer_time`, metres, kept when
        /// the motion samples of that time are pruned: dead reckoning along a tunnel goes on
        /// longer than the motion history (ignored when older than the newest anchor).
        double odometer_m = 0.0;
        ipc::CanTime odometer_time{};
    };
    explicit VehicleState(Parts parts) : m_p(std::move(parts)) {}

    /// The pose at `t` (normally the frame time on the CAN clock).
    [[nodiscard]] EstimatedPose poseAt(ipc::CanTime t) const { return compute(m_p, t); }
    /// The same over the estimator's live parts.
    static EstimatedPose compute(const Parts& parts, ipc::CanTime t);

    [[nodiscard]] const Parts& parts() const { return m_p; }

private:
    Parts m_p;
};

/// The distance driven from `from` to `to` (to >= from): the integral of the speed as deadReckon
/// takes it (linear between samples, the last one held for hold_s, `fallback_speed` before the
/// first), exact for that piecewise linear speed.
double distanceDriven(const std::vector<MotionSample>& motion, ipc::CanTime from, ipc::CanTime to, double hold_s,
                      double fallback_speed);

/// Integrates speed and heading rate from `from` to `to` (to >= from) starting at (x, y, h),
/// using the samples (trapezoid between samples, the last one held for at most holdS after it;
/// before the first sample, `fallbackSpeed` without turning). Steps of at most 50 ms.
void deadReckon(const std::vector<MotionSample>& motion, ipc::CanTime from, ipc::CanTime to, double hold_s,
                double fallback_speed, double& x, double& y, double& heading_rad, double& speed_mps);

}  // namespace navmap::daemon
