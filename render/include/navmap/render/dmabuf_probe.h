// SPDX-License-Identifier: Apache-2.0
#pragma once
// Whether the renderer can hand its frames out as dma-bufs (docs/gles-profile.md "dma-buf
// export"), and why not. The export path allocates linear buffers with GBM on a DRM node, imports
// them into the EGL display (EGL_EXT_image_dma_buf_import) as textures the frame is copied into
// on the GPU (GL_OES_EGL_image), and passes their fds on (Renderer::exportFrame).

#include <string>
#include <vector>

namespace navmap::render {

/// What the probe found. `available` needs every extension of the export path, a DRM node and a
/// GBM allocation on it; `reason` names what is missing when it is not.
struct DmabufCapability {
    bool available = false;
    /// EGL_ANDROID_native_fence_sync: a frame's end travels as a sync fence fd; without it the
    /// exporter finishes the frame (glFinish) before handing a buffer out.
    bool native_fence_sync = false;
    /// The DRM node the buffers come from (where GBM allocated), else the first one found; empty:
    /// none.
    std::string drm_node;
    /// Why not available, e.g. "llvmpipe on the surfaceless platform: no
    /// EGL_EXT_image_dma_buf_import, no DRM node (/dev/dri/renderD*, /dev/dri/card*)"; empty when
    /// available.
    std::string reason;
};

/// What the probe looks at, gathered from the display (or made up by a test).
struct DmabufProbeInput {
    std::string egl_extensions;          ///< eglQueryString(display, EGL_EXTENSIONS)
    std::string gl_extensions;           ///< the context's GL extensions, space-separated
    std::string platform;                ///< EGL platform used: "surfaceless", "device", ...
    std::string gl_renderer;             ///< GL_RENDERER, e.g. "llvmpipe (LLVM 15.0.6, 256 bits)"
    std::vector<std::string> drm_nodes;  ///< findDrmNodes()
};

/// The EGL and GL extensions dma-buf export needs, in the order the reason names them.
inline constexpr const char* kDmabufEglExtensions[] = {"EGL_KHR_image_base", "EGL_EXT_image_dma_buf_import"};
inline constexpr const char* kDmabufGlExtensions[] = {"GL_OES_EGL_image"};

/// Decides from `input` alone (no EGL calls): whether to try a GBM allocation at all.
DmabufCapability decideDmabuf(const DmabufProbeInput& input);

/// After decideDmabuf() said yes: the GBM allocation on every node failed, each for `why`
/// ("/dev/dri/renderD128: Permission denied; ..."). Turns `capability` into a refusal naming it.
void refuseDmabuf(DmabufCapability& capability, const std::string& gl_renderer, const std::string& platform,
                  const std::string& why);

/// The DRM nodes under `dri_dir`: render nodes (renderD*) first, then primary nodes (card*), each
/// sorted; none when the folder is absent. A primary node is where a driver without render-node
/// buffers (vgem's dumb buffers) allocates.
std::vector<std::string> findDrmNodes(const std::string& dri_dir = "/dev/dri");

}  // namespace navmap::render
