// SPDX-License-Identifier: Apache-2.0
#include "render_target.h"

#include <algorithm>
#include <cstdio>
#include <string>

#include "gl/gl_work.h"
#include "navmap/render/renderer.h"

namespace navmap::render::gl {

GLuint makeRenderbuffer(GLenum format, int samples, int w, int h) {
    GLuint rb = 0;
    glGenRenderbuffers(1, &rb);
    glBindRenderbuffer(GL_RENDERBUFFER, rb);
    if (samples > 0)
        glRenderbufferStorageMultisample(GL_RENDERBUFFER, samples, format, w, h);
    else
        glRenderbufferStorage(GL_RENDERBUFFER, format, w, h);
    glBindRenderbuffer(GL_RENDERBUFFER, 0);
    return rb;
}

void checkFramebufferComplete(const char* what) {
    const GLenum status = glCheckFramebufferStatus(GL_FRAMEBUFFER);
    if (status != GL_FRAMEBUFFER_COMPLETE) {
        char code[16];
        std::snprintf(code, sizeof code, "0x%04x", status);
        throw RenderError(std::string("offscreen framebuffer (") + what + ") incomplete: status " + code);
    }
}

int RenderTarget::effectiveSamples(int samples) {
    if (samples <= 1) return 0;
    GLint max_samples = 0;
    glGetIntegerv(GL_MAX_SAMPLES, &max_samples);
    const int s = std::min(samples, static_cast<int>(max_samples));
    return s > 1 ? s : 0;
}

RenderTarget::RenderTarget(int width, int height, int samples, GLuint shared_depth_stencil)
    : m_width(width), m_height(height), m_samples(effectiveSamples(samples)) {
    // Mask texture for the outline pass: drawn into directly without MSAA, resolved into with it.
    glGenTextures(1, &m_mask_texture);
    glBindTexture(GL_TEXTURE_2D, m_mask_texture);
    glTexStorage2D(GL_TEXTURE_2D, 1, GL_R8, width, height);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);  // read with texelFetch
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    glBindTexture(GL_TEXTURE_2D, 0);

    // Drawing framebuffer: colour, road mask, depth + stencil.
    m_color_rb = makeRenderbuffer(GL_RGBA8, m_samples, width, height);
    // The depth/stencil buffer is scratch within one frame (nothing reads a target's depth after
    // its render), so the renderer's targets, which render one after another, share one of the
    // largest target's size. A larger attachment is fine in ES 3.0: the framebuffer's area is the
    // intersection of its attachments, so clears, draws and blits stay within the target.
    m_owns_depth = shared_depth_stencil == 0;
    m_depth_rb = m_owns_depth ? makeRenderbuffer(GL_DEPTH24_STENCIL8, m_samples, width, height) : shared_depth_stencil;
    glGenFramebuffers(1, &m_draw_fbo);
    glBindFramebuffer(GL_FRAMEBUFFER, m_draw_fbo);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, m_color_rb);
    if (m_samples > 0) {
        m_mask_rb = makeRenderbuffer(GL_R8, m_samples, width, height);
        glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT1, GL_RENDERBUFFER, m_mask_rb);
    } else {
        glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT1, GL_TEXTURE_2D, m_mask_texture, 0);
    }
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_STENCIL_ATTACHMENT, GL_RENDERBUFFER, m_depth_rb);
    checkFramebufferComplete(m_samples > 0 ? "multisampled" : "drawing");

    // Composite framebuffer: the same colour and depth/stencil without the mask.
    glGenFramebuffers(1, &m_composite_fbo);
    glBindFramebuffer(GL_FRAMEBUFFER, m_composite_fbo);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, m_color_rb);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_STENCIL_ATTACHMENT, GL_RENDERBUFFER, m_depth_rb);
    checkFramebufferComplete("composite");

    if (m_samples > 0) {
        // Resolved colour for readback, resolved mask for the outline pass.
        m_resolve_color = makeRenderbuffer(GL_RGBA8, 0, width, height);
        glGenFramebuffers(1, &m_resolve_fbo);
        glBindFramebuffer(GL_FRAMEBUFFER, m_resolve_fbo);
        glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, m_resolve_color);
        checkFramebufferComplete("resolve");
        glGenFramebuffers(1, &m_mask_fbo);
        glBindFramebuffer(GL_FRAMEBUFFER, m_mask_fbo);
        glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, m_mask_texture, 0);
        checkFramebufferComplete("mask");
    }
    glBindRenderbuffer(GL_RENDERBUFFER, 0);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
}

