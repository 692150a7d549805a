// SPDX-License-Identifier: Apache-2.0
#pragma once
// ManeuverType: the one manoeuvre enum of the control protocol (set_route maneuvers[].type,
// docs/ipc.md) and of route guidance (map::guidance, docs/guidance.md), so a manoeuvre goes from
// the protocol to guidance and the renderers as a value; its names are the protocol's spelling.
// Plain values, no I/O.

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string_view>
#include <utility>

namespace navmap {

enum class ManeuverType : std::uint8_t {
    Depart,
    Arrive,
    Straight,
    TurnLeft,
    TurnRight,
    SlightLeft,
    SlightRight,
    SharpLeft,
    SharpRight,
    UTurn,
    KeepLeft,
    KeepRight,
    Roundabout,
    Exit,
    Merge,
};
inline constexpr std::size_t kManeuverTypeCount = 15;

/// Every type with its protocol name, in the enum's order (the control parser's list of choices).
inline constexpr std::array<std::pair<ManeuverType, const char*>, kManeuverTypeCount> kManeuverTypeNames{{
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

/// "turn_left" etc., the control protocol's name ("straight" for a value outside the enum).
std::string_view maneuverTypeName(ManeuverType t) noexcept;
/// The type a protocol name spells; nothing for an unknown name.
std::optional<ManeuverType> maneuverTypeFromName(std::string_view name) noexcept;

}  // namespace navmap
