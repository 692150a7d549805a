// SPDX-License-Identifier: Apache-2.0
#pragma once
// The collision force of seed 4.4.4 (eq. 4.2-4.6) between two label boxes.

#include <glm/vec2.hpp>

#include "navmap/render/labels/oriented_box.h"

namespace navmap::render::labels {

/// Outcome of testing one pair of boxes.
struct Collision {
    bool hit = false;       ///< eq. 4.2: no separating axis (touching counts)
    float depth = 0.0F;     ///< smallest overlap over the SAT axes in pixels (OrientedBox::overlapDepth)
    glm::vec2 force{0.0F};  ///< f^(n,k) acting on n, |f| in [0, 1]; zero unless hit
};

/// Separating axis test and force f^(n,k) of seed eq. 4.2-4.5 in one pass.
///
/// On every SAT axis a (the edge normals of both boxes) the projections give delta_0,
/// delta_1 (eq. 4.2), the width w (eq. 4.3) and g_a = 2 (delta_0 / w + 0.5) (eq. 4.4): the
/// center offset normalized by the summed half widths, in [-1, 1] while the projections
/// overlap. Eq. 4.5 is evaluated in the frame (a, b) of the box that owns the axis with the
/// largest |g| (the one closest to separating): f = (g_a a + g_b b) (1 / |g_a| - 1). For two
/// horizontal boxes this is exactly the seed's formula on screen x and y. Picking the axis
/// over both boxes keeps the force continuous when rotated boxes start to touch (it is 0
/// there), which an axis-aligned approximation is not. |f| is clamped to 1 (the raw formula
/// reaches sqrt 2 on the diagonal). f^(k,n) = -f^(n,k) (seed Table 4.1).
///
/// `tie_sign` (+1 or -1) picks the direction (0, tie_sign) when the centers coincide, so that
/// the pair separates deterministically (callers pass opposite signs for n and k).
[[nodiscard]] Collision collide(const OrientedBox& n, const OrientedBox& k, float tie_sign = 1.0F);

/// The force part of collide(): f^(n,k) with magnitude in [0, 1], 0 when the boxes only touch
/// or are apart, growing with the overlap, 1 when the centers coincide.
[[nodiscard]] inline glm::vec2 collisionForce(const OrientedBox& n, const OrientedBox& k, float tie_sign = 1.0F) {
    return collide(n, k, tie_sign).force;
}

}  // namespace navmap::render::labels
