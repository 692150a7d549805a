// SPDX-License-Identifier: Apache-2.0
#include "drawn_geometry.h"

#include <algorithm>
#include <limits>

#include <glm/geometric.hpp>

namespace navmap::test {

float convexOverlapDepth(std::span<const glm::vec2> a, std::span<const glm::vec2> b) {
    float depth = std::numeric_limits<float>::max();
    for (const auto poly : {a, b}) {
        for (std::size_t i = 0; i < poly.size(); ++i) {
            const glm::vec2 e = poly[(i + 1) % poly.size()] - poly[i];
            if (glm::dot(e, e) < 1e-12F) continue;
            const glm::vec2 axis = glm::normalize(glm::vec2(-e.y, e.x));
            float a0 = std::numeric_limits<float>::max(), a1 = std::numeric_limits<float>::lowest();
            float b0 = a0, b1 = a1;
            for (const glm::vec2 p : a) {
                a0 = std::min(a0, glm::dot(p, axis));
                a1 = std::max(a1, glm::dot(p, axis));
            }
            for (const glm::vec2 p : b) {
                b0 = std::min(b0, glm::dot(p, axis));
                b1 = std::max(b1, glm::dot(p, axis));
            }
            depth = std::min(depth, std::min(a1, b1) - std::max(a0, b0));
        }
    }
    return depth;
}

bool glyphsOverlap(std::span<const render::labels::ScreenQuad> a, std::span<const render::labels::ScreenQuad> b,
                   float tolerance_px) {
    for (const auto& qa : a) {
        for (const auto& qb : b) {
            if (convexOverlapDepth(qa, qb) > tolerance_px) return true;
        }
    }
    return false;
}

bool overlapsPolygon(std::span<const render::labels::ScreenQuad> glyphs, std::span<const glm::vec2> polygon,
                     float tolerance_px) {
    if (polygon.size() < 3) return false;
    return std::any_of(glyphs.begin(), glyphs.end(),
                       [&](const auto& q) { return convexOverlapDepth(q, polygon) > tolerance_px; });
}

}  // namespace navmap::test
