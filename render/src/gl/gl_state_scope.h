// SPDX-License-Identifier: Apache-2.0
#pragma once
// GlStateScope: the fixed-function state a pass between the map passes changes (depth function and
// mask, depth test, blending, face culling, stencil test), saved on construction and given back on
// destruction, with the blend, stencil-mask, texture-unit and vertex-array settings the map passes
// expect reset. The occlusion effects and the manoeuvre arrows run inside one. Private to render/.

#include <GLES3/gl3.h>

namespace navmap::render::gl {

class GlStateScope {
public:
    GlStateScope() {
        glGetIntegerv(GL_DEPTH_FUNC, &m_depth_func);
        glGetBooleanv(GL_DEPTH_WRITEMASK, &m_depth_mask);
        m_depth_test = glIsEnabled(GL_DEPTH_TEST);
        m_blend = glIsEnabled(GL_BLEND);
        m_cull = glIsEnabled(GL_CULL_FACE);
        m_stencil = glIsEnabled(GL_STENCIL_TEST);
    }
    ~GlStateScope() {
        glDepthFunc(static_cast<GLenum>(m_depth_func));
        glDepthMask(m_depth_mask);
        set(GL_DEPTH_TEST, m_depth_test);
        set(GL_BLEND, m_blend);
        set(GL_CULL_FACE, m_cull);
        set(GL_STENCIL_TEST, m_stencil);
        glStencilMask(0xFF);
        glBlendEquation(GL_FUNC_ADD);
        glBlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA);
        glActiveTexture(GL_TEXTURE0);
        glBindVertexArray(0);
    }
    GlStateScope(const GlStateScope&) = delete;
    GlStateScope& operator=(const GlStateScope&) = delete;

private:
    static void set(GLenum cap, GLboolean on) { on ? glEnable(cap) : glDisable(cap); }

    GLint m_depth_func = GL_LESS;
    GLboolean m_depth_mask = GL_TRUE;
    GLboolean m_depth_test = GL_TRUE, m_blend = GL_FALSE, m_cull = GL_FALSE, m_stencil = GL_FALSE;
};

}  // namespace navmap::render::gl
