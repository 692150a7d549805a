// SPDX-License-Identifier: Apache-2.0
#pragma once
// Label behaviors, friction, mass and the clamped Euler step of seed 4.4.5-4.4.6 and 4.5.1.
// All vectors are screen pixels; `offset` is the label center minus its projected anchor.

#include <glm/vec2.hpp>

namespace navmap::render::labels {

/// Free annotation (seed eq. 4.7): Hooke spring with constant k1 pulling the offset back to
/// the rest offset a_i of its chosen candidate.
[[nodiscard]] glm::vec2 freeForce(glm::vec2 offset, glm::vec2 rest_offset, float k1);

/// Line annotation (seed eq. 4.10-4.15): a normal spring k2 keeps the label at the signed
/// distance `d_optimum` from the line through the anchor with unit direction `dir`, a tangent
/// spring k3 pulls it along the line back to the anchor. Returns f_normal + f_tangent.
[[nodiscard]] glm::vec2 lineForce(glm::vec2 offset, glm::vec2 dir, float d_optimum, float k2, float k3);

/// Circle annotation (seed eq. 4.17): spring k4 keeping the label on radius r around the
/// anchor. At the anchor itself (no direction) it pushes straight up, deterministically.
[[nodiscard]] glm::vec2 circleForce(glm::vec2 offset, float radius, float k4);

/// Friction (seed eq. 4.8).
[[nodiscard]] glm::vec2 frictionForce(glm::vec2 velocity, float c);

/// Virtual mass from importance (seed 4.4.6): priority 0 -> mass_min, 1 -> mass_max.
[[nodiscard]] float massFromPriority(float priority, float mass_min, float mass_max);

/// State integrated per label.
struct Motion {
    glm::vec2 offset{0.0F};
    glm::vec2 velocity{0.0F};
};

/// One Euler step (seed eq. 4.19-4.21): a = f / m clamped to |a| <= max_accel (seed 4.5.1:
/// clamping the acceleration is what keeps the layout stable), v' = v + a dt, o' = o + v' dt.
[[nodiscard]] Motion eulerStep(Motion m, glm::vec2 force, float mass, float max_accel, float dt);

}  // namespace navmap::render::labels
