// SPDX-License-Identifier: Apache-2.0
#pragma once
// Route guidance manoeuvres (docs/guidance.md): the manoeuvre types (the control protocol's
// enum, navmap/common/maneuver_type.h) and the turn class of a heading change at a junction.
// Plain values, no I/O, thread-safe.

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>

#include "navmap/common/maneuver_type.h"

namespace navmap::map::guidance {

/// The manoeuvre types, the control protocol's own (navmap/common/maneuver_type.h): one enum.
using ManeuverType = navmap::ManeuverType;
using navmap::kManeuverTypeCount;
using navmap::maneuverTypeFromName;
using navmap::maneuverTypeName;

/// Turn-class boundaries on the absolute heading change at a junction, degrees. A change below
/// `straight_deg` is straight on, below `slight_deg` slight, below `turn_deg` an ordinary turn,
/// below `sharp_deg` sharp, and from `sharp_deg` on a U-turn (docs/guidance.md).
struct TurnThresholds {
    double straight_deg = 20.0;
    double slight_deg = 45.0;
    double turn_deg = 135.0;
    double sharp_deg = 170.0;
};

/// Turn class of a signed heading change (degrees, positive = right / clockwise, in
/// [-180, 180]): Straight, Slight*, Turn*, Sharp* or UTurn. Non-finite input gives Straight.
ManeuverType classifyTurn(double turn_deg, const TurnThresholds& thresholds = {}) noexcept;

/// `b - a` wrapped into [-180, 180): the signed change from heading a to heading b.
double headingChange(double a_deg, double b_deg) noexcept;

/// One manoeuvre on a route polyline.
struct Maneuver {
    ManeuverType type = ManeuverType::Straight;
    std::size_t point = 0;       ///< route point where it happens (the junction; a roundabout's entry)
    std::size_t end_point = 0;   ///< route point where it is done (a roundabout's exit; else == point)
    double measure_m = 0.0;      ///< distance from the route start to `point`
    double end_measure_m = 0.0;  ///< distance from the route start to `end_point`
    double turn_deg = 0.0;       ///< signed heading change, positive = right (roundabout: entry to exit)
    int exit = 0;                ///< roundabout exit counted from the entry (1 = first); 0 = none
    std::string street;          ///< name (else ref) of the road taken; empty when unknown
    friend bool operator==(const Maneuver&, const Maneuver&) = default;
};

}  // namespace navmap::map::guidance
