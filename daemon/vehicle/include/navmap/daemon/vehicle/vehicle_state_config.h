// SPDX-License-Identifier: Apache-2.0
#pragma once
// Tuning of the vehicle-state estimator and the map matcher (docs/vehicle-state.md). Times in
// seconds, distances in metres, angles in degrees.

namespace navmap::daemon {

struct VehicleStateConfig {
    // --- staleness
    double gnss_timeout_s = 2.0;         ///< no accepted fix for this long: stale, "position lost"
    double motion_timeout_s = 0.5;       ///< speed/yaw rate held this long past their newest sample
    double max_dead_reckoning_s = 10.0;  ///< after the newest fix, the pose freezes after this long
    // --- tunnels (docs/vehicle-state.md "Tunnels")
    double graph_follow_after_s = 1.0;       ///< no fix for this long and a tunnel ahead: follow the road graph
    double tunnel_dead_reckoning_s = 900.0;  ///< following the graph, the pose freezes after this long

    // --- fusion
    double position_gain = 0.3;          ///< share of the fix innovation taken when speed/yaw drive the track
    double heading_gain = 0.25;          ///< share of the GNSS course innovation (with a yaw-rate sensor)
    double course_min_speed_mps = 3.0;   ///< GNSS course is used above this speed only
    double blend_s = 0.4;                ///< the visible correction at a fix is spread over this time
    bool yaw_rate_positive_left = true;  ///< ISO 8855 / VSS: positive yaw rate = counter-clockwise
    double history_s = 3.0;              ///< anchors kept for interpolation into the past

    // --- rejection
    double jump_gate_m = 30.0;                  ///< a fix further than this from the prediction is a jump ...
    double jump_gate_growth_mps = 10.0;         ///< ... plus this per second since the previous fix
    int jumps_to_relocate = 3;                  ///< this many consecutive jumps: re-initialise at the newest
    double max_distance_from_origin_m = 500e3;  ///< fixes further from the store origin are out of range
    double max_fix_age_s = 5.0;                 ///< fixes older than the newest motion sample by more are dropped

    // --- map matching
    double match_radius_m = 25.0;           ///< candidates within this distance
    double match_sigma_m = 8.0;             ///< distance scale of the confidence
    double match_sigma_heading_deg = 30.0;  ///< heading scale of the confidence
    double heading_min_speed_mps = 2.0;     ///< below this the heading does not count
    double hysteresis_bonus = 1.5;          ///< score bonus of the current edge (switching needs a clearly better one)
    double connected_bonus = 0.75;          ///< score bonus of the current edge's successors/twin
    double snap_full_confidence = 0.5;      ///< at or above: the pose is on the road
    double snap_min_confidence = 0.2;       ///< below: not snapped; in between: blended
    double route_bonus = 1.0;               ///< the route wins over an equally good road
};

}  // namespace navmap::daemon
