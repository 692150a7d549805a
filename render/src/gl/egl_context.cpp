// SPDX-License-Identifier: Apache-2.0
#include "egl_context.h"

#include <EGL/eglext.h>

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
            if (tryDisplay(d, name, why)) return true;
            failures.push_back(name + ": " + why);
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
    // Prefer ES 3.2, fall back to 3.1 and 3.0 (the minimum, docs/architecture.md "Rendering").
    for (int want_minor : {2, 1, 0}) {
        const EGLint ctx_attribs[] = {EGL_CONTEXT_MAJOR_VERSION, 3, EGL_CONTEXT_MINOR_VERSION, want_minor, EGL_NONE};
        EGLContext ctx =
            eglCreateContext(display, have_config ? config : EGL_NO_CONFIG_KHR, EGL_NO_CONTEXT, ctx_attribs);
        if (ctx == EGL_NO_CONTEXT) continue;
        if (!eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, ctx)) {
            why = "eglMakeCurrent (surfaceless) failed: " + eglErrorName(eglGetError());
            eglDestroyContext(display, ctx);
            return false;
        }
        m_display = display;
        m_context = ctx;
        m_platform = name;
        m_major = 3;
        m_minor = want_minor;
        return true;
    }
    why = "eglCreateContext failed for OpenGL ES 3.2, 3.1 and 3.0: " + eglErrorName(eglGetError());
    return false;
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
