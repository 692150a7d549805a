// SPDX-License-Identifier: Apache-2.0
#pragma once
// Realistic longitudinal profile of a car along a DriveRoute: target speed by road class and
// maxspeed, slowing in curves (lateral acceleration limit), bounded acceleration and braking,
// standing start and full stop at the end. Immutable after build(); stateAt() is thread-safe.

#include <cstddef>
#include <vector>

#include "navmap/map/projection.h"
#include "navmap/sim/drive_route.h"

namespace navmap::sim {

struct DriveParams {
    double lateral_accel_mps2 = 2.5;   ///< curve speed: v <= sqrt(a_lat / curvature)
    double accel_mps2 = 1.5;           ///< longitudinal acceleration limit
    double brake_mps2 = 2.5;           ///< longitudinal deceleration limit
    double speed_factor = 1.0;         ///< driver: fraction of the target speed actually driven
    double min_curve_speed_kmh = 8.0;  ///< floor of the curve speed (hairpins, turns at junctions)
    double step_m = 1.0;               ///< grid spacing of the profile along the route
    double heading_window_m = 6.0;     ///< heading = direction of p(s + w) - p(s - w): a car does not turn on a point
};

/// State of the simulated car at one time.
struct VehicleState {
    double t_s = 0.0;           ///< seconds since the start of the drive
    double measure_m = 0.0;     ///< distance driven along the route
    map::PlanarPoint position;  ///< store frame, on the route polyline
    double heading_deg = 0.0;   ///< clockwise from north, [0, 360)
    double speed_mps = 0.0;
    double accel_mps2 = 0.0;    ///< longitudinal
    double yaw_rate_dps = 0.0;  ///< positive counter-clockwise (DBC / VSS convention)
    double limit_mps = 0.0;     ///< the profile's speed limit here (target and curve)
};

class SpeedProfile {
public:
    /// Builds the profile (forward/backward passes over a grid of `params.step_m`).
    static SpeedProfile build(const DriveRoute& route, const DriveParams& params = {});

    [[nodiscard]] double duration() const { return m_t.empty() ? 0.0 : m_t.back(); }
    [[nodiscard]] double length() const { return m_s.empty() ? 0.0 : m_s.back(); }
    /// State at time t (clamped to [0, duration()]).
    [[nodiscard]] VehicleState stateAt(double t_s) const;
    /// Speed limit (target speed and curve speed, before acceleration limits) at a measure, m/s.
    [[nodiscard]] double limitAt(double measure_m) const;
    /// Unsigned curvature used for the curve speed on the grid cell containing `measure_m`, 1/m.
    [[nodiscard]] double curvatureAt(double measure_m) const;
    [[nodiscard]] const DriveParams& params() const { return m_params; }

private:
    [[nodiscard]] std::size_t cellAt(double measure_m) const;

    DriveParams m_params;
    std::vector<map::RoutePoint> m_line;
    std::vector<double> m_s;        // grid measures
    std::vector<double> m_heading;  // unwrapped heading at grid points, degrees clockwise
    std::vector<double> m_limit;    // per cell: min(target, curve) m/s
    std::vector<double> m_kappa;    // per cell
    std::vector<double> m_v;        // grid speeds after the acceleration passes
    std::vector<double> m_t;        // time at grid points
};

}  // namespace navmap::sim
