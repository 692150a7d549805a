// SPDX-License-Identifier: Apache-2.0
#pragma once
// What the GL ES context offers beyond ES 3.0 core, as far as the renderer cares
// (docs/gles-profile.md): read once per context, then every pass asks here instead of the driver.
// Private to render/.

#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace navmap::render::gl {

/// The context's version, its optional features and the limits the renderer checks. The
/// decisions are GL-free (constructed from a version and an extension list), so they are
/// unit-tested without a context; current() reads the context that is current.
class GlFeatures {
public:
    GlFeatures() = default;
    GlFeatures(int major, int minor, std::span<const std::string> extensions, int max_samples);

    /// The current context's (glGetStringi(GL_EXTENSIONS), GL_MAX_SAMPLES); `major`.`minor` as created.
    static GlFeatures current(int major, int minor);

    [[nodiscard]] int major() const { return m_major; }
    [[nodiscard]] int minor() const { return m_minor; }
    [[nodiscard]] int maxSamples() const { return m_max_samples; }
    [[nodiscard]] bool hasExtension(std::string_view name) const;
    /// R32F (and the other float formats) colour-renderable: core in ES 3.2, GL_EXT_color_buffer_float
    /// in 3.0 and 3.1. The shadow-volume roads draw the terrain depth into an R32F target.
    [[nodiscard]] bool colorBufferFloat() const;

    /// The features the renderer turns off on this context, each "what (why): what it does
    /// instead"; empty when it has everything. `msaa_option`: RendererOptions::msaa_samples as
    /// given (-1: auto), `software`: a software rasterizer (auto MSAA is off there).
    [[nodiscard]] std::vector<std::string> featuresOff(int msaa_option, bool software) const;

private:
    int m_major = 3;
    int m_minor = 0;
    int m_max_samples = 0;
    std::vector<std::string> m_extensions;
};

}  // namespace navmap::render::gl
