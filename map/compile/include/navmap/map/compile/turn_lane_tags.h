// SPDX-License-Identifier: Apache-2.0
#pragma once
// The turn lanes of a road from its OSM tags (`turn:lanes`, `turn:lanes:forward`,
// `turn:lanes:backward`, with `lanes`, `lanes:forward`, `lanes:backward` for the counts), per
// direction of travel, as lane_arrow bits left to right (docs/tile-store.md "Turn lanes"). Unknown
// values are counted and ignored. Pure functions over a tag lookup; offline only.

#include <cstddef>
#include <cstdint>
#include <string_view>
#include <vector>

#include "navmap/map/compile/tag_rules.h"
#include "navmap/map/turn_lanes.h"

namespace navmap::map {

/// One `turn:lanes` value: the lanes and how many of its values were not understood.
struct ParsedTurnLanes {
    std::vector<std::uint16_t> lanes;  ///< lane_arrow bits per lane, left to right (0: none)
    std::size_t unknown_values = 0;    ///< values ignored ("slide_left", "foo"); their lane keeps the rest
    bool too_many = false;             ///< more than kMaxTurnLanes lanes: `lanes` is empty
};
/// "left|through;right|none", "merge_to_left||" (an empty lane is `none`). Whitespace around a
/// value is ignored; an empty text gives no lanes.
ParsedTurnLanes parseTurnLanes(std::string_view text);

/// The turn lanes of both directions of a way, relative to its node order.
struct DirectionalTurnLanes {
    std::vector<std::uint16_t> forward;   ///< along the nodes; empty: none
    std::vector<std::uint16_t> backward;  ///< against the nodes; empty: none
    std::size_t unknown_values = 0;       ///< over every tag read
    std::size_t dropped = 0;              ///< tags not used: too many lanes, or counts that contradict
};
/// `oneway_direction`: +1 one-way along the nodes, -1 against them, 0 two-way (tag_rules.h
/// onewayDirection). One-way: `turn:lanes` for the direction driven (or the `:forward` /
/// `:backward` form naming it). Two-way: `turn:lanes:forward` and `turn:lanes:backward`; a plain
/// `turn:lanes` of n lanes only for a direction whose count says n (`lanes:forward` /
/// `lanes:backward`, or `lanes` = 2n without them), as it does not say which direction it means.
DirectionalTurnLanes turnLanesFromTags(const TagLookup& tags, int oneway_direction);

}  // namespace navmap::map
