// SPDX-License-Identifier: Apache-2.0
#include "marker_pass.h"
#include "gl/gl_work.h"

#include <cmath>

#include <glm/gtc/type_ptr.hpp>

namespace navmap::render::gl {

MarkerPass::MarkerPass() : m_program(ShaderProgram::fromEmbedded("marker.vert", "marker.frag")) {
    // CCP arrow: tip at +y, notch at the back (marker units, about one unit across).
    const float arrow[] = {0.0f, 1.0f, -0.6f, -0.7f, 0.0f, -0.35f, 0.0f, 1.0f, 0.0f, -0.35f, 0.6f, -0.7f};
    glGenVertexArrays(1, &m_vao);
    glGenBuffers(1, &m_vbo);
    glBindVertexArray(m_vao);
    glBindBuffer(GL_ARRAY_BUFFER, m_vbo);
    countedBufferData(GL_ARRAY_BUFFER, sizeof arrow, arrow, GL_STATIC_DRAW);
    glEnableVertexAttribArray(0);
    glVertexAttribPointer(0, 2, GL_FLOAT, GL_FALSE, 0, nullptr);
    glBindVertexArray(0);
}

MarkerPass::~MarkerPass() {
    glDeleteVertexArrays(1, &m_vao);
    glDeleteBuffers(1, &m_vbo);
}

std::optional<MarkerPass::OnScreen> MarkerPass::place(const FrameContext& ctx) const {
    const MapFrame& frame = ctx.frame;
    const RenderTarget& target = ctx.target;
    if (!frame.layers.marker || !frame.marker) return std::nullopt;
    const MarkerState& m = *frame.marker;
    const double aspect = static_cast<double>(target.width()) / target.height();
    const glm::mat4 vp = frame.camera.projection(aspect) * frame.camera.viewRelativeTo(m.position);
    OnScreen out;
    out.anchor_clip = vp * glm::vec4(0.0f, 0.0f, 0.0f, 1.0f);
    if (out.anchor_clip.w <= 0.0f) return std::nullopt;  // behind the camera
    // Heading as it appears on screen: project a point a few metres ahead.
    const double rad = glm::radians(m.heading_deg);
    const glm::vec4 ahead =
        vp * glm::vec4(static_cast<float>(5.0 * std::sin(rad)), static_cast<float>(5.0 * std::cos(rad)), 0.0f, 1.0f);
    const glm::vec2 a = glm::vec2(out.anchor_clip) / out.anchor_clip.w * glm::vec2(target.width(), target.height());
    const glm::vec2 b = glm::vec2(ahead) / ahead.w * glm::vec2(target.width(), target.height());
    const glm::vec2 dir = b - a;
    out.screen_dir = glm::length(dir) > 1e-4f ? glm::normalize(dir) : glm::vec2(0.0f, 1.0f);
    // Its outline as drawn (screen pixels, y down): the arrow's convex hull (tip and the two back
    // corners) at the size of its dark outline; labels keep out of it, the metrics measure it.
    const glm::vec2 ndc = glm::vec2(out.anchor_clip) / out.anchor_clip.w;
    const glm::vec2 center((ndc.x * 0.5f + 0.5f) * static_cast<float>(target.width()),
                           (0.5f - ndc.y * 0.5f) * static_cast<float>(target.height()));
    const glm::vec2 side(out.screen_dir.y, -out.screen_dir.x);
    const float size = ctx.style.marker_size_px + 3.0f;
    for (const glm::vec2 corner : {glm::vec2(0.0f, 1.0f), glm::vec2(0.6f, -0.7f), glm::vec2(-0.6f, -0.7f)}) {
        const glm::vec2 up = (corner.x * side + corner.y * out.screen_dir) * size;  // y up
        out.outline.push_back(center + glm::vec2(up.x, -up.y));
    }
    return out;
}

void MarkerPass::draw(const FrameContext& ctx, const OnScreen& marker) {
    const RenderTarget& target = ctx.target;
    const MapStyle& style = ctx.style;
    const MarkerState& m = *ctx.frame.marker;
    ctx.stats.drawn_marker.outline = marker.outline;
    target.bindForDrawing(false);
    glDisable(GL_DEPTH_TEST);
    glDisable(GL_CULL_FACE);
    glUseProgram(m_program.id());
    glUniform4fv(m_program.uniform("u_anchor_clip"), 1, glm::value_ptr(marker.anchor_clip));
    glUniform2fv(m_program.uniform("u_screen_dir"), 1, glm::value_ptr(marker.screen_dir));
    glUniform2f(m_program.uniform("u_viewport"), static_cast<float>(target.width()),
                static_cast<float>(target.height()));
    // Outline first (slightly larger, dark), then the fill.
    glBindVertexArray(m_vao);
    const glm::vec4 dark(0.1f, 0.1f, 0.1f, 1.0f);
    glUniform1f(m_program.uniform("u_size_px"), style.marker_size_px + 3.0f);
    glUniform4fv(m_program.uniform("u_color"), 1, glm::value_ptr(dark));
    countedDrawArrays(GL_TRIANGLES, 0, 6);
    glUniform1f(m_program.uniform("u_size_px"), style.marker_size_px);
    const glm::vec4 color = m.stale ? style.marker_stale_color : style.marker_color;
    glUniform4fv(m_program.uniform("u_color"), 1, glm::value_ptr(color));
    countedDrawArrays(GL_TRIANGLES, 0, 6);
    glEnable(GL_DEPTH_TEST);
}

}  // namespace navmap::render::gl
