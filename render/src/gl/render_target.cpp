#include "render_target.h"

#include <algorithm>
#include <string>

#include "navmap/render/renderer.h"

namespace navmap::render::gl {

namespace {

void checkComplete(const char* what) {
    const GLenum status = glCheckFramebufferStatus(GL_FRAMEBUFFER);
    if (status != GL_FRAMEBUFFER_COMPLETE) {
        throw RenderError(std::string("offscreen framebuffer (") + what + ") incomplete: status 0x" +
                          [&] { char b[16]; std::snprintf(b, sizeof b, "%04x", status); return std::string(b); }());
    }
}

}  // namespace

RenderTarget::RenderTarget(int width, int height, int samples) : m_width(width), m_height(height) {
    GLint max_samples = 0;
    glGetIntegerv(GL_MAX_SAMPLES, &max_samples);
    m_samples = samples > 1 ? std::min(samples, static_cast<int>(max_samples)) : 0;
    if (m_samples == 1) m_samples = 0;

    glGenFramebuffers(1, &m_resolve_fbo);
    glGenRenderbuffers(1, &m_resolve_color);
    glBindRenderbuffer(GL_RENDERBUFFER, m_resolve_color);
    glRenderbufferStorage(GL_RENDERBUFFER, GL_RGBA8, width, height);
    glBindFramebuffer(GL_FRAMEBUFFER, m_resolve_fbo);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, m_resolve_color);
    if (m_samples == 0) {
        glGenRenderbuffers(1, &m_resolve_depth);
        glBindRenderbuffer(GL_RENDERBUFFER, m_resolve_depth);
        glRenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH24_STENCIL8, width, height);
        glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_STENCIL_ATTACHMENT, GL_RENDERBUFFER, m_resolve_depth);
    }
    checkComplete("resolve");

    if (m_samples > 0) {
        glGenFramebuffers(1, &m_msaa_fbo);
        glGenRenderbuffers(1, &m_msaa_color);
        glGenRenderbuffers(1, &m_msaa_depth);
        glBindRenderbuffer(GL_RENDERBUFFER, m_msaa_color);
        glRenderbufferStorageMultisample(GL_RENDERBUFFER, m_samples, GL_RGBA8, width, height);
        glBindRenderbuffer(GL_RENDERBUFFER, m_msaa_depth);
        glRenderbufferStorageMultisample(GL_RENDERBUFFER, m_samples, GL_DEPTH24_STENCIL8, width, height);
        glBindFramebuffer(GL_FRAMEBUFFER, m_msaa_fbo);
        glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, m_msaa_color);
        glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_STENCIL_ATTACHMENT, GL_RENDERBUFFER, m_msaa_depth);
        checkComplete("multisampled");
    }
    glBindRenderbuffer(GL_RENDERBUFFER, 0);
}

RenderTarget::~RenderTarget() {
    const GLuint fbos[] = {m_msaa_fbo, m_resolve_fbo};
    const GLuint rbs[] = {m_msaa_color, m_msaa_depth, m_resolve_color, m_resolve_depth};
    glDeleteFramebuffers(2, fbos);
    glDeleteRenderbuffers(4, rbs);
}

void RenderTarget::bindForDrawing() const {
    glBindFramebuffer(GL_FRAMEBUFFER, m_samples > 0 ? m_msaa_fbo : m_resolve_fbo);
    glViewport(0, 0, m_width, m_height);
}

void RenderTarget::resolve() const {
    if (m_samples > 0) {
        glBindFramebuffer(GL_READ_FRAMEBUFFER, m_msaa_fbo);
        glBindFramebuffer(GL_DRAW_FRAMEBUFFER, m_resolve_fbo);
        glBlitFramebuffer(0, 0, m_width, m_height, 0, 0, m_width, m_height, GL_COLOR_BUFFER_BIT, GL_NEAREST);
    }
    glBindFramebuffer(GL_READ_FRAMEBUFFER, m_resolve_fbo);
}

}  // namespace navmap::render::gl
