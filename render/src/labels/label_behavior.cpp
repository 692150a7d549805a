// SPDX-License-Identifier: Apache-2.0
#include "label_behavior.h"

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>

namespace navmap::render::labels {

glm::vec2 freeForce(glm::vec2 offset, glm::vec2 rest_offset, float k1) {
    return -k1 * (offset - rest_offset);  // eq. 4.7 with o_i measured from p'_i + a_i
}

glm::vec2 lineForce(glm::vec2 offset, glm::vec2 dir, float d_optimum, float k2, float k3) {
    const glm::vec2 normal{-dir.y, dir.x};  // s'_normal of eq. 4.12
    // eq. 4.10-4.11: distance to the nearest point on the line, here signed along the normal
    // so that the optimum distance can lie on either side of the line.
    const float d_real0 = glm::dot(offset, normal);
    const glm::vec2 f_normal = -k2 * (d_real0 - d_optimum) * normal;  // eq. 4.12
    // eq. 4.13-4.14: distance to the nearest point on the normal through the anchor, i.e. the
    // displacement along the line; eq. 4.15 pulls it back to the anchor.
    const float d_real1 = glm::dot(offset, dir);
    const glm::vec2 f_tangent = -k3 * d_real1 * dir;  // eq. 4.15
    return f_normal + f_tangent;                      // part of eq. 4.16
}

glm::vec2 circleForce(glm::vec2 offset, float radius, float k4) {
    const float len = glm::length(offset);
    const glm::vec2 dir = len > 1e-6F ? offset / len : glm::vec2(0.0F, -1.0F);
    return -k4 * (len - radius) * dir;  // eq. 4.17
}

glm::vec2 frictionForce(glm::vec2 velocity, float c) { return -c * velocity; }  // eq. 4.8

float massFromPriority(float priority, float mass_min, float mass_max) {
    const float p = std::clamp(priority, 0.0F, 1.0F);
    return mass_min + (mass_max - mass_min) * p;
}

Motion eulerStep(Motion m, glm::vec2 force, float mass, float max_accel, float dt) {
    glm::vec2 a = force / mass;  // eq. 4.19
    const float a2 = glm::dot(a, a);
    if (a2 > max_accel * max_accel) {
        a *= max_accel / std::sqrt(a2);  // seed 4.5.1: clamp the final acceleration
    }
    m.velocity += a * dt;         // eq. 4.20
    m.offset += m.velocity * dt;  // eq. 4.21 (uses v', semi-implicit)
    return m;
}

}  // namespace navmap::render::labels
