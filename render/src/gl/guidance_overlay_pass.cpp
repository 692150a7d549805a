// SPDX-License-Identifier: Apache-2.0
#include "guidance_overlay_pass.h"
#include "street_bar_layout.h"
#include "text_layer.h"

#include <algorithm>
#include <cmath>
#include <string>

#include <glm/gtc/type_ptr.hpp>

#include "gl/gl_work.h"
#include "navmap/map/turn_lanes.h"
#include "navmap/render/guidance_symbol.h"

namespace navmap::render::gl {

GuidanceLayout guidanceLayout(int width, int height) {
    // The HUD's 800 x 240 in layout pixels, scaled to fit the target (within readable bounds).
    const float unit = std::clamp(std::min(float(width) / 800.0f, float(height) / 240.0f), 0.5f, 1.6f);
    GuidanceLayout l;
    l.unit = unit;
    l.symbol_px = 150.0f * unit;
    l.symbol_centre = glm::vec2(20.0f * unit + 0.5f * l.symbol_px, 0.5f * float(height) - 6.0f * unit);
    const float text_x = 20.0f * unit + l.symbol_px + 18.0f * unit;
    l.distance_px = 64.0f * unit;
    l.distance_at = {text_x, l.symbol_centre.y + 2.0f * unit};
    l.street_px = 30.0f * unit;
    l.street_at = {text_x, l.symbol_centre.y + 48.0f * unit};
    l.remaining_px = 26.0f * unit;
    l.remaining_right = {float(width) - 18.0f * unit, float(height) - 16.0f * unit};
    return l;
}

SpeedLimitSignLayout speedLimitSignLayout(int width, int height, SignCorner corner, int digits) {
    const float unit = guidanceLayout(width, height).unit;
    SpeedLimitSignLayout l;
    l.radius = 36.0f * unit;
    // The ring is a sixth of the diameter, as on the signs of the Vienna Convention (C14).
    l.inner_radius = l.radius * (2.0f / 3.0f);
    const float margin = 14.0f * unit + l.radius;
    const bool left = corner == SignCorner::TopLeft || corner == SignCorner::BottomLeft;
    const bool top = corner == SignCorner::TopLeft || corner == SignCorner::TopRight;
    l.centre = {left ? margin : float(width) - margin, top ? margin : float(height) - margin};
    l.text_px = (digits >= 3 ? 0.82f : 1.05f) * l.inner_radius;
    return l;
}

LaneRowLayout laneRowInPanel(const GuidanceLayout& g) {
    LaneRowLayout l;
    l.box = glm::vec2(26.0f, 28.0f) * g.unit;
    l.gap = 3.0f * g.unit;
    l.origin = {g.distance_at.x, g.symbol_centre.y - 0.5f * g.symbol_px};
    return l;
}

LaneRowLayout laneRowAtTop(int width, int height, std::size_t lanes) {
    const float unit = guidanceLayout(width, height).unit;
    LaneRowLayout l;
    l.box = glm::vec2(34.0f, 40.0f) * unit;
    l.gap = 4.0f * unit;
    l.pad = 6.0f * unit;
    l.origin = {0.5f * (float(width) - l.width(std::min(lanes, map::kMaxTurnLanes))), 14.0f * unit + l.pad};
    return l;
}

std::pair<glm::vec2, glm::vec2> laneRowPanel(const LaneRowLayout& l, std::size_t lanes) {
    const glm::vec2 lo = l.origin - glm::vec2(l.pad);
    const glm::vec2 hi = l.origin + glm::vec2(l.width(std::min(lanes, map::kMaxTurnLanes)), l.box.y) + glm::vec2(l.pad);
    return {lo, hi};
}

namespace {

/// Two triangles covering the box lo..hi.
std::vector<glm::vec2> rectangle(glm::vec2 lo, glm::vec2 hi) {
    return {lo, {lo.x, hi.y}, {hi.x, lo.y}, {hi.x, lo.y}, {lo.x, hi.y}, hi};
}

/// A disc as a triangle list (screen pixels).
void appendDisc(std::vector<glm::vec2>& out, glm::vec2 centre, float radius) {
    constexpr int kSegments = 64;
    constexpr float kTwoPi = 6.28318530718f;
    for (int i = 0; i < kSegments; ++i) {
        const float a0 = kTwoPi * float(i) / kSegments, a1 = kTwoPi * float(i + 1) / kSegments;
        out.push_back(centre);
        out.push_back(centre + radius * glm::vec2(std::cos(a0), std::sin(a0)));
        out.push_back(centre + radius * glm::vec2(std::cos(a1), std::sin(a1)));
    }
}

/// A rectangle with rounded corners (convex) as a fan of triangles from its centre.
void appendRoundedRect(std::vector<glm::vec2>& out, glm::vec2 lo, glm::vec2 hi, float radius) {
    constexpr int kCornerSegments = 8;
    constexpr float kHalfPi = 1.57079632679f;
    radius = std::clamp(radius, 0.0f, 0.5f * std::min(hi.x - lo.x, hi.y - lo.y));
    // Corner centres in order round the rectangle, each with the angle its arc starts at.
    const glm::vec2 corners[4] = {{hi.x - radius, hi.y - radius},
                                  {lo.x + radius, hi.y - radius},
                                  {lo.x + radius, lo.y + radius},
                                  {hi.x - radius, lo.y + radius}};
    std::vector<glm::vec2> rim;
    rim.reserve(4 * (kCornerSegments + 1));
    for (int c = 0; c < 4; ++c)
        for (int i = 0; i <= kCornerSegments; ++i) {
            const float a = kHalfPi * (float(c) + float(i) / kCornerSegments);
            rim.push_back(corners[c] + radius * glm::vec2(std::cos(a), std::sin(a)));
        }
    const glm::vec2 centre = 0.5f * (lo + hi);
    for (std::size_t i = 0; i < rim.size(); ++i) {
        out.push_back(centre);
        out.push_back(rim[i]);
        out.push_back(rim[(i + 1) % rim.size()]);
    }
}

// Every overlay draws over the finished frame: no depth test, no culling, blended, and the
// frame's alpha stays opaque.
void beginOverlay(const RenderTarget& target) {
    target.bindForDrawing(false);
    glDisable(GL_DEPTH_TEST);
    glDisable(GL_CULL_FACE);
    glEnable(GL_BLEND);
    glBlendFuncSeparate(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA, GL_ZERO, GL_ONE);
}

// Text in one colour, without outline or halo (on a sign or a panel of its own).
text::TextStyle plainText(const glm::vec4& fill) {
    text::TextStyle ts;
    ts.fill = fill;
    ts.outline = {0.0f, 0.0f, 0.0f, 0.0f};
    ts.outline_px = 0.0f;
    ts.halo = {fill.r, fill.g, fill.b, 0.0f};
    ts.halo_px = 0.0f;
    return ts;
}

}  // namespace

GuidanceOverlayPass::GuidanceOverlayPass()
    : m_text(std::make_unique<TextLayer>(m_engine.atlas())),
      m_program(ShaderProgram::fromEmbedded("guidance_symbol.vert", "guidance_symbol.frag")) {
    glGenVertexArrays(1, &m_vao);
    glGenBuffers(1, &m_vbo);
    glBindVertexArray(m_vao);
    glBindBuffer(GL_ARRAY_BUFFER, m_vbo);
    glEnableVertexAttribArray(0);
    glVertexAttribPointer(0, 2, GL_FLOAT, GL_FALSE, 0, nullptr);
    glBindVertexArray(0);
    glBindBuffer(GL_ARRAY_BUFFER, 0);
}

GuidanceOverlayPass::~GuidanceOverlayPass() {
    glDeleteVertexArrays(1, &m_vao);
    glDeleteBuffers(1, &m_vbo);
}

void GuidanceOverlayPass::drawTriangles(const std::vector<glm::vec2>& vertices, glm::vec4 color, glm::vec2 viewport) {
    if (vertices.empty()) return;
    glUseProgram(m_program.id());
    glUniform2fv(m_program.uniform("u_viewport"), 1, glm::value_ptr(viewport));
    glUniform4fv(m_program.uniform("u_color"), 1, glm::value_ptr(color));
    glBindVertexArray(m_vao);
    glBindBuffer(GL_ARRAY_BUFFER, m_vbo);
    countedBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(vertices.size() * sizeof(glm::vec2)), vertices.data(),
                      GL_STREAM_DRAW);
    countedDrawArrays(GL_TRIANGLES, 0, static_cast<GLsizei>(vertices.size()));
    glBindBuffer(GL_ARRAY_BUFFER, 0);
    glBindVertexArray(0);
}

