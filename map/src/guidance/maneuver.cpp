// SPDX-License-Identifier: Apache-2.0
#include "navmap/map/guidance/maneuver.h"

#include <cmath>

namespace navmap::map::guidance {

double headingChange(double a_deg, double b_deg) noexcept {
    double d = std::fmod(b_deg - a_deg + 180.0, 360.0);
    if (d < 0.0) d += 360.0;
    return d - 180.0;
}

ManeuverType classifyTurn(double turn_deg, const TurnThresholds& t) noexcept {
    if (!std::isfinite(turn_deg)) return ManeuverType::Straight;
    const double a = std::abs(turn_deg);
    const bool right = turn_deg > 0.0;
    if (a < t.straight_deg) return ManeuverType::Straight;
    if (a < t.slight_deg) return right ? ManeuverType::SlightRight : ManeuverType::SlightLeft;
    if (a < t.turn_deg) return right ? ManeuverType::TurnRight : ManeuverType::TurnLeft;
    if (a < t.sharp_deg) return right ? ManeuverType::SharpRight : ManeuverType::SharpLeft;
    return ManeuverType::UTurn;
}

}  // namespace navmap::map::guidance
