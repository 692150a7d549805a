// SPDX-License-Identifier: Apache-2.0
#include "navmap/render/labels/oriented_box.h"

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>

namespace navmap::render::labels {

OrientedBox OrientedBox::fromAngle(glm::vec2 center, glm::vec2 half_extents, float angle_rad) {
    return OrientedBox{center, half_extents, {std::cos(angle_rad), std::sin(angle_rad)}};
}

float OrientedBox::angle() const { return std::atan2(axis.y, axis.x); }

glm::vec2 OrientedBox::aabbHalfExtents() const {
    const float ax = std::abs(axis.x);
    const float ay = std::abs(axis.y);
    return {half_extents.x * ax + half_extents.y * ay, half_extents.x * ay + half_extents.y * ax};
}

void OrientedBox::corners(glm::vec2 out[4]) const {
    const glm::vec2 ex = axis * half_extents.x;
    const glm::vec2 ey = axisY() * half_extents.y;
    out[0] = center - ex - ey;
    out[1] = center + ex - ey;
    out[2] = center + ex + ey;
    out[3] = center - ex + ey;
}

Interval OrientedBox::project(glm::vec2 unit_axis) const {
    // seed eq. 4.1 evaluated in closed form: centre projection +- projected radius, which is
    // the min/max over the four corners without building them.
    const float c = glm::dot(center, unit_axis);
    const float r =
        half_extents.x * std::abs(glm::dot(axis, unit_axis)) + half_extents.y * std::abs(glm::dot(axisY(), unit_axis));
    return {c - r, c + r};
}

OrientedBox OrientedBox::inflated(float margin) const {
    return OrientedBox{center, half_extents + glm::vec2(margin), axis};
}

namespace {

// Overlap of the two projections on one axis: -(max(delta_0, delta_1)) with delta from
// seed 4.4.4; >= 0 means the intervals touch or overlap.
float axisOverlap(const OrientedBox& a, const OrientedBox& b, glm::vec2 unit_axis) {
    const Interval ia = a.project(unit_axis);
    const Interval ib = b.project(unit_axis);
    const float delta0 = ia.min - ib.max;
    const float delta1 = ib.min - ia.max;
    return -std::max(delta0, delta1);
}

}  // namespace

float OrientedBox::overlapDepth(const OrientedBox& other) const {
    float depth = axisOverlap(*this, other, axis);
    if (depth < 0.0F) {
        return depth;
    }
    depth = std::min(depth, axisOverlap(*this, other, axisY()));
    if (depth < 0.0F) {
        return depth;
    }
    // Parallel boxes share their axes (the common case: horizontal labels), so two axes suffice.
    const float cross = axis.x * other.axis.y - axis.y * other.axis.x;
    if (std::abs(cross) < 1e-6F) {
        return depth;
    }
    depth = std::min(depth, axisOverlap(*this, other, other.axis));
    if (depth < 0.0F) {
        return depth;
    }
    return std::min(depth, axisOverlap(*this, other, other.axisY()));
}

}  // namespace navmap::render::labels
