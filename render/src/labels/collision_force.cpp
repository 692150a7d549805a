// SPDX-License-Identifier: Apache-2.0
#include "collision_force.h"

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>

namespace navmap::render::labels {

namespace {

struct AxisResult {
    bool apart = false;
    float overlap = 0.0F;  // -(max(delta_0, delta_1)): >= 0 when the projections touch or overlap
    float g = 0.0F;        // eq. 4.4
};

// seed eq. 4.1-4.4 on one unit axis.
AxisResult onAxis(const OrientedBox& n, const OrientedBox& k, glm::vec2 axis) {
    const Interval in = n.project(axis);
    const Interval ik = k.project(axis);
    const float delta0 = in.min - ik.max;  // i_min^(n) - i_max^(k)
    const float delta1 = ik.min - in.max;  // i_min^(k) - i_max^(n)
    AxisResult r;
    r.overlap = -std::max(delta0, delta1);
    if (delta0 > 0.0F || delta1 > 0.0F) {  // eq. 4.2
        r.apart = true;
        return r;
    }
    const float w = -(delta0 + delta1);                  // eq. 4.3: summed widths on this axis
    r.g = w > 0.0F ? 2.0F * (delta0 / w + 0.5F) : 0.0F;  // eq. 4.4, the delta_0 component
    return r;
}

}  // namespace

Collision collide(const OrientedBox& n, const OrientedBox& k, float tie_sign) {
    Collision c;
    const glm::vec2 axes[4] = {n.axis, n.axisY(), k.axis, k.axisY()};
    // Parallel boxes share their axes (the common case: horizontal labels): two suffice.
    const bool parallel = std::abs(n.axis.x * k.axis.y - n.axis.y * k.axis.x) < 1e-6F;
    const int count = parallel ? 2 : 4;
    float g[4] = {0.0F, 0.0F, 0.0F, 0.0F};
    float depth = 0.0F;
    for (int i = 0; i < count; ++i) {
        const AxisResult r = onAxis(n, k, axes[i]);
        if (r.apart) {
            c.depth = r.overlap;  // negative: the separation along this axis
            return c;
        }
        depth = i == 0 ? r.overlap : std::min(depth, r.overlap);
        g[i] = r.g;
    }
    c.hit = true;
    c.depth = depth;

    // The frame (a, b) holding the axis with the largest |g| (eq. 4.5: |g_y / g_x| > 1 picks g_y).
    int dominant = 0;
    for (int i = 1; i < count; ++i) {
        if (std::abs(g[i]) > std::abs(g[dominant])) dominant = i;
    }
    const float gd = std::abs(g[dominant]);
    if (gd < 1e-6F) {
        c.force = {0.0F, tie_sign < 0.0F ? -1.0F : 1.0F};  // coincident centers: full force
        return c;
    }
    const int frame = dominant / 2 * 2;
    const glm::vec2 gvec = g[frame] * axes[frame] + g[frame + 1] * axes[frame + 1];
    glm::vec2 f = gvec * (1.0F / gd - 1.0F);  // eq. 4.5
    const float len2 = glm::dot(f, f);
    if (len2 > 1.0F) {
        f /= std::sqrt(len2);  // keep |f| in [0, 1] as the seed states
    }
    c.force = f;
    return c;
}

}  // namespace navmap::render::labels
