// SPDX-License-Identifier: Apache-2.0
#pragma once
// The legal speed limit of a road from its OSM tags (`maxspeed`, `maxspeed:forward`,
// `maxspeed:backward`, `maxspeed:conditional`), in whole km/h per direction, 0 where it is not
// known (docs/tile-store.md "Speed limits"). Numbers with units (km/h, mph, knots) and the
// implicit values of the OSM wiki's "Default speed limits" table (`FR:urban`, `DE:motorway`,
// ...) are understood; `none`, `walk`, `signals`, several values and anything else are unknown.
// Pure functions over a tag lookup; offline only.

#include <cstdint>
#include <optional>
#include <string_view>
#include <vector>

#include "navmap/map/compile/tag_rules.h"

namespace navmap::map {

/// A limit in km/h (rounded to whole km/h) from one maxspeed value: "50", "30 mph", "10 knots",
/// "90 km/h", "FR:urban", "GB:nsl_single". 0: not a limit known as a number ("none", "walk",
/// "signals", "variable", "50;30", an unknown country code, junk).
std::uint16_t parseSpeedLimitKmh(std::string_view text);

/// The implicit limit of a "CC:context" value (the OSM wiki table), or nullopt when the table
/// does not list it (a listed context without a fixed limit, such as "DE:motorway", gives 0).
std::optional<std::uint16_t> implicitSpeedLimitKmh(std::string_view code);

/// One entry of `maxspeed:conditional` ("30 @ (22:00-06:00); 70 @ wet").
struct ConditionalSpeedLimit {
    std::uint16_t kmh = 0;          ///< 0: the value is not a known limit
    std::string_view condition;     ///< the text in (or without) the parentheses
    bool time_of_day_only = false;  ///< only "hh:mm-hh:mm" ranges, comma separated
};
/// Splits a `maxspeed:conditional` value into its entries (an entry without "@" is skipped).
std::vector<ConditionalSpeedLimit> parseConditionalSpeedLimits(std::string_view text);

/// The limits in both directions of a way, relative to its node order.
struct DirectionalSpeedLimits {
    std::uint16_t forward_kmh = 0;
    std::uint16_t backward_kmh = 0;
};
/// `maxspeed:forward` / `maxspeed:backward` where given, else `maxspeed` for both. A
/// conditional limit does not change them (the store has no time; docs/tile-store.md).
DirectionalSpeedLimits speedLimitsFromTags(const TagLookup& tags);

}  // namespace navmap::map
