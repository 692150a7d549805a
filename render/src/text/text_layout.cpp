// SPDX-License-Identifier: Apache-2.0
#include "navmap/render/text/text_layout.h"

#include <algorithm>
#include <cmath>

namespace navmap::render::text {

namespace {

// Appends the quads of `text` with the pen starting at `origin` (px, baseline, y down).
void appendQuads(const ShapedText& text, GlyphAtlas& atlas, float size_px, glm::vec2 origin, std::uint8_t layer,
                 LaidOutText& out) {
    float pen = 0.0f;  // em
    float pen_y = 0.0f;
    for (const ShapedGlyph& sg : text.glyphs) {
        const AtlasGlyph* g = atlas.glyph(sg.font, sg.glyph);
        if (!g) {
            ++out.dropped;
        } else if (!g->empty) {
            const float x0 = pen + sg.x_offset + g->left;
            const float top = pen_y + sg.y_offset + g->top;
            GlyphQuad q;
            q.p0 = origin + glm::vec2(x0, -top) * size_px;
            q.p1 = origin + glm::vec2(x0 + g->width, -(top - g->height)) * size_px;
            q.t0 = glm::vec2(static_cast<float>(g->texels.x), static_cast<float>(g->texels.y));
            q.t1 =
                glm::vec2(static_cast<float>(g->texels.x + g->texels.w), static_cast<float>(g->texels.y + g->texels.h));
            q.layer = layer;
            out.quads.push_back(q);
        }
        pen += sg.x_advance;
        pen_y += sg.y_advance;
    }
}

}  // namespace

TextMetrics measureText(const ShapedText& text, float size_px) {
    TextMetrics m;
    m.width = text.advance * size_px;
    m.ascent = text.ascender * size_px;
    m.descent = -text.descender * size_px;
    m.height = m.ascent + m.descent;
    m.cap_height = text.cap_height * size_px;
    return m;
}

LaidOutText layoutText(const ShapedText& text, GlyphAtlas& atlas, float size_px, TextAnchor anchor) {
    LaidOutText out;
    out.size_px = size_px;
    out.metrics = measureText(text, size_px);
    out.quads.reserve(text.glyphs.size());
    glm::vec2 origin(0.0f);
    if (anchor == TextAnchor::Center) {
        // Box spans x [0, width], y [-ascent, descent] around the pen start; center it.
        origin = glm::vec2(-0.5f * out.metrics.width, 0.5f * (out.metrics.ascent - out.metrics.descent));
    }
    appendQuads(text, atlas, size_px, origin, 0, out);
    return out;
}

LaidOutText layoutIconText(const ShapedText& icon, const ShapedText& text, GlyphAtlas& atlas, float size_px,
                           float icon_scale, float gap_em) {
    LaidOutText out;
    out.size_px = size_px;
    const float icon_px = size_px * icon_scale;
    const TextMetrics mi = measureText(icon, icon_px);
    const TextMetrics mt = measureText(text, size_px);
    const float gap = gap_em * size_px;
    out.metrics.width = mi.width + gap + mt.width;
    out.metrics.ascent = std::max(mi.ascent, mt.ascent);
    out.metrics.descent = std::max(mi.descent, mt.descent);
    out.metrics.height = out.metrics.ascent + out.metrics.descent;
    out.metrics.cap_height = mt.cap_height;
    const float left = -0.5f * out.metrics.width;
    // Both line boxes centered on the anchor's y.
    const float icon_base = 0.5f * (mi.ascent - mi.descent);
    const float text_base = 0.5f * (mt.ascent - mt.descent);
    // The icon quads were rasterized at the same atlas base size: lay them out at icon_px but
    // express them in units of size_px so one SDF scale per label holds (the shader scales
    // distances by size_px; icon distances come out icon_scale too small, which only thins
    // their outline slightly).
    LaidOutText icon_quads;
    appendQuads(icon, atlas, icon_px, glm::vec2(left, icon_base), 1, icon_quads);
    appendQuads(text, atlas, size_px, glm::vec2(left + mi.width + gap, text_base), 0, out);
    out.quads.insert(out.quads.begin(), icon_quads.quads.begin(), icon_quads.quads.end());
    out.dropped += icon_quads.dropped;
    return out;
}

float drawnGlyphInsetPx(float em_px, float spread_em, float outline_px, float halo_px, float scale) {
    // As text_sdf.vert: outline and halo must stay inside the stored distance range of the quad.
    const float spread = spread_em * em_px;
    const float reach = std::max(spread - 1.0f, 0.0f);
    const float outline = std::min(outline_px * scale, reach);
    const float halo = std::min(halo_px * scale, reach - outline);
    return std::max(spread - (outline + halo + 0.5f), 0.0f);
}

void appendDrawnGlyphBoxes(std::span<const GlyphQuad> quads, float size_px, float scale, float angle_rad,
                           glm::vec2 position, float spread_em, float outline_px, float halo_px,
                           std::vector<ScreenQuad>& out) {
    const float inset = drawnGlyphInsetPx(size_px * scale, spread_em, outline_px, halo_px, scale);
    const float c = std::cos(angle_rad);
    const float s = std::sin(angle_rad);
    const auto place = [&](glm::vec2 p) { return position + glm::vec2(c * p.x - s * p.y, s * p.x + c * p.y); };
    for (const GlyphQuad& q : quads) {
        const glm::vec2 lo = q.p0 * scale + inset;
        const glm::vec2 hi = q.p1 * scale - inset;
        if (!(hi.x > lo.x && hi.y > lo.y)) continue;
        out.push_back({place(lo), place({hi.x, lo.y}), place(hi), place({lo.x, hi.y})});
    }
}

}  // namespace navmap::render::text
