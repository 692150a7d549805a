// SPDX-License-Identifier: Apache-2.0
#pragma once
// DmabufExporter: the GPU side of dma-buf frames (docs/frame-protocol.md "dma-buf frames",
// docs/gles-profile.md "dma-buf export"). Buffers are allocated with GBM on a DRM node (linear
// ABGR8888, so that any importer reads them: a compositor, another process's EGL, a CPU mapping),
// imported into the renderer's EGL display (EGL_EXT_image_dma_buf_import) and bound as textures
// of framebuffers (GL_OES_EGL_image). A frame is copied into a free one with a blit that also turns
// it top row first, the optional overlay is blended over it, and its end is marked by a native
// fence fd or, without EGL_ANDROID_native_fence_sync, by glFinish. Private to render/.

#include <EGL/egl.h>
#include <EGL/eglext.h>
#include <GLES3/gl3.h>

#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "navmap/render/renderer.h"
#include "shader_program.h"

struct gbm_device;
struct gbm_bo;

namespace navmap::render::gl {

class DmabufExporter {
public:
    /// A target's buffers: made on its first export, freed with it (or on a new context).
    class Pool {
    public:
        ~Pool();
        Pool() = default;
        Pool(const Pool&) = delete;
        Pool& operator=(const Pool&) = delete;

    private:
        friend class DmabufExporter;
        void release();  // every buffer and the overlay texture
        struct Buffer {
            gbm_bo* bo = nullptr;
            int fd = -1;
            std::uint32_t stride = 0, offset = 0;
            std::uint64_t modifier = 0;
            EGLImage image = nullptr;
            GLuint texture = 0, fbo = 0;
            std::uint64_t generation = 0;
        };
        EGLDisplay m_display = EGL_NO_DISPLAY;
        PFNEGLDESTROYIMAGEKHRPROC m_destroy_image = nullptr;
        int m_width = 0, m_height = 0;
        int m_next = 0;  // where the search for a free buffer starts: round robin
        std::array<Buffer, kDmabufBuffers> m_buffers{};
        std::uint64_t m_overlay_id = 0;  // what m_overlay_texture holds (0: nothing)
        GLuint m_overlay_texture = 0;
    };

    /// Runs the probe's allocation: on the display `display` of the current context, with
    /// `capability` from decideDmabuf(). Tries GBM on each node of `nodes` (findDrmNodes()) and
    /// keeps the first that allocates a linear ABGR8888 render buffer; otherwise turns
    /// `capability` into a refusal naming each node's error. Does nothing when `capability` is
    /// already a refusal.
    DmabufExporter(EGLDisplay display, const std::vector<std::string>& nodes, DmabufCapability& capability,
                   const std::string& gl_renderer, const std::string& platform);
    ~DmabufExporter();
    DmabufExporter(const DmabufExporter&) = delete;
    DmabufExporter& operator=(const DmabufExporter&) = delete;

    [[nodiscard]] bool ready() const { return m_gbm != nullptr; }

    /// Copies the colour of the bound read framebuffer (width x height, bottom row first, as GL
    /// has it) into a buffer of `pool` not set in `busy`, top row first, and blends `overlay`
    /// over it. Remakes the pool's buffers when the size changed. Throws RenderError when GBM or
    /// EGL refuse a buffer.
    std::optional<DmabufFrame> exportFrame(Pool& pool, int width, int height, std::uint32_t busy,
                                           const FrameOverlay* overlay);

private:
    void makeBuffer(Pool& pool, Pool::Buffer& b);
    void drawOverlay(Pool& pool, const FrameOverlay& overlay);
    int fenceFd();

    int m_drm_fd = -1;
    gbm_device* m_gbm = nullptr;
    EGLDisplay m_display = EGL_NO_DISPLAY;
    bool m_native_fences = false;
    std::uint64_t m_generation = 0;
    ShaderProgram m_overlay;  // made on the first overlay
    GLuint m_vao = 0;
};

}  // namespace navmap::render::gl
