// SPDX-License-Identifier: Apache-2.0
#pragma once
// Screen projection shared by the label pass's sources (label_pass*.cpp). Private to render/.
#include <glm/vec2.hpp>
#include <glm/vec4.hpp>

namespace navmap::render::gl {

/// Clip coordinates to screen pixels (origin top left, y down).
inline glm::vec2 toScreen(const glm::vec4& clip, glm::vec2 viewport) {
    const glm::vec2 ndc = glm::vec2(clip) / clip.w;
    return {(ndc.x * 0.5f + 0.5f) * viewport.x, (0.5f - ndc.y * 0.5f) * viewport.y};
}

}  // namespace navmap::render::gl
