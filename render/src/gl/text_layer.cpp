// SPDX-License-Identifier: Apache-2.0
#include "text_layer.h"

#include "gl/gl_work.h"
#include "render_target.h"

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
    for (GLuint i = 0; i < 10; ++i) {
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
        countedTexImage2D(GL_TEXTURE_2D, 0, GL_R8, w, h, 0, GL_RED, GL_UNSIGNED_BYTE, m_atlas.pixels().data());
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
        countedTexSubImage2D(GL_TEXTURE_2D, 0, 0, first, w, end - first, GL_RED, GL_UNSIGNED_BYTE,
                             m_atlas.pixels().data() + static_cast<std::size_t>(first) * w);
        ++m_stats.atlas_uploads;
    }
    m_uploaded_version = m_atlas.version();
    m_atlas.clearDirty();
}

void TextLayer::appendLabel(std::span<const text::GlyphQuad> quads, const text::TextStyle& style, glm::vec4 anchor,
                            glm::vec4 params, glm::vec3 right, glm::vec3 up) {
    for (const text::GlyphQuad& q : quads) {
        Instance in;
        in.rect = glm::vec4(q.p0, q.p1);
        in.tex = glm::vec4(q.t0, q.t1);
        in.anchor = anchor;
        in.params = params;
        in.fill = q.layer == 1 ? style.icon : style.fill;
        in.outline = style.outline;
        in.halo = style.halo;
        in.widths = glm::vec4(style.outline_px, style.halo_px, 0.0f, 0.0f);
        in.right = glm::vec4(right, 0.0f);
        in.up = glm::vec4(up, 0.0f);
        m_instances.push_back(in);
    }
}

void TextLayer::drawScreen(std::span<const text::TextDraw> labels, glm::ivec2 viewport) {
    m_instances.clear();
    for (const text::TextDraw& l : labels) {
        if (l.alpha <= 0.0f || l.scale <= 0.0f || l.size_px <= 0.0f) continue;
        appendLabel(l.quads, l.style, glm::vec4(l.position, 0.0f, l.angle_rad),
                    glm::vec4(l.scale, l.size_px, std::min(l.alpha, 1.0f), 0.0f));
    }
    m_stats.labels = labels.size();
    draw(false, glm::mat4(1.0f), 1.0f, viewport);
}

void TextLayer::drawWorld(std::span<const text::WorldTextDraw> labels, const glm::mat4& view,
                          const glm::mat4& projection, glm::ivec2 viewport) {
    m_instances.clear();
    for (const text::WorldTextDraw& l : labels) {
        if (l.alpha <= 0.0f || l.size_px <= 0.0f || !(l.em_m > 0.0f)) continue;
        appendLabel(l.quads, l.style, glm::vec4(l.position, 0.0f),
                    glm::vec4(l.em_m, l.size_px, std::min(l.alpha, 1.0f), 0.0f), l.right, l.up);
    }
    m_stats.labels = labels.size();
    draw(true, projection * view, projection[1][1], viewport);
}

void TextLayer::draw(bool world, const glm::mat4& view_projection, float focal_y, glm::ivec2 viewport) {
    m_stats.glyphs = m_instances.size();
    syncAtlas();
    if (m_instances.empty() || viewport.x <= 0 || viewport.y <= 0) return;
    glEnable(GL_BLEND);
    glBlendFuncSeparate(GL_ONE, GL_ONE_MINUS_SRC_ALPHA, GL_ONE, GL_ONE_MINUS_SRC_ALPHA);
    if (world) {
        // Depth-tested where the text lies in the scene: hidden behind buildings and terrain.
        glEnable(GL_DEPTH_TEST);
        glDepthFunc(GL_LEQUAL);
    } else {
        glDisable(GL_DEPTH_TEST);
    }
    drawInstances(m_program, world, view_projection, focal_y, viewport);
    glDisable(GL_BLEND);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    glDepthMask(GL_TRUE);
}

void TextLayer::drawInstances(ShaderProgram& program, bool world, const glm::mat4& view_projection, float focal_y,
                              glm::ivec2 viewport) {
    glBindBuffer(GL_ARRAY_BUFFER, m_vbo);
    const auto bytes = static_cast<GLsizeiptr>(m_instances.size() * sizeof(Instance));
    if (m_instances.size() > m_vbo_capacity) {
        m_vbo_capacity = std::max(m_instances.size(), m_vbo_capacity * 2);
        countedBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(m_vbo_capacity * sizeof(Instance)), nullptr,
                          GL_STREAM_DRAW);
    }
    countedBufferSubData(GL_ARRAY_BUFFER, 0, bytes, m_instances.data());

    glUseProgram(program.id());
    glUniform2f(program.uniform("u_viewport"), static_cast<float>(viewport.x), static_cast<float>(viewport.y));
    glUniform2f(program.uniform("u_atlas_size"), static_cast<float>(m_atlas.width()),
                static_cast<float>(m_atlas.height()));
    glUniform1f(program.uniform("u_spread_em"),
                static_cast<float>(m_atlas.params().spread_px) / static_cast<float>(m_atlas.params().base_em_px));
    glUniform1i(program.uniform("u_world"), world ? 1 : 0);
    glUniformMatrix4fv(program.uniform("u_view_projection"), 1, GL_FALSE, glm::value_ptr(view_projection));
    glUniform1f(program.uniform("u_focal_y"), focal_y);
    glUniform1i(program.uniform("u_atlas"), 0);
    glActiveTexture(GL_TEXTURE0);
    glBindTexture(GL_TEXTURE_2D, m_texture);

    glDisable(GL_CULL_FACE);
    glDepthMask(GL_FALSE);
    glBindVertexArray(m_vao);
    countedDrawArraysInstanced(GL_TRIANGLE_STRIP, 0, 4, static_cast<GLsizei>(m_instances.size()));
    glBindVertexArray(0);
    glBindBuffer(GL_ARRAY_BUFFER, 0);
}

