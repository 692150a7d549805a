// SPDX-License-Identifier: Apache-2.0
#pragma once
// Headless EGL display + OpenGL ES 3 context without any surface. Private to render/.

#include <EGL/egl.h>

#include <string>

#include "navmap/render/renderer.h"

namespace navmap::render::gl {

/// Whether GL_RENDERER `gl_renderer` is a software rasterizer (llvmpipe, softpipe, swrast).
bool isSoftwareRasterizer(const std::string& gl_renderer);

/// Owns an EGL display and a GLES 3.x context made current (surfaceless) on the creating thread.
class EglContext {
public:
    /// Platform::Auto takes a hardware EGL device (one whose context is no software rasterizer),
    /// else the surfaceless platform, else any device.
    /// Throws RenderError naming every platform tried and why it failed.
    explicit EglContext(Platform requested);
    ~EglContext();
    EglContext(const EglContext&) = delete;
    EglContext& operator=(const EglContext&) = delete;

    /// Makes this context current on the calling thread (several renderers, e.g. one per
    /// display profile, share a thread). Cheap when it already is.
    void makeCurrent() const;

    [[nodiscard]] const std::string& platformUsed() const { return m_platform; }
    [[nodiscard]] int glesMajor() const { return m_major; }
    [[nodiscard]] int glesMinor() const { return m_minor; }
    /// Made with EGL_EXT_create_context_robustness and LOSE_CONTEXT_ON_RESET.
    [[nodiscard]] bool robust() const { return m_robust; }
    /// A robust context whose GL offers the reset status query: resets are noticed.
    [[nodiscard]] bool detectsResets() const { return m_robust && m_reset_query != nullptr; }
    /// The display's EGL extensions (eglQueryString), for the dma-buf probe.
    [[nodiscard]] std::string displayExtensions() const;
    /// The EGL display (the dma-buf exporter imports its buffers into it).
    [[nodiscard]] EGLDisplay display() const { return m_display; }

    /// Whether the context was lost or reset: glGetGraphicsResetStatus (ES 3.2 core,
    /// GL_EXT_robustness or GL_KHR_robustness before; GL_NO_ERROR where neither is offered), or
    /// GL_UNKNOWN_CONTEXT_RESET after loseForTest(). Call with the context current.
    [[nodiscard]] unsigned resetStatus() const;
    /// Destroys the context and makes a new one on the same display, config and attributes,
    /// current on the calling thread. Throws RenderError when EGL refuses.
    void recreate();
    /// Test hook: destroys the context as a GPU reset would lose it; resetStatus() reports it
    /// until recreate().
    void loseForTest();

private:
    bool tryDisplay(EGLDisplay display, const std::string& name, std::string& why);
    /// The reset status query of the current context (null where it has none).
    void findResetQuery();

    EGLDisplay m_display = EGL_NO_DISPLAY;
    EGLContext m_context = EGL_NO_CONTEXT;
    EGLConfig m_config = nullptr;  // null: EGL_NO_CONFIG_KHR
    std::string m_platform;
    int m_major = 0;
    int m_minor = 0;
    bool m_robust = false;
    bool m_lost_for_test = false;
    unsigned (*m_reset_query)() = nullptr;  // glGetGraphicsResetStatus[EXT|KHR]
};

}  // namespace navmap::render::gl
