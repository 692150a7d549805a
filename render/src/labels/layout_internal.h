// SPDX-License-Identifier: Apache-2.0
#pragma once
// Small tests shared by the parts of LabelLayout (label_layout.cpp, label_forces.cpp,
// label_placement.cpp, label_overlaps.cpp).

#include <glm/common.hpp>
#include <glm/vec2.hpp>

#include "navmap/render/labels/label_types.h"

namespace navmap::render::labels {

// Boxes whose bounding boxes are further apart than this skip the separating-axis test; the
// margin stays above the test's own rounding, so the outcome equals testing every pair.
inline constexpr float kTouchSlack = 0.05F;

inline bool apart(glm::vec2 ca, glm::vec2 ha, glm::vec2 cb, glm::vec2 hb) {
    const glm::vec2 gap = glm::abs(ca - cb) - ha - hb;
    return gap.x > kTouchSlack || gap.y > kTouchSlack;
}

/// Fading in or visible: the labels the forces act on.
inline bool placed(LabelState s) { return s == LabelState::FadingIn || s == LabelState::Visible; }

}  // namespace navmap::render::labels
