// SPDX-License-Identifier: Apache-2.0
#include "egl_context.h"

#include <EGL/eglext.h>
#include <GLES3/gl3.h>

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

namespace navmap::render::gl {

namespace {

bool hasExtension(const char* list, const char* name) {
    if (!list) return false;
    const std::size_t n = std::strlen(name);
    for (const char* p = list; (p = std::strstr(p, name)) != nullptr; p += n) {
        if ((p == list || p[-1] == ' ') && (p[n] == ' ' || p[n] == '\0')) return true;
    }
    return false;
}

// EGL_EXT_create_context_robustness with the reset notification only: a reset is reported
// (LOSE_CONTEXT_ON_RESET) without asking for robust buffer access, which costs checks per draw.
std::vector<EGLint> contextAttributes(int minor, bool robust) {
    std::vector<EGLint> a = {EGL_CONTEXT_MAJOR_VERSION, 3, EGL_CONTEXT_MINOR_VERSION, minor};
    if (robust) {
        a.insert(a.end(), {EGL_CONTEXT_OPENGL_RESET_NOTIFICATION_STRATEGY_EXT, EGL_LOSE_CONTEXT_ON_RESET_EXT});
    }
    a.push_back(EGL_NONE);
    return a;
}

bool glHasExtension(const char* name) {
    GLint count = 0;
    glGetIntegerv(GL_NUM_EXTENSIONS, &count);
    for (GLint i = 0; i < count; ++i) {
        const auto* ext = reinterpret_cast<const char*>(glGetStringi(GL_EXTENSIONS, static_cast<GLuint>(i)));
        if (ext && std::strcmp(ext, name) == 0) return true;
    }
    return false;
}

std::string eglErrorName(EGLint e) {
    switch (e) {
        case EGL_SUCCESS: return "EGL_SUCCESS";
        case EGL_NOT_INITIALIZED: return "EGL_NOT_INITIALIZED";
        case EGL_BAD_ACCESS: return "EGL_BAD_ACCESS";
        case EGL_BAD_ALLOC: return "EGL_BAD_ALLOC";
        case EGL_BAD_ATTRIBUTE: return "EGL_BAD_ATTRIBUTE";
        case EGL_BAD_CONFIG: return "EGL_BAD_CONFIG";
        case EGL_BAD_CONTEXT: return "EGL_BAD_CONTEXT";
        case EGL_BAD_DISPLAY: return "EGL_BAD_DISPLAY";
        case EGL_BAD_MATCH: return "EGL_BAD_MATCH";
        case EGL_BAD_PARAMETER: return "EGL_BAD_PARAMETER";
        default: {
            char buf[32];
            std::snprintf(buf, sizeof buf, "EGL error 0x%04x", static_cast<unsigned>(e));
            return buf;
        }
    }
}

}  // namespace

bool isSoftwareRasterizer(const std::string& gl_renderer) {
    return gl_renderer.find("llvmpipe") != std::string::npos || gl_renderer.find("softpipe") != std::string::npos ||
           gl_renderer.find("swrast") != std::string::npos;
}

namespace {

Platform platformFromEnvironment(Platform requested) {
    if (requested != Platform::Auto) return requested;
    const char* env = std::getenv("NAVMAP_EGL_PLATFORM");
    if (!env || !*env) return Platform::Auto;
    if (auto p = parsePlatform(env)) return *p;
    throw RenderError(std::string("NAVMAP_EGL_PLATFORM=") + env + ": expected auto, surfaceless or device");
}

}  // namespace

EglContext::EglContext(Platform requested) {
    const Platform platform = platformFromEnvironment(requested);
    const char* client = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
    if (!client || !hasExtension(client, "EGL_EXT_platform_base")) {
        throw RenderError(
            "EGL: the EGL library offers no EGL_EXT_platform_base, so no headless platform can be "
            "chosen (is libegl-mesa0 or the NVIDIA EGL driver installed?)");
    }
    auto get_platform_display =
        reinterpret_cast<PFNEGLGETPLATFORMDISPLAYEXTPROC>(eglGetProcAddress("eglGetPlatformDisplayEXT"));
    auto query_devices = reinterpret_cast<PFNEGLQUERYDEVICESEXTPROC>(eglGetProcAddress("eglQueryDevicesEXT"));
    auto query_device_string =
        reinterpret_cast<PFNEGLQUERYDEVICESTRINGEXTPROC>(eglGetProcAddress("eglQueryDeviceStringEXT"));

    std::vector<std::string> failures;
    const bool has_surfaceless = hasExtension(client, "EGL_MESA_platform_surfaceless");
    const bool has_device = hasExtension(client, "EGL_EXT_platform_device") &&
                            hasExtension(client, "EGL_EXT_device_enumeration") && query_devices;

    auto try_devices = [&](bool hardware_only) {
        if (!has_device) {
            failures.push_back("device platform: EGL_EXT_platform_device/EGL_EXT_device_enumeration not offered");
            return false;
        }
        EGLint count = 0;
        query_devices(0, nullptr, &count);
        std::vector<EGLDeviceEXT> devices(static_cast<std::size_t>(count));
        if (count > 0) query_devices(count, devices.data(), &count);
        if (count == 0) failures.push_back("device platform: no EGL devices");
        for (EGLint i = 0; i < count; ++i) {
            const char* dev_ext = query_device_string ? query_device_string(devices[i], EGL_EXTENSIONS) : nullptr;
            const bool software = hasExtension(dev_ext, "EGL_MESA_device_software");
            if (hardware_only && software) continue;
            EGLDisplay d = get_platform_display(EGL_PLATFORM_DEVICE_EXT, devices[i], nullptr);
            std::string why;
            const std::string name = std::string("device#") + std::to_string(i) + (software ? " (software)" : "");
            if (!tryDisplay(d, name, why)) {
                failures.push_back(name + ": " + why);
                continue;
            }
            // A DRM device without a GPU driver (vgem, a display-only KMS device) draws with a
            // software rasterizer on that node, which cannot make the buffers it is given: not the
            // hardware device asked for. The surfaceless platform uses the same rasterizer properly.
            const char* gl_renderer = reinterpret_cast<const char*>(glGetString(GL_RENDERER));
            const std::string drawn_by = gl_renderer ? gl_renderer : "";
            if (!hardware_only || !isSoftwareRasterizer(drawn_by)) return true;
            failures.push_back(name + ": no GPU driver for it (" + drawn_by.substr(0, drawn_by.find(' ')) + ")");
            eglMakeCurrent(m_display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
            eglDestroyContext(m_display, m_context);
            m_display = EGL_NO_DISPLAY;
            m_context = EGL_NO_CONTEXT;
        }
        return false;
    };
    auto try_surfaceless = [&]() {
        if (!has_surfaceless) {
            failures.push_back("surfaceless platform: EGL_MESA_platform_surfaceless not offered");
            return false;
        }
        EGLDisplay d = get_platform_display(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
        std::string why;
        if (tryDisplay(d, "surfaceless", why)) return true;
        failures.push_back("surfaceless: " + why);
        return false;
    };

    bool ok = false;
    switch (platform) {
        case Platform::Surfaceless: ok = try_surfaceless(); break;
        case Platform::Device: ok = try_devices(false); break;
        case Platform::Auto: ok = try_devices(true) || try_surfaceless() || try_devices(false); break;
    }
    if (!ok) {
        std::string msg = std::string("EGL: no usable headless OpenGL ES 3 context (requested platform '") +
                          platformName(platform) + "'):";
        for (const auto& f : failures) msg += "\n  - " + f;
        throw RenderError(msg);
    }
}

std::string EglContext::displayExtensions() const {
    const char* ext = eglQueryString(m_display, EGL_EXTENSIONS);
    return ext != nullptr ? ext : "";
}

bool EglContext::tryDisplay(EGLDisplay display, const std::string& name, std::string& why) {
    if (display == EGL_NO_DISPLAY) {
        why = "eglGetPlatformDisplay failed: " + eglErrorName(eglGetError());
        return false;
    }
    EGLint major = 0, minor = 0;
    if (!eglInitialize(display, &major, &minor)) {
        why = "eglInitialize failed: " + eglErrorName(eglGetError());
        return false;
    }
    const char* ext = eglQueryString(display, EGL_EXTENSIONS);
    if (!hasExtension(ext, "EGL_KHR_surfaceless_context")) {
        why = "EGL_KHR_surfaceless_context not offered";
        return false;
    }
    if (!eglBindAPI(EGL_OPENGL_ES_API)) {
        why = "eglBindAPI(EGL_OPENGL_ES_API) failed: " + eglErrorName(eglGetError());
        return false;
    }
    const EGLint config_attribs[] = {EGL_RENDERABLE_TYPE,
                                     EGL_OPENGL_ES3_BIT,
                                     EGL_SURFACE_TYPE,
                                     0,
                                     EGL_RED_SIZE,
                                     8,
                                     EGL_GREEN_SIZE,
                                     8,
                                     EGL_BLUE_SIZE,
                                     8,
                                     EGL_NONE};
    EGLConfig config = nullptr;
    EGLint num_configs = 0;
    const bool have_config = eglChooseConfig(display, config_attribs, &config, 1, &num_configs) && num_configs > 0;
    if (!have_config && !hasExtension(ext, "EGL_KHR_no_config_context")) {
        why = "no EGL config with OpenGL ES 3 support";
        return false;
    }
    // Prefer ES 3.2, fall back to 3.1 and 3.0 (the minimum, docs/architecture.md "Rendering"); each
    // robust where EGL offers it (docs/gles-profile.md "Lost contexts"), else plain.
    const bool can_be_robust = hasExtension(ext, "EGL_EXT_create_context_robustness");
    for (int want_minor : {2, 1, 0}) {
        for (bool robust : {true, false}) {
            if (robust && !can_be_robust) continue;
            const std::vector<EGLint> ctx_attribs = contextAttributes(want_minor, robust);
            EGLContext ctx =
                eglCreateContext(display, have_config ? config : EGL_NO_CONFIG_KHR, EGL_NO_CONTEXT, ctx_attribs.data());
            if (ctx == EGL_NO_CONTEXT) continue;
            if (!eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, ctx)) {
                why = "eglMakeCurrent (surfaceless) failed: " + eglErrorName(eglGetError());
                eglDestroyContext(display, ctx);
                return false;
            }
            m_display = display;
            m_context = ctx;
            m_config = have_config ? config : nullptr;
            m_platform = name;
            m_major = 3;
            m_minor = want_minor;
            m_robust = robust;
            findResetQuery();
            return true;
        }
    }
    why = "eglCreateContext failed for OpenGL ES 3.2, 3.1 and 3.0: " + eglErrorName(eglGetError());
    return false;
}

void EglContext::findResetQuery() {
    using Query = unsigned (*)();
    m_reset_query = nullptr;
    const char* name = m_minor >= 2                          ? "glGetGraphicsResetStatus"
                       : glHasExtension("GL_EXT_robustness") ? "glGetGraphicsResetStatusEXT"
                       : glHasExtension("GL_KHR_robustness") ? "glGetGraphicsResetStatusKHR"
                                                             : nullptr;
    if (name) m_reset_query = reinterpret_cast<Query>(eglGetProcAddress(name));
}

unsigned EglContext::resetStatus() const {
    constexpr unsigned kUnknownContextReset = 0x8255;  // GL_UNKNOWN_CONTEXT_RESET (ES 3.2, EXT_robustness)
    if (m_lost_for_test) return kUnknownContextReset;
    return m_reset_query ? m_reset_query() : GL_NO_ERROR;
}

void EglContext::loseForTest() {
    eglMakeCurrent(m_display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
    if (m_context != EGL_NO_CONTEXT) eglDestroyContext(m_display, m_context);
    m_context = EGL_NO_CONTEXT;
    m_lost_for_test = true;
}

void EglContext::recreate() {
    eglMakeCurrent(m_display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
    if (m_context != EGL_NO_CONTEXT) eglDestroyContext(m_display, m_context);
    m_context = EGL_NO_CONTEXT;
    eglBindAPI(EGL_OPENGL_ES_API);
    const std::vector<EGLint> attribs = contextAttributes(m_minor, m_robust);
    EGLContext ctx =
        eglCreateContext(m_display, m_config ? m_config : EGL_NO_CONFIG_KHR, EGL_NO_CONTEXT, attribs.data());
    if (ctx == EGL_NO_CONTEXT) {
        throw RenderError("EGL: a lost context could not be made anew: eglCreateContext failed: " +
                          eglErrorName(eglGetError()));
    }
    if (!eglMakeCurrent(m_display, EGL_NO_SURFACE, EGL_NO_SURFACE, ctx)) {
        const std::string why = eglErrorName(eglGetError());
        eglDestroyContext(m_display, ctx);
        throw RenderError("EGL: a lost context could not be made anew: eglMakeCurrent failed: " + why);
    }
    m_context = ctx;
    m_lost_for_test = false;
    findResetQuery();
}

void EglContext::makeCurrent() const {
    if (eglGetCurrentContext() != m_context) eglMakeCurrent(m_display, EGL_NO_SURFACE, EGL_NO_SURFACE, m_context);
}

EglContext::~EglContext() {
    if (m_display == EGL_NO_DISPLAY) return;
    eglMakeCurrent(m_display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
    if (m_context != EGL_NO_CONTEXT && !eglDestroyContext(m_display, m_context)) {
        std::fprintf(stderr, "<4>navmap: eglDestroyContext failed: %s\n", eglErrorName(eglGetError()).c_str());
    }
    // No eglTerminate: an EGL display is one per platform and process, shared by every
    // renderer (one per display profile); terminating it would invalidate the others.
}

}  // namespace navmap::render::gl
