// SPDX-License-Identifier: Apache-2.0
#include <cmath>
#include <numbers>

#include <gtest/gtest.h>

#include "navmap/render/labels/oriented_box.h"

namespace nl = navmap::render::labels;

namespace {

nl::OrientedBox box(float cx, float cy, float hx, float hy, float deg = 0.0F) {
    return nl::OrientedBox::fromAngle({cx, cy}, {hx, hy}, deg * std::numbers::pi_v<float> / 180.0F);
}

}  // namespace

TEST(OrientedBox, SeparatedBoxesDoNotIntersect) {
    const auto a = box(0, 0, 10, 5);
    const auto b = box(25, 0, 10, 5);
    EXPECT_FALSE(a.intersects(b));
    EXPECT_FALSE(b.intersects(a));
    EXPECT_NEAR(a.overlapDepth(b), -5.0F, 1e-4F);
}

TEST(OrientedBox, TouchingBoxesIntersectWithZeroDepth) {
    // eq. 4.2: no collision only if delta_0 > 0 or delta_1 > 0, so touching collides.
    const auto a = box(0, 0, 10, 5);
    const auto b = box(20, 3, 10, 5);
    EXPECT_TRUE(a.intersects(b));
    EXPECT_NEAR(a.overlapDepth(b), 0.0F, 1e-4F);
    EXPECT_FALSE(a.overlaps(b));
}

TEST(OrientedBox, OverlapDepthIsSmallestPenetration) {
    const auto a = box(0, 0, 10, 5);
    const auto b = box(16, 2, 10, 5);
    EXPECT_NEAR(a.overlapDepth(b), 4.0F, 1e-4F);  // x: 20 - 16, y: 10 - 2 = 8
    EXPECT_TRUE(a.overlaps(b));
}

TEST(OrientedBox, RotatedBoxesSeparatedOnlyByTheirOwnAxis) {
    // Two 45-degree boxes side by side along their normal: their axis-aligned bounds overlap
    // but the SAT finds the separating axis of the rotated boxes.
    const auto a = box(0, 0, 20, 2, 45);
    const auto b = box(-5, 5, 20, 2, 45);  // 7.07 px along the normal (-1, 1)/sqrt 2
    const glm::vec2 ha = a.aabbHalfExtents();
    EXPECT_GT(ha.x, 15.0F);
    EXPECT_FALSE(a.intersects(b));
    EXPECT_NEAR(a.overlapDepth(b), -(std::sqrt(50.0F) - 4.0F), 1e-3F);
    // Closer along the normal: they overlap.
    const auto c = box(-1, 1, 20, 2, 45);
    EXPECT_TRUE(a.overlaps(c));
}

TEST(OrientedBox, RotatedAgainstAxisAligned) {
    const auto diamond = box(0, 0, 10, 10, 45);  // corner reaches x = 14.14
    EXPECT_TRUE(diamond.intersects(box(20, 0, 6.5F, 1)));
    EXPECT_FALSE(diamond.intersects(box(20, 0, 5.5F, 1)));
    // Near the diamond's corner region the AABBs overlap but the shapes do not.
    EXPECT_FALSE(diamond.intersects(box(12, 12, 2, 2)));
}

TEST(OrientedBox, ProjectionAndCorners) {
    const auto b = box(10, 20, 4, 2, 90);
    glm::vec2 c[4];
    b.corners(c);
    const nl::Interval ix = b.project({1, 0});
    EXPECT_NEAR(ix.min, 8.0F, 1e-4F);
    EXPECT_NEAR(ix.max, 12.0F, 1e-4F);
    float mn = 1e9F;
    float mx = -1e9F;
    for (const auto& p : c) {
        mn = std::min(mn, p.y);
        mx = std::max(mx, p.y);
    }
    EXPECT_NEAR(mn, 16.0F, 1e-4F);
    EXPECT_NEAR(mx, 24.0F, 1e-4F);
    EXPECT_NEAR(b.angle(), std::numbers::pi_v<float> / 2.0F, 1e-5F);
    EXPECT_NEAR(b.inflated(3).half_extents.x, 7.0F, 1e-6F);
}
