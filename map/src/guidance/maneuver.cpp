// SPDX-License-Identifier: Apache-2.0
#include "navmap/map/guidance/maneuver.h"

#include <array>
#include <cmath>
#include <utility>

namespace navmap::map::guidance {

namespace {

constexpr std::array<std::pair<ManeuverType, std::string_view>, kManeuverTypeCount> kNames{{
    {ManeuverType::Depart, "depart"},
    {ManeuverType::Arrive, "arrive"},
    {ManeuverType::Straight, "straight"},
    {ManeuverType::TurnLeft, "turn_left"},
    {ManeuverType::TurnRight, "turn_right"},
    {ManeuverType::SlightLeft, "slight_left"},
    {ManeuverType::SlightRight, "slight_right"},
    {ManeuverType::SharpLeft, "sharp_left"},
    {ManeuverType::SharpRight, "sharp_right"},
    {ManeuverType::UTurn, "u_turn"},
    {ManeuverType::KeepLeft, "keep_left"},
    {ManeuverType::KeepRight, "keep_right"},
    {ManeuverType::Roundabout, "roundabout"},
    {ManeuverType::Exit, "exit"},
    {ManeuverType::Merge, "merge"},
}};

}  // namespace

std::string_view maneuverTypeName(ManeuverType t) noexcept {
    for (const auto& [value, name] : kNames) {
        if (value == t) return name;
    }
    return "straight";
}

std::optional<ManeuverType> maneuverTypeFromName(std::string_view name) noexcept {
    for (const auto& [value, n] : kNames) {
        if (n == name) return value;
    }
    return std::nullopt;
}

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
