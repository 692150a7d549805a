// SPDX-License-Identifier: Apache-2.0
#include "dmabuf_import.h"

#include <EGL/egl.h>
#include <EGL/eglext.h>
#include <GLES3/gl3.h>
// after gl3.h, which defines what it uses
#include <GLES2/gl2ext.h>

#include <cstdio>
#include <cstring>

namespace navmap::test {

namespace {

template <typename F>
F proc(const char* name) {
    return reinterpret_cast<F>(eglGetProcAddress(name));
}

bool fail(std::string* error, const std::string& what) {
    char code[16];
    std::snprintf(code, sizeof code, " (0x%04x)", static_cast<unsigned>(eglGetError()));
    *error = what + code;
    return false;
}

}  // namespace

bool readThroughEgl(const DmabufLayout& b, render::Image* out, std::string* error) {
    const auto get_display = proc<PFNEGLGETPLATFORMDISPLAYEXTPROC>("eglGetPlatformDisplayEXT");
    const auto create_image = proc<PFNEGLCREATEIMAGEKHRPROC>("eglCreateImageKHR");
    const auto destroy_image = proc<PFNEGLDESTROYIMAGEKHRPROC>("eglDestroyImageKHR");
    const auto target_texture = proc<PFNGLEGLIMAGETARGETTEXTURE2DOESPROC>("glEGLImageTargetTexture2DOES");
    if (!get_display || !create_image || !destroy_image || !target_texture) return fail(error, "EGL entry points");
    EGLDisplay display = get_display(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
    if (display == EGL_NO_DISPLAY || !eglInitialize(display, nullptr, nullptr)) return fail(error, "eglInitialize");
    const char* ext = eglQueryString(display, EGL_EXTENSIONS);
    if (!ext || !std::strstr(ext, "EGL_EXT_image_dma_buf_import")) {
        *error = "no EGL_EXT_image_dma_buf_import";
        return false;
    }
    eglBindAPI(EGL_OPENGL_ES_API);
    const EGLint context_attribs[] = {EGL_CONTEXT_MAJOR_VERSION, 3, EGL_NONE};
    EGLContext context = eglCreateContext(display, EGL_NO_CONFIG_KHR, EGL_NO_CONTEXT, context_attribs);
    if (context == EGL_NO_CONTEXT || !eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, context))
        return fail(error, "eglCreateContext");
    const EGLint attribs[] = {EGL_WIDTH,
                              b.width,
                              EGL_HEIGHT,
                              b.height,
                              EGL_LINUX_DRM_FOURCC_EXT,
                              static_cast<EGLint>(b.fourcc),
                              EGL_DMA_BUF_PLANE0_FD_EXT,
                              b.fd,
                              EGL_DMA_BUF_PLANE0_OFFSET_EXT,
                              static_cast<EGLint>(b.offset),
                              EGL_DMA_BUF_PLANE0_PITCH_EXT,
                              static_cast<EGLint>(b.stride),
                              EGL_DMA_BUF_PLANE0_MODIFIER_LO_EXT,
                              static_cast<EGLint>(b.modifier & 0xffffffffULL),
                              EGL_DMA_BUF_PLANE0_MODIFIER_HI_EXT,
                              static_cast<EGLint>(b.modifier >> 32),
                              EGL_NONE};
    EGLImageKHR image = create_image(display, EGL_NO_CONTEXT, EGL_LINUX_DMA_BUF_EXT, nullptr, attribs);
    bool ok = image != EGL_NO_IMAGE_KHR;
    if (!ok) fail(error, "eglCreateImageKHR(EGL_LINUX_DMA_BUF_EXT)");
    GLuint texture = 0, fbo = 0;
    if (ok) {
        glGenTextures(1, &texture);
        glBindTexture(GL_TEXTURE_2D, texture);
        target_texture(GL_TEXTURE_2D, image);
        glGenFramebuffers(1, &fbo);
        glBindFramebuffer(GL_FRAMEBUFFER, fbo);
        glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, texture, 0);
        ok = glCheckFramebufferStatus(GL_FRAMEBUFFER) == GL_FRAMEBUFFER_COMPLETE;
        if (!ok) *error = "the imported texture is no complete framebuffer";
    }
    if (ok) {
        *out = render::Image(b.width, b.height);
        glPixelStorei(GL_PACK_ALIGNMENT, 1);
        glReadPixels(0, 0, b.width, b.height, GL_RGBA, GL_UNSIGNED_BYTE, out->rgba.data());
        ok = glGetError() == GL_NO_ERROR;
        if (!ok) *error = "glReadPixels of the imported buffer";
    }
    if (fbo) glDeleteFramebuffers(1, &fbo);
    if (texture) glDeleteTextures(1, &texture);
    if (image != EGL_NO_IMAGE_KHR) destroy_image(display, image);
    eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
    eglDestroyContext(display, context);
    return ok;
}

}  // namespace navmap::test