RenderTarget::~RenderTarget() {
    const GLuint fbos[] = {m_draw_fbo, m_resolve_fbo, m_mask_fbo, m_composite_fbo};
    const GLuint rbs[] = {m_color_rb, m_mask_rb, m_resolve_color, m_owns_depth ? m_depth_rb : 0};
    glDeleteFramebuffers(4, fbos);
    glDeleteRenderbuffers(4, rbs);
    glDeleteTextures(1, &m_mask_texture);
    glDeleteFramebuffers(1, &m_packed_fbo);
    glDeleteTextures(1, &m_packed_texture);
}

bool RenderTarget::readsMaskBytes() const {
    if (m_reads_mask_bytes < 0) {
        GLint format = 0, type = 0;
        if (m_samples == 0) {  // with MSAA the mask is per sample; the filter reads the resolved one
            glBindFramebuffer(GL_READ_FRAMEBUFFER, m_draw_fbo);
            glReadBuffer(GL_COLOR_ATTACHMENT1);
            glGetIntegerv(GL_IMPLEMENTATION_COLOR_READ_FORMAT, &format);
            glGetIntegerv(GL_IMPLEMENTATION_COLOR_READ_TYPE, &type);
            glReadBuffer(GL_COLOR_ATTACHMENT0);
        }
        m_reads_mask_bytes = format == GL_RED && type == GL_UNSIGNED_BYTE ? 1 : 0;
    }
    return m_reads_mask_bytes == 1;
}

void RenderTarget::readMask(std::vector<std::uint8_t>& bytes) const {
    bytes.resize(static_cast<std::size_t>(m_width) * static_cast<std::size_t>(m_height));
    glBindFramebuffer(GL_READ_FRAMEBUFFER, m_draw_fbo);
    glReadBuffer(GL_COLOR_ATTACHMENT1);
    glPixelStorei(GL_PACK_ALIGNMENT, 1);  // as every read here sets it (readback.cpp)
    glReadPixels(0, 0, m_width, m_height, GL_RED, GL_UNSIGNED_BYTE, bytes.data());
    glReadBuffer(GL_COLOR_ATTACHMENT0);
}

GLuint RenderTarget::uploadPackedMask(const std::uint16_t* texels) const {
    makePackedMask();
    glBindTexture(GL_TEXTURE_2D, m_packed_texture);
    GLint alignment = 4;
    glGetIntegerv(GL_UNPACK_ALIGNMENT, &alignment);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 2);
    countedTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, packedMaskWidth(), m_height, GL_RED_INTEGER, GL_UNSIGNED_SHORT,
                         texels);
    glPixelStorei(GL_UNPACK_ALIGNMENT, alignment);
    glBindTexture(GL_TEXTURE_2D, 0);
    return m_packed_texture;
}

void RenderTarget::makePackedMask() const {
    if (m_packed_texture) return;
    glGenTextures(1, &m_packed_texture);
    glBindTexture(GL_TEXTURE_2D, m_packed_texture);
    glTexStorage2D(GL_TEXTURE_2D, 1, GL_R16UI, packedMaskWidth(), m_height);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);  // integer: read with texelFetch
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    glBindTexture(GL_TEXTURE_2D, 0);
}

