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

}  // namespace

DmabufCapability decideDmabuf(const DmabufProbeInput& input) {
    DmabufCapability c;
    c.native_fence_sync = hasExtension(input.egl_extensions, "EGL_KHR_fence_sync") &&
                          hasExtension(input.egl_extensions, "EGL_ANDROID_native_fence_sync");
    if (!input.render_nodes.empty()) c.render_node = input.render_nodes.front();
    std::string missing;
    for (const char* ext : kDmabufExportExtensions) {
        if (!hasExtension(input.egl_extensions, ext)) missing += std::string(missing.empty() ? "" : ", ") + "no " + ext;
    }
    if (input.render_nodes.empty())
        missing += std::string(missing.empty() ? "" : ", ") + "no render node (/dev/dri/renderD*)";
    c.available = missing.empty();
    if (!c.available) {
        // "llvmpipe (LLVM 15.0.6, 256 bits)" -> "llvmpipe"
        std::string gpu = input.gl_renderer.substr(0, input.gl_renderer.find(' '));
        if (gpu.empty()) gpu = "the GL renderer";
        const std::string platform = input.platform.empty() ? "an unknown" : "the " + input.platform;
        c.reason = gpu + " on " + platform + " platform: " + missing;
    }
    return c;
}

std::vector<std::string> findRenderNodes(const std::string& dri_dir) {
    std::vector<std::string> nodes;
    std::error_code ec;
    for (std::filesystem::directory_iterator it(dri_dir, ec), end; !ec && it != end; it.increment(ec)) {
        const std::string name = it->path().filename().string();
        if (name.rfind("renderD", 0) == 0) nodes.push_back(it->path().string());
    }
    std::sort(nodes.begin(), nodes.end());
    return nodes;
}

}  // namespace navmap::render
