// SPDX-License-Identifier: Apache-2.0
#pragma once
// A label as it was drawn in one frame, in screen pixels after projection: what the label
// quality metrics measure (docs/architecture.md "Quality bars": measured on what is drawn, never on layout
// boxes alone). The renderer's label pass fills one per label with drawn opacity > 0.
// Screen pixels: origin top left, x right, y down.

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include <glm/vec2.hpp>

#include "navmap/render/labels/label_types.h"

namespace navmap::render::labels {

/// A convex quadrilateral on screen (corners in order around it).
using ScreenQuad = std::array<glm::vec2, 4>;

struct DrawnLabel {
    std::uint64_t id = 0;  ///< the layout id (stable over frames)
    std::string text;      ///< the label's text as drawn (UTF-8)
    LabelKind kind = LabelKind::Point;
    bool world_space = false;  ///< drawn in the 3D world (perspective) rather than on the screen plane
    /// Opacity as drawn: the layout's fade times the weight of its space (SS/WS cross-fade) and
    /// any legibility fade (world-space text too small to read fades out).
    float opacity = 0.0F;
    glm::vec2 anchor{0.0F};  ///< projected anchor of the feature
    glm::vec2 center{0.0F};  ///< center of the drawn text box
    /// Cap height of the text on screen, px; for world-space text the smallest over the label
    /// (perspective shrinks its far end).
    float cap_height_px = 0.0F;
    /// Each glyph's drawn extent with its outline and halo (what the fragment shader can colour),
    /// after rotation and projection. The icon of a POI label is a glyph too.
    std::vector<ScreenQuad> glyph_boxes;
    /// Share of the label's drawn pixels hidden by scene geometry (buildings, terrain) in the
    /// final frame, the transparency aura taken into account; negative when not measured.
    float occluded_fraction = -1.0F;
};

/// Why a label's candidate came into or went out of the layout's input between two frames (the
/// renderer's label pass reports it for the labels the pop causes need: docs/labels.md "Pops by
/// cause").
enum class InputCause : std::uint8_t {
    View,          ///< its anchor crossed the viewport's edge or the near plane (camera motion)
    Tiles,         ///< no drawn tile carried it before / any more (tile loaded, dropped, other level)
    TooSmall,      ///< world-space text too small to read (left out / back in)
    Hidden,        ///< behind the terrain
    StreetRepeat,  ///< another piece of the same street nearby carries the name
};

/// One change of the layout's input: `arrived` true for a candidate that was none in the
/// previous frame, false for a label of the previous frame's layout output that is no candidate
/// any more.
struct LabelInputChange {
    std::uint64_t id = 0;
    bool arrived = false;
    InputCause cause = InputCause::Tiles;
};

/// The vehicle marker as drawn: its screen outline (convex), or an empty vector when no marker.
struct DrawnMarker {
    std::vector<glm::vec2> outline;
};

}  // namespace navmap::render::labels