void GuidanceOverlayPass::draw(const GuidanceOverlay& overlay, const MapStyle& style, const RenderTarget& target) {
    const glm::ivec2 size(target.width(), target.height());
    const glm::vec2 viewport(size);
    const GuidanceLayout l = guidanceLayout(size.x, size.y);
    beginOverlay(target);

    // Texts first laid out, so that the panel can span them.
    m_engine.beginFrame();
    text::TextStyle ts;
    ts.fill = glm::vec4(style.guidance_text, 1.0f);
    ts.outline = {0.0f, 0.0f, 0.0f, 0.9f};
    ts.outline_px = 2.0f;
    ts.halo = {0.0f, 0.0f, 0.0f, 0.55f};  // dark: black is transparent on a HUD combiner
    ts.halo_px = 3.0f;
    std::vector<text::LaidOutText> laid;
    laid.reserve(5);
    std::vector<text::TextDraw> draws;
    float panel_right = l.symbol_centre.x + 0.5f * l.symbol_px;
    const LaneRowLayout lane_row = laneRowInPanel(l);
    if (overlay.lanes && !overlay.lanes->lanes.empty()) {
        const std::size_t n = std::min(overlay.lanes->lanes.size(), map::kMaxTurnLanes);
        panel_right = std::max(panel_right, lane_row.origin.x + lane_row.width(n));
    }
    auto add = [&](const std::string& utf8, text::FontStyle font, float px, glm::vec2 at, text::TextAnchor anchor,
                   bool right_aligned) {
        if (utf8.empty()) return;
        const text::RunId run = m_engine.run(utf8, font);
        laid.push_back(m_engine.layout(run, px, anchor));
        const text::LaidOutText& t = laid.back();
        if (right_aligned)
            at.x -= t.metrics.width;
        else if (anchor == text::TextAnchor::BaselineLeft)
            panel_right = std::max(panel_right, at.x + t.metrics.width);
        draws.push_back({t.quads, t.size_px, at, 0.0f, 1.0f, 1.0f, ts});
    };
    add(overlay.distance, text::FontStyle::Bold, l.distance_px, l.distance_at, text::TextAnchor::BaselineLeft, false);
    add(overlay.street, text::FontStyle::Regular, l.street_px, l.street_at, text::TextAnchor::BaselineLeft, false);
    std::string remaining = overlay.remaining_distance;
    if (!remaining.empty() && !overlay.remaining_time.empty()) remaining += "  ·  ";
    remaining += overlay.remaining_time;
    add(remaining, text::FontStyle::Regular, l.remaining_px, l.remaining_right, text::TextAnchor::BaselineLeft, true);

    const GuidanceSymbolGeometry symbol =
        guidanceSymbol(overlay.symbol, overlay.roundabout_exit, l.symbol_centre, l.symbol_px);
    if (symbol.exit_label_px > 0.0f && overlay.roundabout_exit > 0) {
        add(std::to_string(overlay.roundabout_exit), text::FontStyle::Bold, 0.8f * symbol.exit_label_px,
            symbol.exit_label_at, text::TextAnchor::Center, false);
    }

    if (style.guidance_panel.a > 0.0f) {
        const float pad = 10.0f * l.unit;
        const glm::vec2 lo(l.symbol_centre.x - 0.5f * l.symbol_px - pad, l.symbol_centre.y - 0.5f * l.symbol_px - pad);
        const glm::vec2 hi(panel_right + pad, l.symbol_centre.y + 0.5f * l.symbol_px + pad);
        drawTriangles(rectangle(lo, hi), style.guidance_panel, viewport);
    }
    if (overlay.lanes) drawLaneBoxes(*overlay.lanes, lane_row, style, viewport);
    drawTriangles(symbol.secondary, glm::vec4(style.guidance_symbol_dim, 1.0f), viewport);
    drawTriangles(symbol.primary, glm::vec4(style.guidance_symbol, 1.0f), viewport);
    if (!draws.empty()) m_text->drawScreen(draws, size);
    glDisable(GL_BLEND);
    glDisable(GL_DEPTH_TEST);
    target.bindForDrawing(false);
}

