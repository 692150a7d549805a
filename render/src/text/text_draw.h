// SPDX-License-Identifier: Apache-2.0
#pragma once
// GL-free descriptions of label text to draw, screen-space and world-space (docs/architecture.md "Render passes": SS
// labels in bird's-eye, WS labels in snail's view). The GL layer consumes them.

#include <span>

#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include "navmap/render/text/text_layout.h"

namespace navmap::render::text {

/// Appearance (seed 4.5.2, Fig. 4.7): fill, a dark outline for contrast and a light halo that
/// clears the background. Colours are straight (not premultiplied) RGBA in [0, 1]; widths in
/// pixels at scale 1 (they scale with the label).
struct TextStyle {
    glm::vec4 fill{0.1f, 0.1f, 0.1f, 1.0f};
    glm::vec4 outline{0.0f, 0.0f, 0.0f, 0.0f};
    float outline_px = 0.0f;
    glm::vec4 halo{1.0f, 1.0f, 1.0f, 0.85f};
    float halo_px = 2.0f;
    glm::vec4 icon{0.8f, 0.3f, 0.1f, 1.0f};  ///< fill of quads with layer 1
};

/// A label in screen space. `quads` must stay alive for the draw call.
struct TextDraw {
    std::span<const GlyphQuad> quads;
    float size_px = 16.0f;     ///< size the quads were laid out at (LaidOutText::size_px)
    glm::vec2 position{0.0f};  ///< anchor, screen pixels, origin top left, y down
    float angle_rad = 0.0f;    ///< rotation about the anchor, clockwise on screen (y down)
    float scale = 1.0f;        ///< depth scale of the layout (PlacedLabel::scale)
    float alpha = 1.0f;        ///< fade (PlacedLabel::alpha)
    TextStyle style;
};

/// A label that is part of the 3D world (seed 5.2.1): its text lies in a plane of the scene,
/// spanned by `right` (the baseline, along which it reads) and `up`, so the perspective
/// projection foreshortens it with distance like everything else; depth-tested against the scene.
struct WorldTextDraw {
    std::span<const GlyphQuad> quads;
    float size_px = 16.0f;              ///< size the quads were laid out at
    glm::vec3 position{0.0f};           ///< the text box's center, in the frame of the view matrix passed to the draw
    glm::vec3 right{1.0f, 0.0f, 0.0f};  ///< unit baseline direction
    glm::vec3 up{0.0f, 0.0f, 1.0f};     ///< unit direction from the baseline to the tops of the glyphs
    float em_m = 20.0f;                 ///< em height of the text in the world, metres
    float alpha = 1.0f;
    TextStyle style;
};

}  // namespace navmap::render::text
