// SPDX-License-Identifier: Apache-2.0
#pragma once
// Whether the renderer's EGL display could hand its frames out as dma-bufs (docs/gles-profile.md
// "dma-buf export"), and why not. Only the probe exists: navmapd does not render into exported
// buffers yet, and serves shared-memory frames whatever the probe says.

#include <string>
#include <vector>

namespace navmap::render {

/// What the probe found. `available` needs every EGL extension of the export path and a DRM
/// render node; `reason` names what is missing when it is not.
struct DmabufCapability {
    bool available = false;
    /// EGL_ANDROID_native_fence_sync: a frame's end could travel as a sync fence fd; without it
    /// the exporter would glFinish() before handing a buffer out.
    bool native_fence_sync = false;
    std::string render_node;  ///< the first /dev/dri/renderD* found; empty: none
    /// Why not available, e.g. "llvmpipe on the surfaceless platform: no
    /// EGL_MESA_image_dma_buf_export, no render node (/dev/dri/renderD*)"; empty when available.
    std::string reason;
};

/// What the probe looks at, gathered from the display (or made up by a test).
struct DmabufProbeInput {
    std::string egl_extensions;             ///< eglQueryString(display, EGL_EXTENSIONS)
    std::string platform;                   ///< EGL platform used: "surfaceless", "device", ...
    std::string gl_renderer;                ///< GL_RENDERER, e.g. "llvmpipe (LLVM 15.0.6, 256 bits)"
    std::vector<std::string> render_nodes;  ///< /dev/dri/renderD* present
};

/// The EGL extensions dma-buf export needs, in the order the reason names them.
inline constexpr const char* kDmabufExportExtensions[] = {"EGL_KHR_image_base", "EGL_KHR_gl_texture_2D_image",
                                                          "EGL_MESA_image_dma_buf_export"};

/// Decides from `input` alone (no EGL calls).
DmabufCapability decideDmabuf(const DmabufProbeInput& input);

/// The render nodes under `dri_dir` (/dev/dri/renderD*), sorted; none when the folder is absent.
std::vector<std::string> findRenderNodes(const std::string& dri_dir = "/dev/dri");

}  // namespace navmap::render
