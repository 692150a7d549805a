// SPDX-License-Identifier: Apache-2.0
#include "dmabuf_export.h"

#include <drm_fourcc.h>
#include <fcntl.h>
#include <gbm.h>
#include <unistd.h>

#include <GLES2/gl2ext.h>

#include <cerrno>
#include <cstring>

#include "gl_state_scope.h"

namespace navmap::render::gl {

namespace {

template <typename F>
F proc(const char* name) {
    return reinterpret_cast<F>(eglGetProcAddress(name));
}

constexpr std::uint32_t kFourcc = GBM_FORMAT_ABGR8888;  // = DRM_FORMAT_ABGR8888: R, G, B, A bytes
constexpr std::uint32_t kUse = GBM_BO_USE_RENDERING | GBM_BO_USE_LINEAR;

}  // namespace

DmabufExporter::Pool::~Pool() { release(); }

void DmabufExporter::Pool::release() {
    for (Buffer& b : m_buffers) {
        if (b.fbo) glDeleteFramebuffers(1, &b.fbo);
        if (b.texture) glDeleteTextures(1, &b.texture);
        if (b.image && m_destroy_image) m_destroy_image(m_display, b.image);
        if (b.fd >= 0) ::close(b.fd);
        if (b.bo) gbm_bo_destroy(b.bo);
    }
    if (m_overlay_texture) glDeleteTextures(1, &m_overlay_texture);
    m_buffers = {};
    m_overlay_texture = 0;
    m_overlay_id = 0;
    m_next = 0;
}

DmabufExporter::DmabufExporter(EGLDisplay display, const std::vector<std::string>& nodes, DmabufCapability& capability,
                               const std::string& gl_renderer, const std::string& platform)
    : m_display(display), m_native_fences(capability.native_fence_sync) {
    if (!capability.available) return;
    std::string why;
    for (const std::string& node : nodes) {
        const int fd = ::open(node.c_str(), O_RDWR | O_CLOEXEC);
        if (fd < 0) {
            why += (why.empty() ? "" : "; ") + node + ": " + std::strerror(errno);
            continue;
        }
        gbm_device* gbm = gbm_create_device(fd);
        gbm_bo* bo = gbm ? gbm_bo_create(gbm, 64, 64, kFourcc, kUse) : nullptr;
        if (bo) {
            gbm_bo_destroy(bo);
            m_drm_fd = fd;
            m_gbm = gbm;
            capability.drm_node = node;
            return;
        }
        // GBM says nothing but errno (a DRM ioctl's: EACCES for dumb buffers on a render node).
        const int err = errno;
        why += (why.empty() ? "" : "; ") + node + ": " +
               (gbm ? std::string("no buffer (") + std::strerror(err) + ")" : std::string("no GBM device"));
        if (gbm) gbm_device_destroy(gbm);
        ::close(fd);
    }
    refuseDmabuf(capability, gl_renderer, platform, why);
}

DmabufExporter::~DmabufExporter() {
    if (m_vao) glDeleteVertexArrays(1, &m_vao);
    if (m_gbm) gbm_device_destroy(m_gbm);
    if (m_drm_fd >= 0) ::close(m_drm_fd);
}

void DmabufExporter::makeBuffer(Pool& pool, Pool::Buffer& b) {
    b.bo = gbm_bo_create(m_gbm, static_cast<std::uint32_t>(pool.m_width), static_cast<std::uint32_t>(pool.m_height),
                         kFourcc, kUse);
    if (!b.bo) throw RenderError(std::string("dma-buf export: gbm_bo_create failed: ") + std::strerror(errno));
    b.fd = gbm_bo_get_fd(b.bo);
    if (b.fd < 0) throw RenderError("dma-buf export: gbm_bo_get_fd failed");
    b.stride = gbm_bo_get_stride(b.bo);
    b.offset = gbm_bo_get_offset(b.bo, 0);
    b.modifier = gbm_bo_get_modifier(b.bo);
    if (b.modifier == DRM_FORMAT_MOD_INVALID) b.modifier = DRM_FORMAT_MOD_LINEAR;  // asked for linear
    const EGLint attribs[] = {EGL_WIDTH,
                              pool.m_width,
                              EGL_HEIGHT,
                              pool.m_height,
                              EGL_LINUX_DRM_FOURCC_EXT,
                              static_cast<EGLint>(kFourcc),
                              EGL_DMA_BUF_PLANE0_FD_EXT,
                              b.fd,
                              EGL_DMA_BUF_PLANE0_OFFSET_EXT,
                              static_cast<EGLint>(b.offset),
                              EGL_DMA_BUF_PLANE0_PITCH_EXT,
                              static_cast<EGLint>(b.stride),
                              EGL_NONE};
    static const auto create_image = proc<PFNEGLCREATEIMAGEKHRPROC>("eglCreateImageKHR");
    static const auto target_texture = proc<PFNGLEGLIMAGETARGETTEXTURE2DOESPROC>("glEGLImageTargetTexture2DOES");
    pool.m_destroy_image = proc<PFNEGLDESTROYIMAGEKHRPROC>("eglDestroyImageKHR");
    b.image = create_image(m_display, EGL_NO_CONTEXT, EGL_LINUX_DMA_BUF_EXT, nullptr, attribs);
    if (!b.image) throw RenderError("dma-buf export: eglCreateImageKHR(EGL_LINUX_DMA_BUF_EXT) refused the buffer");
    glGenTextures(1, &b.texture);
    glBindTexture(GL_TEXTURE_2D, b.texture);
    target_texture(GL_TEXTURE_2D, b.image);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    glGenFramebuffers(1, &b.fbo);
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, b.fbo);
    glFramebufferTexture2D(GL_DRAW_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, b.texture, 0);
    if (glCheckFramebufferStatus(GL_DRAW_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
        throw RenderError("dma-buf export: the imported buffer is no complete framebuffer");
    b.generation = ++m_generation;
}

std::optional<DmabufFrame> DmabufExporter::exportFrame(Pool& pool, int width, int height, std::uint32_t busy,
                                                       const FrameOverlay* overlay) {
    if (!m_gbm) return std::nullopt;
    if (pool.m_width != width || pool.m_height != height) {
        busy = 0;  // the old buffers go (clients keep their own references): new ones, new fds
        pool.release();
        pool.m_display = m_display;
        pool.m_width = width;
        pool.m_height = height;
    }
    int index = -1;
    for (int i = 0; i < kDmabufBuffers && index < 0; ++i) {
        const int k = (pool.m_next + i) % kDmabufBuffers;
        if (!(busy & (1U << k))) index = k;
    }
    if (index < 0) return std::nullopt;
    pool.m_next = (index + 1) % kDmabufBuffers;
    Pool::Buffer& b = pool.m_buffers[static_cast<std::size_t>(index)];
    if (!b.bo) makeBuffer(pool, b);

    // The bound read framebuffer holds the frame bottom row first; the buffer gets it top row first.
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, b.fbo);
    glDisable(GL_SCISSOR_TEST);
    glBlitFramebuffer(0, 0, width, height, 0, height, width, 0, GL_COLOR_BUFFER_BIT, GL_NEAREST);
    if (overlay && overlay->image && !overlay->image->rgba.empty()) drawOverlay(pool, *overlay);

    DmabufFrame f;
    f.buffer = index;
    f.generation = b.generation;
    f.fd = b.fd;
    f.fourcc = kFourcc;
    f.modifier = b.modifier;
    f.stride = b.stride;
    f.offset = b.offset;
    f.width = width;
    f.height = height;
    f.fence_fd = fenceFd();
    return f;
}

void DmabufExporter::drawOverlay(Pool& pool, const FrameOverlay& overlay) {
    const Image& img = *overlay.image;
    if (!m_overlay.id()) {
        m_overlay = ShaderProgram::fromEmbedded("ortho_screen.vert", "export_overlay.frag");
        glGenVertexArrays(1, &m_vao);
    }
    if (pool.m_overlay_id != overlay.id || !pool.m_overlay_texture) {
        if (!pool.m_overlay_texture) glGenTextures(1, &pool.m_overlay_texture);
        glBindTexture(GL_TEXTURE_2D, pool.m_overlay_texture);
        glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
        glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, img.width, img.height, 0, GL_RGBA, GL_UNSIGNED_BYTE, img.rgba.data());
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
        pool.m_overlay_id = overlay.id;
    }
    // The buffer's row 0 is the frame's top row, so frame pixel (x, y) is at GL (x, y) here.
    const GlStateScope state;
    glViewport(0, 0, pool.m_width, pool.m_height);
    glEnable(GL_SCISSOR_TEST);
    glScissor(overlay.x, overlay.y, img.width, img.height);
    glDisable(GL_DEPTH_TEST);
    glDisable(GL_STENCIL_TEST);
    glDisable(GL_CULL_FACE);
    glEnable(GL_BLEND);
    glBlendFunc(GL_ONE, GL_ONE_MINUS_SRC_ALPHA);  // premultiplied
    glUseProgram(m_overlay.id());
    glActiveTexture(GL_TEXTURE0);
    glBindTexture(GL_TEXTURE_2D, pool.m_overlay_texture);
    glUniform1i(m_overlay.uniform("u_overlay"), 0);
    glUniform2i(m_overlay.uniform("u_origin"), overlay.x, overlay.y);
    glBindVertexArray(m_vao);
    glDrawArrays(GL_TRIANGLES, 0, 3);
    glDisable(GL_SCISSOR_TEST);
}

int DmabufExporter::fenceFd() {
    if (m_native_fences) {
        static const auto create_sync = proc<PFNEGLCREATESYNCKHRPROC>("eglCreateSyncKHR");
        static const auto destroy_sync = proc<PFNEGLDESTROYSYNCKHRPROC>("eglDestroySyncKHR");
        static const auto dup_fence = proc<PFNEGLDUPNATIVEFENCEFDANDROIDPROC>("eglDupNativeFenceFDANDROID");
        if (create_sync && destroy_sync && dup_fence) {
            EGLSyncKHR sync = create_sync(m_display, EGL_SYNC_NATIVE_FENCE_ANDROID, nullptr);
            if (sync != EGL_NO_SYNC_KHR) {
                glFlush();  // the fence's fd exists once the fence is submitted
                const int fd = dup_fence(m_display, sync);
                destroy_sync(m_display, sync);
                if (fd >= 0) return fd;
            }
        }
    }
    glFinish();
    return -1;
}

}  // namespace navmap::render::gl
