// SPDX-License-Identifier: Apache-2.0
#include "navmap/map/road_class.h"

#include <array>
#include <utility>

namespace navmap::map {

std::optional<HighwayMapping> roadClassFromHighway(std::string_view h) {
    static constexpr std::array<std::pair<std::string_view, HighwayMapping>, 24> kTable{{
        {"motorway", {RoadClass::Motorway, false}},
        {"motorway_link", {RoadClass::Motorway, true}},
        {"trunk", {RoadClass::Trunk, false}},
        {"trunk_link", {RoadClass::Trunk, true}},
        {"primary", {RoadClass::Primary, false}},
        {"primary_link", {RoadClass::Primary, true}},
        {"secondary", {RoadClass::Secondary, false}},
        {"secondary_link", {RoadClass::Secondary, true}},
        {"tertiary", {RoadClass::Tertiary, false}},
        {"tertiary_link", {RoadClass::Tertiary, true}},
        {"unclassified", {RoadClass::Unclassified, false}},
        {"road", {RoadClass::Unclassified, false}},
        {"residential", {RoadClass::Residential, false}},
        {"living_street", {RoadClass::Residential, false}},
        {"service", {RoadClass::Service, false}},
        {"pedestrian", {RoadClass::Pedestrian, false}},
        {"track", {RoadClass::Track, false}},
        {"path", {RoadClass::Path, false}},
        {"footway", {RoadClass::Path, false}},
        {"cycleway", {RoadClass::Path, false}},
        {"bridleway", {RoadClass::Path, false}},
        {"steps", {RoadClass::Path, false}},
        {"busway", {RoadClass::Service, false}},
        {"escape", {RoadClass::Service, false}},
    }};
    for (const auto& [key, mapping] : kTable) {
        if (key == h) return mapping;
    }
    return std::nullopt;
}

float defaultSpeedKmh(RoadClass cls) {
    static constexpr std::array<float, kRoadClassCount> kSpeed{110, 90, 70, 60, 50, 40, 30, 20, 5, 15, 5};
    return kSpeed[static_cast<std::size_t>(cls)];
}

std::string_view roadClassName(RoadClass cls) {
    static constexpr std::array<std::string_view, kRoadClassCount> kNames{
        "motorway",    "trunk",   "primary",    "secondary", "tertiary", "unclassified",
        "residential", "service", "pedestrian", "track",     "path"};
    return kNames[static_cast<std::size_t>(cls)];
}

}  // namespace navmap::map
