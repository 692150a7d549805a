// SPDX-License-Identifier: Apache-2.0
#include "navmap/sim/speed_profile.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

namespace navmap::sim {

namespace {

constexpr double kDegPerRad = 180.0 / std::numbers::pi;

double wrap180(double deg) {
    double d = std::fmod(deg + 180.0, 360.0);
    if (d < 0) d += 360.0;
    return d - 180.0;
}

}  // namespace

SpeedProfile SpeedProfile::build(const DriveRoute& route, const DriveParams& params) {
    SpeedProfile p;
    p.m_params = params;
    p.m_params.step_m = std::clamp(params.step_m, 0.1, 50.0);
    p.m_params.speed_factor = std::clamp(params.speed_factor, 0.05, 2.0);
    p.m_params.accel_mps2 = std::max(0.05, params.accel_mps2);
    p.m_params.brake_mps2 = std::max(0.05, params.brake_mps2);
    p.m_params.lateral_accel_mps2 = std::max(0.05, params.lateral_accel_mps2);
    p.m_params.min_curve_speed_kmh = std::max(1.0, params.min_curve_speed_kmh);
    p.m_line = route.line;
    const double length = route.length();
    if (route.line.size() < 2 || length <= 0.0) {
        p.m_s = {0.0};
        p.m_heading = {0.0};
        p.m_v = {0.0};
        p.m_t = {0.0};
        return p;
    }
    const DriveParams& q = p.m_params;

    // Grid along the route (at least two cells, so even a tiny route has a moving middle point);
    // the last cell may be shorter.
    const double step = std::min(q.step_m, length / 2.0);
    const auto cells = std::max<std::size_t>(2, static_cast<std::size_t>(std::ceil(length / step)));
    p.m_s.resize(cells + 1);
    for (std::size_t k = 0; k < cells; ++k) p.m_s[k] = std::min(length, static_cast<double>(k) * step);
    p.m_s[cells] = length;

    // Heading of the chord p(s + w) - p(s - w): the car turns over a stretch, not on a polyline
    // vertex, so heading and yaw rate are continuous (unwrapped so differences are turn angles).
    p.m_heading.resize(cells + 1);
    const double w = std::max(0.5, q.heading_window_m);
    for (std::size_t k = 0; k <= cells; ++k) {
        const double s = p.m_s[k];
        const auto a = map::sampleRoute(route.line, std::max(0.0, s - w));
        const auto b = map::sampleRoute(route.line, std::min(length, s + w));
        double h = 0.0;
        const double dx = b.position.x - a.position.x;
        const double dy = b.position.y - a.position.y;
        if (std::hypot(dx, dy) > 1e-3) {
            h = std::atan2(dx, dy) * kDegPerRad;
        } else {
            h = map::sampleRoute(route.line, s).heading_deg;  // exact reversal: the segment's heading
        }
        p.m_heading[k] = k == 0 ? h : p.m_heading[k - 1] + wrap180(h - p.m_heading[k - 1]);
    }

    // Per cell: target speed (class / maxspeed x driver factor) and curve speed from the lateral
    // acceleration limit, v^2 * kappa <= a_lat.
    p.m_limit.resize(cells);
    p.m_kappa.resize(cells);
    const double floor_mps = q.min_curve_speed_kmh / 3.6;
    for (std::size_t k = 0; k < cells; ++k) {
        const double ds = p.m_s[k + 1] - p.m_s[k];
        const double kappa = std::abs(p.m_heading[k + 1] - p.m_heading[k]) / kDegPerRad / std::max(ds, 1e-6);
        const auto mid = map::sampleRoute(route.line, 0.5 * (p.m_s[k] + p.m_s[k + 1]));
        const std::size_t seg = std::min(mid.segment, route.segment_speed_kmh.size() - 1);
        const double target =
            route.segment_speed_kmh.empty() ? 50.0 / 3.6 : route.segment_speed_kmh[seg] / 3.6 * q.speed_factor;
        const double curve =
            kappa > 1e-9 ? std::sqrt(q.lateral_accel_mps2 / kappa) : std::numeric_limits<double>::infinity();
        p.m_kappa[k] = kappa;
        p.m_limit[k] = std::max(std::min(target, curve), std::min(target, floor_mps));
    }

    // Speeds at grid points: bounded by both adjacent cells, 0 at both ends, then a backward
    // pass (braking limit) and a forward pass (acceleration limit). Between grid points the
    // acceleration is constant, so v stays between its end values and under the cell limit.
    p.m_v.assign(cells + 1, 0.0);
    for (std::size_t k = 1; k < cells; ++k) p.m_v[k] = std::min(p.m_limit[k - 1], p.m_limit[k]);
    for (std::size_t k = cells; k-- > 0;) {
        const double ds = p.m_s[k + 1] - p.m_s[k];
        p.m_v[k] = std::min(p.m_v[k], std::sqrt(p.m_v[k + 1] * p.m_v[k + 1] + 2.0 * q.brake_mps2 * ds));
    }
    p.m_v[0] = 0.0;
    for (std::size_t k = 1; k <= cells; ++k) {
        const double ds = p.m_s[k] - p.m_s[k - 1];
        p.m_v[k] = std::min(p.m_v[k], std::sqrt(p.m_v[k - 1] * p.m_v[k - 1] + 2.0 * q.accel_mps2 * ds));
    }

    p.m_t.assign(cells + 1, 0.0);
    for (std::size_t k = 0; k < cells; ++k) {
        const double ds = p.m_s[k + 1] - p.m_s[k];
        const double vsum = p.m_v[k] + p.m_v[k + 1];
        p.m_t[k + 1] = p.m_t[k] + (vsum > 1e-9 ? 2.0 * ds / vsum : 0.0);
    }
    return p;
}

std::size_t SpeedProfile::cellAt(double measure_m) const {
    if (m_s.size() < 2) return 0;
    const auto it = std::upper_bound(m_s.begin(), m_s.end(), measure_m);
    const auto k = static_cast<std::size_t>(std::max<std::ptrdiff_t>(1, it - m_s.begin())) - 1;
    return std::min(k, m_s.size() - 2);
}

double SpeedProfile::limitAt(double measure_m) const { return m_limit.empty() ? 0.0 : m_limit[cellAt(measure_m)]; }

double SpeedProfile::curvatureAt(double measure_m) const { return m_kappa.empty() ? 0.0 : m_kappa[cellAt(measure_m)]; }

VehicleState SpeedProfile::stateAt(double t_s) const {
    VehicleState st;
    st.t_s = t_s;
    if (m_s.size() < 2) {
        if (!m_line.empty()) st.position = m_line.front().position;
        return st;
    }
    const double t = std::clamp(t_s, 0.0, duration());
    const auto it = std::upper_bound(m_t.begin(), m_t.end(), t);
    std::size_t k = static_cast<std::size_t>(std::max<std::ptrdiff_t>(1, it - m_t.begin())) - 1;
    k = std::min(k, m_s.size() - 2);
    const double ds = m_s[k + 1] - m_s[k];
    const double v0 = m_v[k];
    const double v1 = m_v[k + 1];
    const double a = ds > 0 ? (v1 * v1 - v0 * v0) / (2.0 * ds) : 0.0;
    const double tau = std::clamp(t - m_t[k], 0.0, m_t[k + 1] - m_t[k]);
    double v = std::clamp(v0 + a * tau, std::min(v0, v1), std::max(v0, v1));
    double s = std::clamp(m_s[k] + v0 * tau + 0.5 * a * tau * tau, m_s[k], m_s[k + 1]);
    if (t >= duration()) {
        s = length();
        v = 0.0;
    }
    const double f = ds > 0 ? (s - m_s[k]) / ds : 0.0;
    const double dh = m_heading[k + 1] - m_heading[k];
    double heading = std::fmod(m_heading[k] + dh * f, 360.0);
    if (heading < 0) heading += 360.0;

    st.measure_m = s;
    st.position = map::sampleRoute(m_line, s).position;
    st.heading_deg = heading;
    st.speed_mps = v;
    st.accel_mps2 = t >= duration() ? 0.0 : a;
    // Heading is clockwise, the yaw rate counter-clockwise: yaw = -dh/ds * v.
    st.yaw_rate_dps = ds > 0 ? -dh / ds * v : 0.0;
    st.limit_mps = m_limit[k];
    return st;
}

}  // namespace navmap::sim
