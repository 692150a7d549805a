// SPDX-License-Identifier: Apache-2.0
#include "gl_features.h"

#include <GLES3/gl3.h>

#include <algorithm>

namespace navmap::render::gl {

GlFeatures::GlFeatures(int major, int minor, std::span<const std::string> extensions, int max_samples)
    : m_major(major), m_minor(minor), m_max_samples(max_samples), m_extensions(extensions.begin(), extensions.end()) {
    std::sort(m_extensions.begin(), m_extensions.end());
}

GlFeatures GlFeatures::current(int major, int minor) {
    GLint count = 0;
    glGetIntegerv(GL_NUM_EXTENSIONS, &count);
    std::vector<std::string> extensions;
    for (GLint i = 0; i < count; ++i) {
        const auto* ext = reinterpret_cast<const char*>(glGetStringi(GL_EXTENSIONS, static_cast<GLuint>(i)));
        if (ext) extensions.emplace_back(ext);
    }
    GLint max_samples = 0;
    glGetIntegerv(GL_MAX_SAMPLES, &max_samples);
    return GlFeatures(major, minor, extensions, max_samples);
}

bool GlFeatures::hasExtension(std::string_view name) const {
    return std::binary_search(m_extensions.begin(), m_extensions.end(), name,
                              [](std::string_view a, std::string_view b) { return a < b; });
}

bool GlFeatures::colorBufferFloat() const {
    return (m_major > 3 || (m_major == 3 && m_minor >= 2)) || hasExtension("GL_EXT_color_buffer_float");
}

std::vector<std::string> GlFeatures::featuresOff(int msaa_option, bool software) const {
    std::vector<std::string> off;
    if (!colorBufferFloat()) {
        off.emplace_back("shadow-volume roads (no GL_EXT_color_buffer_float before ES 3.2): geometric roads");
    }
    // MSAA is ES 3.0 core (GL_MAX_SAMPLES >= 4); auto turns it off on software rasterizers.
    const int wanted = msaa_option < 0 ? (software ? 0 : 4) : msaa_option;
    if (msaa_option < 0 && software) {
        off.emplace_back("MSAA (software rasterizer, msaa auto): no multisampling");
    } else if (wanted > 1 && m_max_samples < 2) {
        off.emplace_back("MSAA (GL_MAX_SAMPLES " + std::to_string(m_max_samples) + "): no multisampling");
    } else if (wanted > m_max_samples) {
        off.emplace_back("MSAA " + std::to_string(wanted) + "x (GL_MAX_SAMPLES " + std::to_string(m_max_samples) +
                         "): " + std::to_string(m_max_samples) + "x");
    }
    return off;
}

}  // namespace navmap::render::gl