void GuidanceOverlayPass::drawSpeedLimit(const SpeedLimitSign& sign, const RenderTarget& target) {
    if (sign.kmh <= 0) return;
    const glm::ivec2 size(target.width(), target.height());
    const glm::vec2 viewport(size);
    const std::string number = std::to_string(sign.kmh);
    const SpeedLimitSignLayout l = speedLimitSignLayout(size.x, size.y, sign.corner, static_cast<int>(number.size()));
    beginOverlay(target);

    // Red disc, white disc over it: the ring is what stays red.
    std::vector<glm::vec2> disc;
    appendDisc(disc, l.centre, l.radius);
    drawTriangles(disc, glm::vec4(0.80f, 0.05f, 0.05f, 1.0f), viewport);
    disc.clear();
    appendDisc(disc, l.centre, l.inner_radius);
    drawTriangles(disc, glm::vec4(1.0f), viewport);

    m_engine.beginFrame();
    const text::TextStyle ts = plainText(glm::vec4(0.0f, 0.0f, 0.0f, 1.0f));
    const text::LaidOutText laid =
        m_engine.layout(m_engine.run(number, text::FontStyle::Bold), l.text_px, text::TextAnchor::Center);
    const text::TextDraw draw{laid.quads, laid.size_px, l.centre, 0.0f, 1.0f, 1.0f, ts};
    m_text->drawScreen(std::span<const text::TextDraw>(&draw, 1), size);
    glDisable(GL_BLEND);
    target.bindForDrawing(false);
}

