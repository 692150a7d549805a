#include "text_layer.h"

#include <algorithm>
#include <cstddef>

#include <glm/gtc/type_ptr.hpp>

namespace navmap::render::gl {

TextLayer::TextLayer(text::GlyphAtlas& atlas)
    : m_atlas(atlas), m_program(ShaderProgram::fromEmbedded("text_sdf.vert", "text_sdf.frag")) {
    glGenTextures(1, &m_texture);
    glGenVertexArrays(1, &m_vao);
    glGenBuffers(1, &m_vbo);
    glBindVertexArray(m_vao);
    glBindBuffer(GL_ARRAY_BUFFER, m_vbo);
    const auto stride = static_cast<GLsizei>(sizeof(Instance));
    for (GLuint i = 0; i < 8; ++i) {
        glEnableVertexAttribArray(i);
        glVertexAttribPointer(i, 4, GL_FLOAT, GL_FALSE, stride,
                              reinterpret_cast<const void*>(static_cast<std::size_t>(i) * sizeof(glm::vec4)));
        glVertexAttribDivisor(i, 1);
    }
    glBindVertexArray(0);
    glBindBuffer(GL_ARRAY_BUFFER, 0);
}

TextLayer::~TextLayer() {
    glDeleteTextures(1, &m_texture);
    glDeleteBuffers(1, &m_vbo);
    glDeleteVertexArrays(1, &m_vao);
}

void TextLayer::syncAtlas() {
    const int w = m_atlas.width();
    const int h = m_atlas.height();
    glActiveTexture(GL_TEXTURE0);
    glBindTexture(GL_TEXTURE_2D, m_texture);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    if (h != m_texture_height) {
        // New or grown atlas: reallocate and upload everything.
        glTexImage2D(GL_TEXTURE_2D, 0, GL_R8, w, h, 0, GL_RED, GL_UNSIGNED_BYTE, m_atlas.pixels().data());
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
        m_texture_height = h;
        ++m_stats.atlas_uploads;
    } else if (m_atlas.version() != m_uploaded_version && m_atlas.dirtyFirstRow() < m_atlas.dirtyEndRow()) {
        // Only the rows that changed (new glyphs land on one or two shelves per frame).
        const int first = std::clamp(m_atlas.dirtyFirstRow(), 0, h);
        const int end = std::clamp(m_atlas.dirtyEndRow(), first, h);
        glTexSubImage2D(GL_TEXTURE_2D, 0, 0, first, w, end - first, GL_RED, GL_UNSIGNED_BYTE,
                        m_atlas.pixels().data() + static_cast<std::size_t>(first) * w);
        ++m_stats.atlas_uploads;
    }
    m_uploaded_version = m_atlas.version();
    m_atlas.clearDirty();
}

void TextLayer::appendLabel(std::span<const text::GlyphQuad> quads, const text::TextStyle& style, glm::vec4 anchor,
                            glm::vec4 params, float max_px) {
    for (const text::GlyphQuad& q : quads) {
        Instance in;
        in.rect = glm::vec4(q.p0, q.p1);
        in.tex = glm::vec4(q.t0, q.t1);
        in.anchor = anchor;
        in.params = params;
        in.fill = q.layer == 1 ? style.icon : style.fill;
        in.outline = style.outline;
        in.halo = style.halo;
        in.widths = glm::vec4(style.outline_px, style.halo_px, max_px, 0.0f);
        m_instances.push_back(in);
    }
}

void TextLayer::drawScreen(std::span<const text::TextDraw> labels, glm::ivec2 viewport) {
    m_instances.clear();
    for (const text::TextDraw& l : labels) {
        if (l.alpha <= 0.0f || l.scale <= 0.0f || l.size_px <= 0.0f) continue;
        appendLabel(l.quads, l.style, glm::vec4(l.position, 0.0f, l.angle_rad),
                    glm::vec4(l.scale, l.size_px, std::min(l.alpha, 1.0f), 0.0f), 0.0f);
    }
    m_stats.labels = labels.size();
    draw(false, glm::mat4(1.0f), 1.0f, viewport);
}

void TextLayer::drawWorld(std::span<const text::WorldTextDraw> labels, const glm::mat4& view,
                          const glm::mat4& projection, glm::ivec2 viewport) {
    m_instances.clear();
    for (const text::WorldTextDraw& l : labels) {
        if (l.alpha <= 0.0f || l.size_px <= 0.0f) continue;
        appendLabel(l.quads, l.style, glm::vec4(l.position, l.angle_rad),
                    glm::vec4(l.world_em_m, l.size_px, std::min(l.alpha, 1.0f), l.min_px), l.max_px);
    }
    m_stats.labels = labels.size();
    draw(true, projection * view, projection[1][1], viewport);
}

void TextLayer::draw(bool world, const glm::mat4& view_projection, float focal_y, glm::ivec2 viewport) {
    m_stats.glyphs = m_instances.size();
    syncAtlas();
    if (m_instances.empty() || viewport.x <= 0 || viewport.y <= 0) return;

    glBindBuffer(GL_ARRAY_BUFFER, m_vbo);
    const auto bytes = static_cast<GLsizeiptr>(m_instances.size() * sizeof(Instance));
    if (m_instances.size() > m_vbo_capacity) {
        m_vbo_capacity = std::max(m_instances.size(), m_vbo_capacity * 2);
        glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(m_vbo_capacity * sizeof(Instance)), nullptr, GL_STREAM_DRAW);
    }
    glBufferSubData(GL_ARRAY_BUFFER, 0, bytes, m_instances.data());

    glUseProgram(m_program.id());
    glUniform2f(m_program.uniform("u_viewport"), static_cast<float>(viewport.x), static_cast<float>(viewport.y));
    glUniform2f(m_program.uniform("u_atlas_size"), static_cast<float>(m_atlas.width()),
                static_cast<float>(m_atlas.height()));
    glUniform1f(m_program.uniform("u_spread_em"),
                static_cast<float>(m_atlas.params().spread_px) / static_cast<float>(m_atlas.params().base_em_px));
    glUniform1i(m_program.uniform("u_world"), world ? 1 : 0);
    glUniformMatrix4fv(m_program.uniform("u_view_projection"), 1, GL_FALSE, glm::value_ptr(view_projection));
    glUniform1f(m_program.uniform("u_focal_y"), focal_y);
    glUniform1i(m_program.uniform("u_atlas"), 0);
    glActiveTexture(GL_TEXTURE0);
    glBindTexture(GL_TEXTURE_2D, m_texture);

    glDisable(GL_CULL_FACE);
    glEnable(GL_BLEND);
    glBlendFuncSeparate(GL_ONE, GL_ONE_MINUS_SRC_ALPHA, GL_ONE, GL_ONE_MINUS_SRC_ALPHA);
    glDepthMask(GL_FALSE);
    if (world) {
        // Depth-tested at the anchor's depth: hidden behind buildings and terrain.
        glEnable(GL_DEPTH_TEST);
        glDepthFunc(GL_LEQUAL);
    } else {
        glDisable(GL_DEPTH_TEST);
    }
    glBindVertexArray(m_vao);
    glDrawArraysInstanced(GL_TRIANGLE_STRIP, 0, 4, static_cast<GLsizei>(m_instances.size()));
    glBindVertexArray(0);
    glBindBuffer(GL_ARRAY_BUFFER, 0);
    glDisable(GL_BLEND);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    glDepthMask(GL_TRUE);
}

}  // namespace navmap::render::gl
