// SPDX-License-Identifier: Apache-2.0
// ManeuverType, the one manoeuvre enum of the control protocol and route guidance: its names are
// the set_route wire spelling of docs/ipc.md, each name reads back as its type, and nothing else
// is a type.

#include "navmap/common/maneuver_type.h"

#include <gtest/gtest.h>

#include <string>
#include <vector>

namespace {

using navmap::kManeuverTypeCount;
using navmap::ManeuverType;
using navmap::maneuverTypeFromName;
using navmap::maneuverTypeName;

TEST(ManeuverType, NamesAreTheProtocolSpellingInEnumOrder) {
    const std::vector<std::string> wire = {"depart",      "arrive",       "straight",   "turn_left",   "turn_right",
                                           "slight_left", "slight_right", "sharp_left", "sharp_right", "u_turn",
                                           "keep_left",   "keep_right",   "roundabout", "exit",        "merge"};
    ASSERT_EQ(wire.size(), kManeuverTypeCount);
    for (std::size_t i = 0; i < kManeuverTypeCount; ++i) {
        const auto t = static_cast<ManeuverType>(i);
        EXPECT_EQ(maneuverTypeName(t), wire[i]) << i;
        EXPECT_EQ(navmap::kManeuverTypeNames[i].first, t) << i;
        EXPECT_EQ(std::string(navmap::kManeuverTypeNames[i].second), wire[i]) << i;
        ASSERT_TRUE(maneuverTypeFromName(wire[i]).has_value()) << wire[i];
        EXPECT_EQ(*maneuverTypeFromName(wire[i]), t) << wire[i];
    }
}

TEST(ManeuverType, OtherNamesAreNoType) {
    for (const char* name : {"", "Turn_Left", "turn-left", "turn_left ", "uturn", "turn_around", "straight\n"}) {
        EXPECT_FALSE(maneuverTypeFromName(name).has_value()) << name;
    }
    EXPECT_EQ(maneuverTypeName(static_cast<ManeuverType>(kManeuverTypeCount)), "straight");
}

}  // namespace