void GuidanceOverlayPass::drawLaneBoxes(const LaneRow& row, const LaneRowLayout& l, const MapStyle& style,
                                        glm::vec2 viewport) {
    const std::size_t n = std::min(row.lanes.size(), map::kMaxTurnLanes);
    // A lane to take: a lighter box and the arrows in the symbol's colour; the others stay dark
    // with their arrows dimmed, so that the lanes to take stand out also where they have no arrows.
    const glm::vec4 box_on(0.22f, 0.42f, 0.75f, 1.0f), box_off(0.16f, 0.17f, 0.20f, 1.0f);
    std::vector<glm::vec2> on_boxes, off_boxes, on_arrows, off_arrows;
    for (std::size_t i = 0; i < n; ++i) {
        const bool on = i < 32 && (row.recommended >> i & 1U) != 0;
        const glm::vec2 lo = l.origin + glm::vec2(float(i) * (l.box.x + l.gap), 0.0f);
        const glm::vec2 hi = lo + l.box;
        auto& boxes = on ? on_boxes : off_boxes;
        const auto r = rectangle(lo, hi);
        boxes.insert(boxes.end(), r.begin(), r.end());
        const float side = std::min(l.box.x, l.box.y) * 0.9f;
        const auto glyph = laneArrowSymbol(row.lanes[i], 0.5f * (lo + hi), side);
        auto& arrows = on ? on_arrows : off_arrows;
        arrows.insert(arrows.end(), glyph.begin(), glyph.end());
    }
    drawTriangles(off_boxes, box_off, viewport);
    drawTriangles(on_boxes, box_on, viewport);
    drawTriangles(off_arrows, glm::vec4(style.guidance_symbol_dim, 1.0f), viewport);
    drawTriangles(on_arrows, glm::vec4(style.guidance_symbol, 1.0f), viewport);
}

void GuidanceOverlayPass::drawLanes(const LaneRow& row, const MapStyle& style, const RenderTarget& target) {
    if (row.lanes.empty()) return;
    const glm::ivec2 size(target.width(), target.height());
    const glm::vec2 viewport(size);
    const LaneRowLayout l = laneRowAtTop(size.x, size.y, row.lanes.size());
    beginOverlay(target);
    const auto [lo, hi] = laneRowPanel(l, row.lanes.size());
    const glm::vec4 panel =
        style.guidance_panel.a > 0.0f ? style.guidance_panel : glm::vec4(0.06f, 0.07f, 0.10f, 0.78f);
    drawTriangles(rectangle(lo, hi), panel, viewport);
    drawLaneBoxes(row, l, style, viewport);
    glDisable(GL_BLEND);
    target.bindForDrawing(false);
}

void GuidanceOverlayPass::drawStreetBar(const StreetBar& bar, const MapStyle& style, const RenderTarget& target) {
    const glm::ivec2 size(target.width(), target.height());
    m_engine.beginFrame();
    const StreetBarLayout l = streetBarLayout(m_engine, bar, size.x, size.y);
    if (l.text.empty()) return;
    beginOverlay(target);

    std::vector<glm::vec2> panel;
    appendRoundedRect(panel, l.lo, l.hi, l.corner_px);
    drawTriangles(panel, style.street_bar_panel, glm::vec2(size));

    // Plain text on the dark panel: no outline or halo to blur it.
    const text::TextStyle ts = plainText(glm::vec4(style.street_bar_text, 1.0f));
    const text::LaidOutText laid =
        m_engine.layout(m_engine.run(l.text, kStreetBarFont), l.text_px, text::TextAnchor::Center);
    const text::TextDraw draw{laid.quads, laid.size_px, l.text_centre, 0.0f, 1.0f, 1.0f, ts};
    m_text->drawScreen(std::span<const text::TextDraw>(&draw, 1), size);
    glDisable(GL_BLEND);
    target.bindForDrawing(false);
}

}  // namespace navmap::render::gl
