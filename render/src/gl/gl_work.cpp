// SPDX-License-Identifier: Apache-2.0
#include "gl/gl_work.h"

namespace navmap::render::gl {

PassWork& glWork() {
    thread_local PassWork work;
    return work;
}

std::uint64_t texelBytes(GLsizei w, GLsizei h, GLenum format, GLenum type) {
    std::uint64_t channels = 0;
    switch (format) {
        case GL_RED:
        case GL_RED_INTEGER:
        case GL_ALPHA:
        case GL_LUMINANCE:
        case GL_DEPTH_COMPONENT: channels = 1; break;
        case GL_RG:
        case GL_RG_INTEGER:
        case GL_LUMINANCE_ALPHA: channels = 2; break;
        case GL_RGB:
        case GL_RGB_INTEGER: channels = 3; break;
        case GL_RGBA:
        case GL_RGBA_INTEGER: channels = 4; break;
        default: return 0;
    }
    std::uint64_t per_texel = 0;
    switch (type) {
        case GL_UNSIGNED_BYTE:
        case GL_BYTE: per_texel = channels; break;
        case GL_UNSIGNED_SHORT:
        case GL_SHORT:
        case GL_HALF_FLOAT: per_texel = 2 * channels; break;
        case GL_UNSIGNED_INT:
        case GL_INT:
        case GL_FLOAT: per_texel = 4 * channels; break;
        case GL_UNSIGNED_SHORT_5_6_5:
        case GL_UNSIGNED_SHORT_4_4_4_4:
        case GL_UNSIGNED_SHORT_5_5_5_1: per_texel = 2; break;
        default: return 0;
    }
    return per_texel * static_cast<std::uint64_t>(w < 0 ? 0 : w) * static_cast<std::uint64_t>(h < 0 ? 0 : h);
}

}  // namespace navmap::render::gl
