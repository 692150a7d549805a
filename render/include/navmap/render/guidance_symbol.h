// SPDX-License-Identifier: Apache-2.0
#pragma once
// The manoeuvre symbols of the guidance overlay as plain triangles (no font glyphs): a thick path
// ending in an arrow head for each manoeuvre type, the roads not taken and a roundabout's ring
// dimmed, a flag for the arrival. Drawn for right-hand traffic (roundabouts counter-clockwise,
// u-turns to the left). GL-free.

#include <cstdint>
#include <vector>

#include <glm/vec2.hpp>

#include "navmap/render/map_frame.h"

namespace navmap::render {

struct GuidanceSymbolGeometry {
    std::vector<glm::vec2> primary;    ///< triangles (three vertices each): the path taken, the head
    std::vector<glm::vec2> secondary;  ///< triangles in the dim colour: roads not taken, the ring
    glm::vec2 exit_label_at{0.0f};     ///< Roundabout: the ring's centre, where the exit number goes
    float exit_label_px = 0.0f;        ///< room for that number (its em size), 0: no ring
};

/// The symbol in the square of side `size_px` centred on `centre` (screen pixels, y down).
/// `roundabout_exit` (1 = first) turns a roundabout's exit arm: first to the right, second
/// straight on, third to the left, fourth and later back beside the entry; 0: straight on.
GuidanceSymbolGeometry guidanceSymbol(ManeuverSymbol symbol, int roundabout_exit, glm::vec2 centre, float size_px);

/// The arrows painted on one lane (map::lane_arrow bits; turn_lanes.h) as triangles in the
/// square of side `size_px` centred on `centre`: one stem from the bottom, a branch with a head
/// per direction (through up, slight at 45 degrees, turns at 90, sharp at 135, reverse hooked back
/// down on the left, a merge as a diagonal over to its side). No bits: nothing.
std::vector<glm::vec2> laneArrowSymbol(std::uint16_t arrows, glm::vec2 centre, float size_px);

}  // namespace navmap::render
