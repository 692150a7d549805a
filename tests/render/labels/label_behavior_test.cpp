// SPDX-License-Identifier: Apache-2.0
#include <cmath>

#include <gtest/gtest.h>
#include <glm/geometric.hpp>

#include "labels/label_behavior.h"

namespace nl = navmap::render::labels;

namespace {

constexpr float kDt = 1.0F / 60.0F;

// Integrates one label under a behavior force plus friction for `seconds`.
template <class Behavior>
nl::Motion simulate(nl::Motion m, Behavior&& behavior, float seconds, float friction = 10.0F, float mass = 1.0F,
                    float max_accel = 3000.0F) {
    const int steps = static_cast<int>(std::lround(seconds / kDt));
    for (int i = 0; i < steps; ++i) {
        const glm::vec2 f = behavior(m.offset) + nl::frictionForce(m.velocity, friction);
        m = nl::eulerStep(m, f, mass, max_accel, kDt);
    }
    return m;
}

}  // namespace

TEST(LabelBehavior, FreeSpringPullsToRestOffset) {
    const glm::vec2 rest{30, -12};
    EXPECT_EQ(nl::freeForce(rest, rest, 20.0F), glm::vec2(0.0F));
    EXPECT_EQ(nl::freeForce(rest + glm::vec2(2, 0), rest, 20.0F), glm::vec2(-40, 0));
    const nl::Motion m = simulate(
        {rest + glm::vec2(40, 25), {}}, [&](glm::vec2 o) { return nl::freeForce(o, rest, 20.0F); }, 3.0F);
    EXPECT_LT(glm::length(m.offset - rest), 0.05F);
    EXPECT_LT(glm::length(m.velocity), 0.5F);
}

TEST(LabelBehavior, LineLabelReturnsToItsLine) {
    // Segment at 30 degrees; optimum 14 px on the normal side; label pushed off the line and
    // along it.
    const glm::vec2 dir = glm::normalize(glm::vec2(std::cos(0.5236F), std::sin(0.5236F)));
    const glm::vec2 normal{-dir.y, dir.x};
    const float d_opt = 14.0F;
    const auto force = [&](glm::vec2 o) { return nl::lineForce(o, dir, d_opt, 60.0F, 12.0F); };
    EXPECT_NEAR(glm::length(force(normal * d_opt)), 0.0F, 1e-4F);
    // Off the line along the normal only: the force is along the normal, towards the line.
    const glm::vec2 f_off = force(normal * (d_opt + 10.0F));
    EXPECT_NEAR(glm::dot(f_off, dir), 0.0F, 1e-3F);
    EXPECT_LT(glm::dot(f_off, normal), 0.0F);
    // Displaced along the line only: the tangent spring pulls back to the anchor.
    const glm::vec2 f_along = force(normal * d_opt + dir * 30.0F);
    EXPECT_NEAR(glm::dot(f_along, normal), 0.0F, 1e-3F);
    EXPECT_NEAR(glm::dot(f_along, dir), -12.0F * 30.0F, 1e-2F);

    const nl::Motion m = simulate({normal * -20.0F + dir * 50.0F, {}}, force, 4.0F);
    EXPECT_NEAR(glm::dot(m.offset, normal), d_opt, 0.05F);  // back on the line at d_optimum
    EXPECT_NEAR(glm::dot(m.offset, dir), 0.0F, 0.5F);       // and at its anchor
}

TEST(LabelBehavior, CircleLabelReturnsToItsRadius) {
    const float r = 40.0F;
    const auto force = [&](glm::vec2 o) { return nl::circleForce(o, r, 40.0F); };
    EXPECT_NEAR(glm::length(force({r, 0})), 0.0F, 1e-4F);
    EXPECT_LT(force({80, 0}).x, 0.0F);                           // outside: pulled in
    EXPECT_GT(force({10, 0}).x, 0.0F);                           // inside: pushed out
    EXPECT_EQ(glm::normalize(force({0, 0})), glm::vec2(0, -1));  // at the anchor: up
    for (const glm::vec2 start : {glm::vec2(90, 30), glm::vec2(3, -4), glm::vec2(-20, 5)}) {
        const nl::Motion m = simulate({start, {}}, force, 4.0F);
        EXPECT_NEAR(glm::length(m.offset), r, 0.1F) << start.x << "," << start.y;
        // Only the radius is constrained: the direction is kept.
        EXPECT_GT(glm::dot(glm::normalize(m.offset), glm::normalize(start)), 0.99F);
    }
}

TEST(LabelBehavior, EulerStepClampsAcceleration) {
    // A huge force: acceleration limited to max_accel (seed 4.5.1).
    const nl::Motion m = nl::eulerStep({}, {1e6F, 0}, 1.0F, 3000.0F, kDt);
    EXPECT_NEAR(m.velocity.x, 3000.0F * kDt, 1e-3F);
    EXPECT_NEAR(m.offset.x, 3000.0F * kDt * kDt, 1e-4F);  // o' uses v' (eq. 4.21)
    // Below the clamp: a = f / m exactly (eq. 4.19).
    const nl::Motion s = nl::eulerStep({{1, 2}, {3, 0}}, {0, 120}, 2.0F, 3000.0F, 0.5F);
    EXPECT_FLOAT_EQ(s.velocity.y, 30.0F);
    EXPECT_FLOAT_EQ(s.offset.x, 2.5F);
    EXPECT_FLOAT_EQ(s.offset.y, 17.0F);
    // Direction is preserved by the clamp.
    const nl::Motion d = nl::eulerStep({}, {3e5F, 4e5F}, 1.0F, 100.0F, 1.0F);
    EXPECT_NEAR(d.velocity.x, 60.0F, 1e-3F);
    EXPECT_NEAR(d.velocity.y, 80.0F, 1e-3F);
}

TEST(LabelBehavior, FrictionAndMass) {
    EXPECT_EQ(nl::frictionForce({10, -4}, 2.0F), glm::vec2(-20, 8));
    EXPECT_FLOAT_EQ(nl::massFromPriority(0.0F, 1.0F, 3.0F), 1.0F);
    EXPECT_FLOAT_EQ(nl::massFromPriority(0.5F, 1.0F, 3.0F), 2.0F);
    EXPECT_FLOAT_EQ(nl::massFromPriority(7.0F, 1.0F, 3.0F), 3.0F);  // clamped
    // A heavier (more important) label moves less under the same force.
    const nl::Motion light = nl::eulerStep({}, {100, 0}, 1.0F, 3000.0F, kDt);
    const nl::Motion heavy = nl::eulerStep({}, {100, 0}, 3.0F, 3000.0F, kDt);
    EXPECT_NEAR(heavy.offset.x * 3.0F, light.offset.x, 1e-6F);
}
