// SPDX-License-Identifier: Apache-2.0
#include "navmap/common/maneuver_type.h"

namespace navmap {

std::string_view maneuverTypeName(ManeuverType t) noexcept {
    for (const auto& [value, name] : kManeuverTypeNames) {
        if (value == t) {
            return name;
        }
    }
    return "straight";
}

std::optional<ManeuverType> maneuverTypeFromName(std::string_view name) noexcept {
    for (const auto& [value, n] : kManeuverTypeNames) {
        if (n == name) {
            return value;
        }
    }
    return std::nullopt;
}

}  // namespace navmap