std::pair<std::vector<std::uint64_t>, std::vector<std::uint64_t>> TextLayer::countIdPixels(
    std::span<const text::WorldTextDraw> labels, const glm::mat4& view, const glm::mat4& projection,
    glm::ivec2 viewport, GLuint depth_stencil_rb, int samples) {
    std::pair<std::vector<std::uint64_t>, std::vector<std::uint64_t>> counts;
    counts.first.assign(labels.size() + 1, 0);
    counts.second.assign(labels.size() + 1, 0);
    if (labels.empty() || viewport.x <= 0 || viewport.y <= 0 || labels.size() >= (1U << 24)) return counts;
    if (m_id_program.id() == 0) {
        m_id_program = ShaderProgram::fromEmbedded("text_sdf.vert", "text_sdf.frag", "#define NAVMAP_TEXT_IDS 1\n");
    }
    m_instances.clear();
    for (std::size_t i = 0; i < labels.size(); ++i) {
        const text::WorldTextDraw& l = labels[i];
        if (l.size_px <= 0.0f || !(l.em_m > 0.0f)) continue;
        const auto id = static_cast<std::uint32_t>(i + 1);
        text::TextStyle style = l.style;
        style.fill = style.outline =
            glm::vec4(static_cast<float>(id & 0xFFU) / 255.0f, static_cast<float>((id >> 8U) & 0xFFU) / 255.0f,
                      static_cast<float>((id >> 16U) & 0xFFU) / 255.0f, 1.0f);
        style.icon = style.fill;
        appendLabel(l.quads, style, glm::vec4(l.position, 0.0f), glm::vec4(l.em_m, l.size_px, 1.0f, 0.0f), l.right,
                    l.up);
    }
    syncAtlas();
    const auto pixel_count = static_cast<std::size_t>(viewport.x) * static_cast<std::size_t>(viewport.y);
    GLuint fbo = 0, resolve_fbo = 0;
    const GLuint color = makeRenderbuffer(GL_RGBA8, samples, viewport.x, viewport.y);
    const GLuint resolved = samples > 0 ? makeRenderbuffer(GL_RGBA8, 0, viewport.x, viewport.y) : 0;
    glGenFramebuffers(1, &fbo);
    glBindFramebuffer(GL_FRAMEBUFFER, fbo);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, color);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_STENCIL_ATTACHMENT, GL_RENDERBUFFER, depth_stencil_rb);
    checkFramebufferComplete("label occlusion measurement");
    if (resolved) {
        glGenFramebuffers(1, &resolve_fbo);
        glBindFramebuffer(GL_FRAMEBUFFER, resolve_fbo);
        glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, resolved);
        checkFramebufferComplete("label occlusion measurement (resolve)");
    }
    std::vector<std::uint8_t> rgba(pixel_count * 4);
    for (const bool depth_test : {false, true}) {
        glBindFramebuffer(GL_FRAMEBUFFER, fbo);
        glViewport(0, 0, viewport.x, viewport.y);
        const GLenum draw_buffer = GL_COLOR_ATTACHMENT0;
        glDrawBuffers(1, &draw_buffer);
        const float zero[4] = {0.0f, 0.0f, 0.0f, 0.0f};
        glClearBufferfv(GL_COLOR, 0, zero);
        glDisable(GL_BLEND);
        if (depth_test) {
            glEnable(GL_DEPTH_TEST);
            glDepthFunc(GL_LEQUAL);  // as drawWorld
        } else {
            glDisable(GL_DEPTH_TEST);
        }
        drawInstances(m_id_program, true, projection * view, projection[1][1], viewport);
        if (resolved) {
            glBindFramebuffer(GL_READ_FRAMEBUFFER, fbo);
            glBindFramebuffer(GL_DRAW_FRAMEBUFFER, resolve_fbo);
            glBlitFramebuffer(0, 0, viewport.x, viewport.y, 0, 0, viewport.x, viewport.y, GL_COLOR_BUFFER_BIT,
                              GL_NEAREST);
            glBindFramebuffer(GL_READ_FRAMEBUFFER, resolve_fbo);
        } else {
            glBindFramebuffer(GL_READ_FRAMEBUFFER, fbo);
        }
        glPixelStorei(GL_PACK_ALIGNMENT, 1);
        glReadPixels(0, 0, viewport.x, viewport.y, GL_RGBA, GL_UNSIGNED_BYTE, rgba.data());
        auto& out = depth_test ? counts.second : counts.first;
        for (std::size_t i = 0; i < pixel_count; ++i) {
            const std::uint32_t id = rgba[4 * i] | (static_cast<std::uint32_t>(rgba[4 * i + 1]) << 8U) |
                                     (static_cast<std::uint32_t>(rgba[4 * i + 2]) << 16U);
            if (id < out.size()) ++out[id];
        }
    }
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    glDeleteFramebuffers(1, &fbo);
    if (resolve_fbo) glDeleteFramebuffers(1, &resolve_fbo);
    glDeleteRenderbuffers(1, &color);
    if (resolved) glDeleteRenderbuffers(1, &resolved);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    glDepthMask(GL_TRUE);
    return counts;
}

}  // namespace navmap::render::gl
