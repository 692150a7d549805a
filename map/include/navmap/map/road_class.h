// SPDX-License-Identifier: Apache-2.0
#pragma once
// Functional road classes (FRC, seed 3.6) and the OSM highway=* mapping that produces them.

#include <cstdint>
#include <optional>
#include <string_view>

namespace navmap::map {

/// Functional road class, most important first (seed 3.6: "each polyline has a functional
/// road class defining a distinct width and color"; tiles store roads sorted by it).
/// Link roads (motorway_link, ...) take their parent's class and set road_flags::kLink.
enum class RoadClass : std::uint8_t {
    Motorway = 0,
    Trunk,
    Primary,
    Secondary,
    Tertiary,
    Unclassified,
    Residential,  ///< residential, living_street
    Service,
    Pedestrian,  ///< pedestrian streets and squares
    Track,       ///< agricultural/forest tracks
    Path,        ///< path, footway, cycleway, bridleway, steps (lowest class)
};
inline constexpr int kRoadClassCount = 11;

/// Flags on a road polyline or graph edge.
namespace road_flags {
inline constexpr std::uint8_t kOneway = 1;  ///< traffic only in the direction of the points
inline constexpr std::uint8_t kBridge = 2;
inline constexpr std::uint8_t kTunnel = 4;
inline constexpr std::uint8_t kLink = 8;  ///< *_link ramp
inline constexpr std::uint8_t kRoundabout = 16;
}  // namespace road_flags

struct HighwayMapping {
    RoadClass cls;
    bool link;
};

/// Maps a highway=* value to its class; nullopt for values that are not roads to draw
/// (construction, proposed, platform, bus_stop, corridor, elevator, raceway, ...).
std::optional<HighwayMapping> roadClassFromHighway(std::string_view highway);

/// Typical free-flow speed in km/h for a class when maxspeed is absent (used by routing).
float defaultSpeedKmh(RoadClass cls);

/// Short lower-case name ("motorway", "path", ...).
std::string_view roadClassName(RoadClass cls);

}  // namespace navmap::map
