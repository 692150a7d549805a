// SPDX-License-Identifier: Apache-2.0
#include "navmap/render/renderer.h"

#include "gl/gl_renderer.h"
#include "noop/noop_renderer.h"

namespace navmap::render {

std::optional<Platform> parsePlatform(const std::string& name) {
    if (name == "auto") return Platform::Auto;
    if (name == "surfaceless") return Platform::Surfaceless;
    if (name == "device") return Platform::Device;
    return std::nullopt;
}

const char* platformName(Platform platform) {
    switch (platform) {
        case Platform::Auto: return "auto";
        case Platform::Surfaceless: return "surfaceless";
        case Platform::Device: return "device";
    }
    return "?";
}

std::unique_ptr<Renderer> Renderer::create(const RendererOptions& options) {
    return std::make_unique<gl::GlRenderer>(options);
}

std::unique_ptr<Renderer> Renderer::createNoop(const RendererOptions& options) {
    return std::make_unique<noop::NoopRenderer>(options);
}

}  // namespace navmap::render
