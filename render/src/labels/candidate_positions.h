// SPDX-License-Identifier: Apache-2.0
#pragma once
// Candidate positions for the initial placement of a label (seed 4.4.3, Fig. 4.3).

#include <cstdint>

#include <glm/vec2.hpp>

#include "navmap/render/labels/label_types.h"

namespace navmap::render::labels {

struct LayoutParams;

/// The candidates of one label, best visual association first (Yoeli's ranking).
struct CandidateSet {
    std::uint8_t count = 0;
    glm::vec2 offset[4]{};  ///< label center minus anchor, pixels
    float d_optimum[4]{};   ///< Line, rotated: signed distance from the line along its normal (eq. 4.12)
};

/// Candidates for a label whose scaled text box has half extents `half`.
/// - Point, Area: four-position model (upper right, upper left, lower right, lower left).
/// - Circle: the same four directions at radius `radius` (eq. 4.17's r).
/// - Line: three offsets, above the line, below it, and on it; along the normal of `dir`
///   when `rotated`, else vertically with horizontal text.
/// `upright` (a label standing in the 3D world on its anchor) keeps only positions above the
/// anchor: Point/Area upper right, upper left, above; Line above, and one line higher.
[[nodiscard]] CandidateSet candidatePositions(LabelKind kind, glm::vec2 half, bool rotated, glm::vec2 dir, float radius,
                                              const LayoutParams& params, bool upright = false);

/// Radius of a circle label: the caller's value if > 0, else the four-position distance.
[[nodiscard]] float circleRadius(float requested, glm::vec2 half, const LayoutParams& params);

}  // namespace navmap::render::labels
