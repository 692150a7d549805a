// SPDX-License-Identifier: Apache-2.0
#include "navmap/render/dmabuf_probe.h"

#include <algorithm>
#include <filesystem>
#include <sstream>
#include <system_error>

namespace navmap::render {

namespace {

bool hasExtension(const std::string& list, const std::string& name) {
    std::istringstream words(list);
    std::string w;
    while (words >> w) {
        if (w == name) return true;
    }
    return false;
}

// "llvmpipe (LLVM 15.0.6, 256 bits) on the surfaceless platform"
std::string whereDrawn(const std::string& gl_renderer, const std::string& platform) {
    std::string gpu = gl_renderer.substr(0, gl_renderer.find(' '));
    if (gpu.empty()) gpu = "the GL renderer";
    return gpu + " on " + (platform.empty() ? "an unknown" : "the " + platform) + " platform";
}

}  // namespace

DmabufCapability decideDmabuf(const DmabufProbeInput& input) {
    DmabufCapability c;
    c.native_fence_sync = hasExtension(input.egl_extensions, "EGL_KHR_fence_sync") &&
                          hasExtension(input.egl_extensions, "EGL_ANDROID_native_fence_sync");
    if (!input.drm_nodes.empty()) c.drm_node = input.drm_nodes.front();
    std::string missing;
    const auto add = [&missing](const std::string& what) { missing += (missing.empty() ? "" : ", ") + what; };
    for (const char* ext : kDmabufEglExtensions) {
        if (!hasExtension(input.egl_extensions, ext)) add(std::string("no ") + ext);
    }
    for (const char* ext : kDmabufGlExtensions) {
        if (!hasExtension(input.gl_extensions, ext)) add(std::string("no ") + ext);
    }
    if (input.drm_nodes.empty()) add("no DRM node (/dev/dri/renderD*, /dev/dri/card*)");
    c.available = missing.empty();
    if (!c.available) c.reason = whereDrawn(input.gl_renderer, input.platform) + ": " + missing;
    return c;
}

void refuseDmabuf(DmabufCapability& capability, const std::string& gl_renderer, const std::string& platform,
                  const std::string& why) {
    capability.available = false;
    capability.reason =
        whereDrawn(gl_renderer, platform) + ": GBM allocates no linear ABGR8888 render buffer (" + why + ")";
}

std::vector<std::string> findDrmNodes(const std::string& dri_dir) {
    std::vector<std::string> render, primary;
    std::error_code ec;
    for (std::filesystem::directory_iterator it(dri_dir, ec), end; !ec && it != end; it.increment(ec)) {
        const std::string name = it->path().filename().string();
        if (name.rfind("renderD", 0) == 0) render.push_back(it->path().string());
        if (name.rfind("card", 0) == 0) primary.push_back(it->path().string());
    }
    std::sort(render.begin(), render.end());
    std::sort(primary.begin(), primary.end());
    render.insert(render.end(), primary.begin(), primary.end());
    return render;
}

}  // namespace navmap::render
