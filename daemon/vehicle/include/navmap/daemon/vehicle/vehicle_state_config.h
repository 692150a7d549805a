// SPDX-License-Identifier: Apache-2.0
#pragma once
// Tuning of the vehicle-state estimator and the map matcher (docs/vehicle-state.md). Times in
// seconds, distances in metres, angles in degrees.

namespace navmap::daemon {

struct VehicleStateConfig {
    // --- staleness
    double gnssTimeoutS = 2.0;        ///< no accepted fix for this long: stale, "position lost"
    double motionTimeoutS = 0.5;      ///< speed/yaw rate held this long past their newest sample
    double maxDeadReckoningS = 10.0;  ///< after the newest fix, the pose freezes after this long

    // --- fusion
    double positionGain = 0.3;        ///< share of the fix innovation taken when speed/yaw drive the track
    double headingGain = 0.25;        ///< share of the GNSS course innovation (with a yaw-rate sensor)
    double courseMinSpeedMps = 3.0;   ///< GNSS course is used above this speed only
    double blendS = 0.4;              ///< the visible correction at a fix is spread over this time
    bool yawRatePositiveLeft = true;  ///< ISO 8855 / VSS: positive yaw rate = counter-clockwise
    double historyS = 3.0;            ///< anchors kept for interpolation into the past

    // --- rejection
    double jumpGateM = 30.0;                ///< a fix further than this from the prediction is a jump ...
    double jumpGateGrowthMps = 10.0;        ///< ... plus this per second since the previous fix
    int jumpsToRelocate = 3;                ///< this many consecutive jumps: re-initialise at the newest
    double maxDistanceFromOriginM = 500e3;  ///< fixes further from the store origin are out of range
    double maxFixAgeS = 5.0;                ///< fixes older than the newest motion sample by more are dropped

    // --- map matching
    double matchRadiusM = 25.0;          ///< candidates within this distance
    double matchSigmaM = 8.0;            ///< distance scale of the confidence
    double matchSigmaHeadingDeg = 30.0;  ///< heading scale of the confidence
    double headingMinSpeedMps = 2.0;     ///< below this the heading does not count
    double hysteresisBonus = 1.5;        ///< score bonus of the current edge (switching needs a clearly better one)
    double connectedBonus = 0.75;        ///< score bonus of the current edge's successors/twin
    double snapFullConfidence = 0.5;     ///< at or above: the pose is on the road
    double snapMinConfidence = 0.2;      ///< below: not snapped; in between: blended
    double routeBonus = 1.0;             ///< the route wins over an equally good road
};

}  // namespace navmap::daemon
