#pragma once
// The camera of one display: bird's-eye or snail's view following the vehicle (seed 5.3),
// zoom by speed, heading-up or north-up, with every parameter moved by a critically damped
// spring so that view and zoom changes never jump.

#include <functional>

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
    double distance_m = 0.0;   ///< eye to look-at point
    double pitch_deg = 0.0;    ///< elevation of the eye above the horizontal, seen from the look-at point
    double yaw_deg = 0.0;      ///< direction the camera looks, 0 = north, clockwise
    double look_ahead_m = 0.0; ///< look-at point ahead of the vehicle
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
    double smoothing_s = 0.6;       ///< time constant of the critically damped springs
    double ground_clearance_m = 8.0; ///< the eye stays this far above the DEM
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
    RigState m_state;
    RigState m_velocity;
};

}  // namespace navmap::render
