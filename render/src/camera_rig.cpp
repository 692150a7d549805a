// SPDX-License-Identifier: Apache-2.0
#include "navmap/render/camera_rig.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "navmap/render/maplibre_camera.h"

namespace navmap::render {

namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

// Shortest signed difference b - a in degrees, in (-180, 180].
double angleDelta(double a, double b) {
    double d = std::fmod(b - a, 360.0);
    if (d > 180.0) d -= 360.0;
    if (d <= -180.0) d += 360.0;
    return d;
}

}  // namespace

double smoothDamp(double current, double target, double& velocity, double smooth_time, double dt) {
    // Critically damped spring, closed-form step (no overshoot, frame-rate independent).
    const double omega = 2.0 / std::max(smooth_time, 1e-4);
    const double x = omega * dt;
    const double decay = 1.0 / (1.0 + x + 0.48 * x * x + 0.235 * x * x * x);
    const double change = current - target;
    const double temp = (velocity + omega * change) * dt;
    velocity = (velocity - omega * temp) * decay;
    return target + (change + temp) * decay;
}

CameraRig::CameraRig(CameraRigParams params) : m_params(params) {}

void CameraRig::setMapLibreFollow(const MapLibreFollow& follow, const map::Projection& projection,
                                  int viewport_height_px) {
    m_follow = Follow{follow, projection, viewport_height_px};
}

std::optional<MapLibreFollow> CameraRig::mapLibreFollow() const {
    if (!m_follow) return std::nullopt;
    return m_follow->camera;
}

RigState CameraRig::goal(const VehiclePose& pose) const {
    RigState g;
    g.yaw_deg = m_orientation == Orientation::NorthUp ? 0.0 : pose.heading_deg;
    g.fov_y_deg = m_params.fov_y_deg;
    if (m_follow) {
        // MapLibre's camera (maplibre_camera.h): centred on the vehicle, no look-ahead, the
        // distance that gives the zoom's pixel scale at the center, pitch from straight down.
        double lat = 0.0, lon = 0.0;
        m_follow->projection.reverse({pose.position.x, pose.position.y}, lat, lon);
        const MapLibreFollow& f = m_follow->camera;
        g.distance_m = mapLibreCameraDistance(lat, f.zoom, m_follow->viewport_height_px);
        g.pitch_deg = 90.0 - f.pitch_deg;
        g.look_ahead_m = 0.0;
        g.fov_y_deg = kMapLibreFovYDeg;
        if (f.bearing_deg || m_orientation == Orientation::NorthUp) {
            // A bearing from true north; the store frame's y axis is grid north.
            g.yaw_deg =
                std::fmod(gridBearingDeg(m_follow->projection, lat, lon, f.bearing_deg.value_or(0.0)) + 720.0, 360.0);
        }
        return g;
    }
    if (m_mode == ViewMode::Bird) {
        const double t = std::clamp(pose.speed_mps / m_params.bird_fast_speed_mps, 0.0, 1.0);
        g.distance_m =
            m_params.bird_distance_slow_m + t * (m_params.bird_distance_fast_m - m_params.bird_distance_slow_m);
        g.pitch_deg = m_params.bird_pitch_deg;
        g.look_ahead_m = m_params.bird_look_ahead_m;
    } else {
        g.distance_m = m_params.snail_distance_m;
        g.pitch_deg = m_params.snail_pitch_deg;
        g.look_ahead_m = m_params.snail_look_ahead_m;
    }
    return g;
}

Camera CameraRig::update(const VehiclePose& pose, double dt, const TerrainHeight& terrain) {
    const RigState g = goal(pose);
    if (!m_initialised || dt <= 0.0) {
        if (!m_initialised) {
            m_state = g;
            m_velocity = {};
            m_initialised = true;
        }
    } else {
        const double st = m_params.smoothing_s;
        m_state.distance_m = smoothDamp(m_state.distance_m, g.distance_m, m_velocity.distance_m, st, dt);
        m_state.pitch_deg = smoothDamp(m_state.pitch_deg, g.pitch_deg, m_velocity.pitch_deg, st, dt);
        m_state.look_ahead_m = smoothDamp(m_state.look_ahead_m, g.look_ahead_m, m_velocity.look_ahead_m, st, dt);
        m_state.fov_y_deg = smoothDamp(m_state.fov_y_deg, g.fov_y_deg, m_velocity.fov_y_deg, st, dt);
        // Yaw moves along the shortest arc.
        const double yaw_goal = m_state.yaw_deg + angleDelta(m_state.yaw_deg, g.yaw_deg);
        m_state.yaw_deg = smoothDamp(m_state.yaw_deg, yaw_goal, m_velocity.yaw_deg, st, dt);
        m_state.yaw_deg = std::fmod(m_state.yaw_deg + 360.0, 360.0);
    }

    const glm::dvec2 forward{std::sin(m_state.yaw_deg * kDeg), std::cos(m_state.yaw_deg * kDeg)};
    glm::dvec3 target = pose.position + glm::dvec3(forward * m_state.look_ahead_m, 0.0);
    if (terrain) target.z = terrain(target.x, target.y);
    const double horizontal = m_state.distance_m * std::cos(m_state.pitch_deg * kDeg);
    const double vertical = m_state.distance_m * std::sin(m_state.pitch_deg * kDeg);
    glm::dvec3 eye = target - glm::dvec3(forward * horizontal, 0.0) + glm::dvec3(0.0, 0.0, vertical);

    if (terrain) {
        // Never below the surface: check the eye and the line of sight towards the target,
        // and lift the eye until every sample clears the DEM by the clearance.
        const double clearance = m_params.ground_clearance_m;
        for (int i = 0; i <= 16; ++i) {
            const double s = i / 16.0;  // 0 = eye, 1 = target
            const glm::dvec3 p = eye + (target - eye) * s;
            const double need = terrain(p.x, p.y) + clearance * (1.0 - s) - p.z;
            if (need > 0.0 && s < 1.0) eye.z += need / (1.0 - s);
        }
    }

    Camera camera;
    camera.eye = eye;
    camera.target = target;
    // The screen's up direction: z while the camera looks down at an angle (the same view), the
    // forward direction when it looks straight down (MapLibre pitch 0), where z is undefined.
    const double elevation = m_state.pitch_deg * kDeg;
    camera.up = glm::dvec3(forward * std::sin(elevation), std::cos(elevation));
    camera.fov_y_deg = m_state.fov_y_deg;
    const double dist = glm::length(target - eye);
    camera.near_m = std::clamp(dist * 0.02, 1.0, 50.0);
    camera.far_m = std::max(60000.0, dist * 20.0);
    return camera;
}

}  // namespace navmap::render