GLuint RenderTarget::bindPackedMask() const {
    makePackedMask();
    if (!m_packed_fbo) {
        glGenFramebuffers(1, &m_packed_fbo);
        glBindFramebuffer(GL_FRAMEBUFFER, m_packed_fbo);
        glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, m_packed_texture, 0);
        checkFramebufferComplete("packed mask");
    }
    glBindFramebuffer(GL_FRAMEBUFFER, m_packed_fbo);
    const GLenum color = GL_COLOR_ATTACHMENT0;
    glDrawBuffers(1, &color);
    glViewport(0, 0, packedMaskWidth(), m_height);
    return m_packed_texture;
}

void RenderTarget::attachDepthStencil(GLuint shared_depth_stencil) {
    if (m_owns_depth) glDeleteRenderbuffers(1, &m_depth_rb);
    m_owns_depth = false;
    m_depth_rb = shared_depth_stencil;
    glBindFramebuffer(GL_FRAMEBUFFER, m_draw_fbo);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_STENCIL_ATTACHMENT, GL_RENDERBUFFER, m_depth_rb);
    checkFramebufferComplete(m_samples > 0 ? "multisampled" : "drawing");
    glBindFramebuffer(GL_FRAMEBUFFER, m_composite_fbo);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_STENCIL_ATTACHMENT, GL_RENDERBUFFER, m_depth_rb);
    checkFramebufferComplete("composite");
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
}

void RenderTarget::bindForDrawing(bool with_mask) const {
    if (with_mask) {
        glBindFramebuffer(GL_FRAMEBUFFER, m_draw_fbo);
        const GLenum both[] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1};
        glDrawBuffers(2, both);
    } else {
        // Without the mask attached, so any pass may sample maskTexture() (no feedback loop).
        glBindFramebuffer(GL_FRAMEBUFFER, m_composite_fbo);
        const GLenum color = GL_COLOR_ATTACHMENT0;
        glDrawBuffers(1, &color);
    }
    glViewport(0, 0, m_width, m_height);
}

void RenderTarget::clear(float r, float g, float b) const {
    glBindFramebuffer(GL_FRAMEBUFFER, m_draw_fbo);
    const GLenum both[] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1};
    glDrawBuffers(2, both);
    const GLfloat color[] = {r, g, b, 1.0f};
    const GLfloat zero[] = {0.0f, 0.0f, 0.0f, 0.0f};
    glClearBufferfv(GL_COLOR, 0, color);
    glClearBufferfv(GL_COLOR, 1, zero);
    glStencilMask(0xFF);  // every bit: the passes' stencil marks start at 0 in each frame
    glClearBufferfi(GL_DEPTH_STENCIL, 0, 1.0f, 0);
}

void RenderTarget::resolveMask() const {
    if (m_samples > 0) {
        glBindFramebuffer(GL_READ_FRAMEBUFFER, m_draw_fbo);
        glReadBuffer(GL_COLOR_ATTACHMENT1);
        glBindFramebuffer(GL_DRAW_FRAMEBUFFER, m_mask_fbo);
        glBlitFramebuffer(0, 0, m_width, m_height, 0, 0, m_width, m_height, GL_COLOR_BUFFER_BIT, GL_NEAREST);
        glReadBuffer(GL_COLOR_ATTACHMENT0);
    }
    bindForDrawing(false);
}

void RenderTarget::resolve() const {
    if (m_samples == 0) {  // nothing to resolve: read the drawing framebuffer's colour
        glBindFramebuffer(GL_READ_FRAMEBUFFER, m_draw_fbo);
        glReadBuffer(GL_COLOR_ATTACHMENT0);
        return;
    }
    glBindFramebuffer(GL_READ_FRAMEBUFFER, m_draw_fbo);
    glReadBuffer(GL_COLOR_ATTACHMENT0);
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, m_resolve_fbo);
    glBlitFramebuffer(0, 0, m_width, m_height, 0, 0, m_width, m_height, GL_COLOR_BUFFER_BIT, GL_NEAREST);
    glBindFramebuffer(GL_READ_FRAMEBUFFER, m_resolve_fbo);
}

}  // namespace navmap::render::gl
