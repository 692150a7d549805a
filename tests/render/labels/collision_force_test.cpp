// SPDX-License-Identifier: Apache-2.0
#include <cmath>

#include <gtest/gtest.h>
#include <glm/geometric.hpp>

#include "labels/collision_force.h"

namespace nl = navmap::render::labels;

namespace {

nl::OrientedBox box(float cx, float cy, float hx = 50, float hy = 10) { return {{cx, cy}, {hx, hy}, {1, 0}}; }

}  // namespace

TEST(CollisionForce, NoForceWhenApartOrTouching) {
    EXPECT_EQ(nl::collisionForce(box(0, 0), box(150, 0)), glm::vec2(0.0F));
    EXPECT_EQ(nl::collisionForce(box(0, 0), box(0, 40)), glm::vec2(0.0F));
    const glm::vec2 touching = nl::collisionForce(box(0, 0), box(100, 0));
    EXPECT_NEAR(glm::length(touching), 0.0F, 1e-6F);
}

TEST(CollisionForce, PushesApartAndIsAntisymmetric) {
    const auto n = box(90, 0);
    const auto k = box(0, 0);
    const glm::vec2 f_nk = nl::collisionForce(n, k);
    const glm::vec2 f_kn = nl::collisionForce(k, n);
    EXPECT_GT(f_nk.x, 0.0F);  // n is right of k: pushed right
    EXPECT_NEAR(f_nk.y, 0.0F, 1e-6F);
    EXPECT_NEAR(f_nk.x, 0.1F, 1e-5F);  // g = 0.9 -> 1/0.9 - 1 scaled by 0.9 = 0.1
    EXPECT_FLOAT_EQ(f_kn.x, -f_nk.x);
}

TEST(CollisionForce, MagnitudeGrowsWithOverlapWithinUnitRange) {
    float previous = 0.0F;
    for (float dx = 99.0F; dx >= 0.0F; dx -= 1.0F) {
        const float m = glm::length(nl::collisionForce(box(dx, 0), box(0, 0)));
        EXPECT_GE(m, previous) << "dx=" << dx;
        EXPECT_LE(m, 1.0F + 1e-6F);
        previous = m;
    }
    EXPECT_NEAR(previous, 1.0F, 1e-6F);  // coincident centers: full force
    // Diagonal overlap stays within [0, 1] too (the raw eq. 4.5 would reach sqrt 2).
    const float diag = glm::length(nl::collisionForce(box(10, 2), box(0, 0)));
    EXPECT_GT(diag, 0.0F);
    EXPECT_LE(diag, 1.0F + 1e-6F);
}

TEST(CollisionForce, DominantAxisFollowsNormalizedOffset) {
    // Wide labels stacked with a small vertical offset: the push is mostly vertical (eq. 4.5).
    const glm::vec2 f = nl::collisionForce(box(5, 5), box(0, 0));
    EXPECT_GT(f.y, 0.0F);
    EXPECT_GT(std::abs(f.y), 3.0F * std::abs(f.x));
}

TEST(CollisionForce, CoincidentCentersUseTieSign) {
    EXPECT_EQ(nl::collisionForce(box(0, 0), box(0, 0), -1.0F), glm::vec2(0.0F, -1.0F));
    EXPECT_EQ(nl::collisionForce(box(0, 0), box(0, 0), 1.0F), glm::vec2(0.0F, 1.0F));
}
