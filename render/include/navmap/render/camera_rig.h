// SPDX-License-Identifier: Apache-2.0
#pragma once
// The camera of one display: bird's-eye or snail's view following the vehicle (seed 5.3),
// zoom by speed, heading-up or north-up, with every parameter moved by a critically damped
// spring so that view and zoom changes never jump. A display may instead follow the vehicle
// with a camera stated in MapLibre GL JS's convention (zoom and pitch, maplibre_camera.h).

#include <functional>
#include <optional>

#include "navmap/map/projection.h"
#include "navmap/render/camera.h"

namespace navmap::render {

enum class ViewMode { Bird, Snail };
enum class Orientation { HeadingUp, NorthUp };

/// Where the vehicle is at frame time (planar metres of the map frame).
struct VehiclePose {
    glm::dvec3 position{0.0};  ///< x east, y north, z terrain height
    double heading_deg = 0.0;  ///< 0 = north, clockwise
    double speed_mps = 0.0;
};

/// The pose of a camera as orbit parameters around a look-at point ahead of the vehicle.
struct RigState {
    double distance_m = 0.0;    ///< eye to look-at point
    double pitch_deg = 0.0;     ///< elevation of the eye above the horizontal, seen from the look-at point
    double yaw_deg = 0.0;       ///< direction the camera looks, 0 = north, clockwise
    double look_ahead_m = 0.0;  ///< look-at point ahead of the vehicle
    double fov_y_deg = 0.0;     ///< vertical field of view (goal() sets it; 0 in a velocity)
};

/// A camera following the vehicle as MapLibre GL JS would show it (maplibre_camera.h): centred
/// on the vehicle, at the distance of `zoom` for the viewport height, `pitch_deg` from straight
/// down, with MapLibre's 36.87 degree field of view.
struct MapLibreFollow {
    double zoom = 16.0;       ///< 0..24, 512-px tiles
    double pitch_deg = 60.0;  ///< 0..85, 0 = straight down
    /// A fixed bearing (degrees clockwise from true north); empty: the rig's orientation decides
    /// (heading-up: the vehicle's heading, north-up: north).
    std::optional<double> bearing_deg;
    bool operator==(const MapLibreFollow&) const = default;
};

struct CameraRigParams {
    // Bird's-eye: high, moderate pitch, zoom grows with speed.
    double bird_pitch_deg = 50.0;
    double bird_distance_slow_m = 900.0;   ///< at standstill
    double bird_distance_fast_m = 3200.0;  ///< at bird_fast_speed_mps and above
    double bird_fast_speed_mps = 33.0;     ///< ~120 km/h
    double bird_look_ahead_m = 120.0;
    // Snail's view: low behind the car, looking along the road.
    double snail_pitch_deg = 14.0;
    double snail_distance_m = 180.0;
    double snail_look_ahead_m = 70.0;
    double fov_y_deg = 45.0;
    double smoothing_s = 0.6;         ///< time constant of the critically damped springs
    double ground_clearance_m = 8.0;  ///< the eye stays this far above the DEM
};

/// Critically damped spring towards `target` (closed form, stable for any dt).
double smoothDamp(double current, double target, double& velocity, double smooth_time, double dt);

class CameraRig {
public:
    using TerrainHeight = std::function<double(double x, double y)>;

    explicit CameraRig(CameraRigParams params = {});

    void setMode(ViewMode mode) { m_mode = mode; }
    void setOrientation(Orientation orientation) { m_orientation = orientation; }
    [[nodiscard]] ViewMode mode() const { return m_mode; }
    /// Follow with a MapLibre-convention camera instead of the mode's distances; the springs move
    /// to it from the current view. `projection` (the store's) gives the vehicle's latitude for
    /// the map scale and true north; `viewport_height_px` the distance (MapLibre keeps the
    /// center in the middle of the viewport at a fixed pixel scale).
    void setMapLibreFollow(const MapLibreFollow& follow, const map::Projection& projection, int viewport_height_px);
    /// Back to the mode's own distances (the springs move there).
    void clearMapLibreFollow() { m_follow.reset(); }
    [[nodiscard]] std::optional<MapLibreFollow> mapLibreFollow() const;

    /// The parameters the springs move towards for this pose and mode.
    [[nodiscard]] RigState goal(const VehiclePose& pose) const;
    /// Advances the springs by dt seconds (the first call snaps to the goal) and returns the
    /// camera for `pose` at frame time. `terrain` (may be empty) keeps the eye above the DEM
    /// along the line of sight.
    Camera update(const VehiclePose& pose, double dt, const TerrainHeight& terrain = {});
    [[nodiscard]] const RigState& state() const { return m_state; }

private:
    CameraRigParams m_params;
    ViewMode m_mode = ViewMode::Bird;
    Orientation m_orientation = Orientation::HeadingUp;
    bool m_initialised = false;
    struct Follow {
        MapLibreFollow camera;
        map::Projection projection;
        int viewport_height_px;
    };
    std::optional<Follow> m_follow;
    RigState m_state;
    RigState m_velocity;
};

}  // namespace navmap::render
