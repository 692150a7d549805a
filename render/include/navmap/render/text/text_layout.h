// SPDX-License-Identifier: Apache-2.0
#pragma once
// Shaped text -> glyph quads in pixels relative to the label anchor, and text metrics for
// the label layout's boxes (seed 4.4.4 OOBBs).

#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include <glm/vec2.hpp>

#include "navmap/render/text/glyph_atlas.h"
#include "navmap/render/text/shaped_text.h"

namespace navmap::render::text {

/// One glyph to draw: a screen-aligned quad before rotation. Pixels relative to the label
/// anchor, x right, y down (screen convention); atlas coordinates in texels (the shader
/// divides by the atlas size, so quads survive atlas growth but not a repack).
struct GlyphQuad {
    glm::vec2 p0{0.0f};      ///< top-left corner, px
    glm::vec2 p1{0.0f};      ///< bottom-right corner, px
    glm::vec2 t0{0.0f};      ///< atlas texel of p0
    glm::vec2 t1{0.0f};      ///< atlas texel of p1
    std::uint8_t layer = 0;  ///< 0: text, 1: icon (drawn in the icon colour)
};

/// Text extent at a given size in pixels; linear in the size.
struct TextMetrics {
    float width = 0.0f;       ///< pen advance of the whole run
    float height = 0.0f;      ///< ascent + descent (line box of the primary font)
    float ascent = 0.0f;      ///< above the baseline, positive
    float descent = 0.0f;     ///< below the baseline, positive
    float cap_height = 0.0f;  ///< capital letters above the baseline (the legibility measure)
};

/// Where the anchor lies on the text box.
enum class TextAnchor : std::uint8_t {
    Center,        ///< box center (the label layout's boxes are centered)
    BaselineLeft,  ///< pen start on the baseline
};

/// Quads and metrics of one label.
struct LaidOutText {
    std::vector<GlyphQuad> quads;
    TextMetrics metrics;      ///< the whole label box (icon included)
    float size_px = 0.0f;     ///< em size the quads were laid out at (the SDF scale)
    std::size_t dropped = 0;  ///< glyphs the atlas could not hold this frame
};

TextMetrics measureText(const ShapedText& text, float size_px);

/// Lays out `text` at `size_px`, rasterizing missing glyphs into `atlas`.
LaidOutText layoutText(const ShapedText& text, GlyphAtlas& atlas, float size_px,
                       TextAnchor anchor = TextAnchor::Center);

/// POI label: `icon` (a symbol run) left of `text`, vertically centered on the text's
/// x-height band, separated by `gap_em` em; the whole box centered on the anchor.
LaidOutText layoutIconText(const ShapedText& icon, const ShapedText& text, GlyphAtlas& atlas, float size_px,
                           float icon_scale = 1.2f, float gap_em = 0.3f);

/// A glyph's drawn extent on screen: a convex quadrilateral, corners in order around it.
using ScreenQuad = std::array<glm::vec2, 4>;

/// How far inside a glyph quad its drawn pixels end, in screen px. A quad carries `spread_em`
/// em of distance field around the ink; the SDF shader colours the outline and the halo out to
/// at most that spread less a pixel, plus half a pixel of antialiasing (text_sdf.vert/.frag).
/// `em_px` is the em size on screen; outline and halo widths are px at scale 1, `scale` is the
/// label's scale. Never negative.
float drawnGlyphInsetPx(float em_px, float spread_em, float outline_px, float halo_px, float scale);

/// The drawn extent of each glyph of a screen-space label (quads laid out at `size_px`, drawn at
/// `scale`, rotated by `angle_rad` clockwise on a y-down screen about `position`): the quad
/// shrunk by drawnGlyphInsetPx(), rotated and moved, appended to `out`.
void appendDrawnGlyphBoxes(std::span<const GlyphQuad> quads, float size_px, float scale, float angle_rad,
                           glm::vec2 position, float spread_em, float outline_px, float halo_px,
                           std::vector<ScreenQuad>& out);

}  // namespace navmap::render::text
