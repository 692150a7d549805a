// SPDX-License-Identifier: Apache-2.0
#pragma once
// Headless EGL display + OpenGL ES 3 context without any surface. Private to render/.

#include <EGL/egl.h>

#include <string>

#include "navmap/render/renderer.h"

namespace navmap::render::gl {

/// Owns an EGL display and a GLES 3.x context made current (surfaceless) on the creating thread.
class EglContext {
public:
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

private:
    bool tryDisplay(EGLDisplay display, const std::string& name, std::string& why);

    EGLDisplay m_display = EGL_NO_DISPLAY;
    EGLContext m_context = EGL_NO_CONTEXT;
    std::string m_platform;
    int m_major = 0;
    int m_minor = 0;
};

}  // namespace navmap::render::gl
