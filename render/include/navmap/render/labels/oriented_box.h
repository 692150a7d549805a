// SPDX-License-Identifier: Apache-2.0
#pragma once
// Object-oriented bounding box (OOBB) of a label in screen space and the separating axis
// test between two of them (seed 4.4.4, eq. 4.1-4.2). Hand-written: no Debian package
// provides a 2D OBB/SAT routine small enough to embed here.

#include <glm/vec2.hpp>

namespace navmap::render::labels {

/// A closed interval [min, max] on a projection axis (seed eq. 4.1).
struct Interval {
    float min = 0.0F;
    float max = 0.0F;
};

/// 2D oriented box: center, half extents along its own axes, and the unit x axis of the box
/// (cos a, sin a) in screen pixels (y down). A plain value type; cheap to copy.
struct OrientedBox {
    glm::vec2 center{0.0F};
    glm::vec2 half_extents{0.0F};
    glm::vec2 axis{1.0F, 0.0F};  ///< unit vector along the box width; (1, 0) = horizontal

    /// A box rotated by `angle_rad` (counter-clockwise in math convention on a y-down
    /// screen this turns clockwise visually).
    [[nodiscard]] static OrientedBox fromAngle(glm::vec2 center, glm::vec2 half_extents, float angle_rad);

    [[nodiscard]] float angle() const;  ///< rotation in radians, atan2(axis.y, axis.x)
    [[nodiscard]] glm::vec2 axisY() const { return {-axis.y, axis.x}; }
    /// Half extents of the axis-aligned box that encloses this one.
    [[nodiscard]] glm::vec2 aabbHalfExtents() const;
    /// Corners c0..c3 in order (counter-clockwise in box coordinates).
    void corners(glm::vec2 out[4]) const;
    /// Projection of the four corners on a unit axis (seed eq. 4.1).
    [[nodiscard]] Interval project(glm::vec2 unit_axis) const;
    /// The same box with `margin` pixels added on every side (buffer zones, seed 4.5.3).
    [[nodiscard]] OrientedBox inflated(float margin) const;

    /// Separating axis theorem over the four edge normals (seed 4.4.4): the smallest overlap
    /// of the two projections over all axes. Negative: separated by that many pixels along
    /// some axis; 0: touching; positive: penetration depth along the best separating axis.
    [[nodiscard]] float overlapDepth(const OrientedBox& other) const;
    /// Collision in the sense of eq. 4.2: no axis with delta_0 > 0 or delta_1 > 0, so touching
    /// boxes collide (with zero force, see collisionForce()).
    [[nodiscard]] bool intersects(const OrientedBox& other) const { return overlapDepth(other) >= 0.0F; }
    /// Interiors overlap by more than `tolerance` pixels (what layout quality counts).
    [[nodiscard]] bool overlaps(const OrientedBox& other, float tolerance = 1e-3F) const {
        return overlapDepth(other) > tolerance;
    }
};

}  // namespace navmap::render::labels
