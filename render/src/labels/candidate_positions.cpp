// SPDX-License-Identifier: Apache-2.0
#include "candidate_positions.h"

#include <glm/geometric.hpp>

#include "navmap/render/labels/layout_params.h"

namespace navmap::render::labels {

namespace {

// Yoeli's four-position model [Yoe72] in screen space (y down): the ranking of seed Fig. 4.3(a).
constexpr glm::vec2 kFourPositions[4] = {{1.0F, -1.0F}, {-1.0F, -1.0F}, {1.0F, 1.0F}, {-1.0F, 1.0F}};

}  // namespace

float circleRadius(float requested, glm::vec2 half, const LayoutParams& params) {
    if (requested > 0.0F) {
        return requested;
    }
    return glm::length(half + glm::vec2(params.candidate_gap_px));
}

CandidateSet candidatePositions(LabelKind kind, glm::vec2 half, bool rotated, glm::vec2 dir, float radius,
                                const LayoutParams& params, bool upright) {
    CandidateSet set;
    switch (kind) {
        case LabelKind::Point:
        case LabelKind::Area: {
            // seed 4.4.3: four candidate OOBBs offset from p'_i (area: from the barycenter).
            const glm::vec2 d = half + glm::vec2(params.candidate_gap_px);
            if (upright) {
                // Standing on the anchor: the two upper positions, then straight above it.
                set.count = 3;
                set.offset[0] = kFourPositions[0] * d;
                set.offset[1] = kFourPositions[1] * d;
                set.offset[2] = glm::vec2(0.0F, -d.y);
                break;
            }
            set.count = 4;
            for (int k = 0; k < 4; ++k) {
                set.offset[k] = kFourPositions[k] * d;
            }
            break;
        }
        case LabelKind::Circle: {
            const float r = circleRadius(radius, half, params);
            set.count = 4;
            for (int k = 0; k < 4; ++k) {
                set.offset[k] = glm::normalize(kFourPositions[k]) * r;
            }
            break;
        }
        case LabelKind::Line: {
            // seed 4.4.3: three offset OOBBs, rotated along s'_i or horizontal (Fig. 4.3(b, c)).
            const float d = half.y + params.line_gap_px;
            const glm::vec2 normal = rotated ? glm::vec2(-dir.y, dir.x) : glm::vec2(0.0F, 1.0F);
            // The normal side with negative screen y is "above".
            const float above = normal.y > 0.0F ? -d : d;
            if (upright) {
                // Standing on the line, or one line higher (a sign above the road): never in it.
                const float higher = above * (1.0F + (2.0F * half.y + params.line_gap_px) / d);
                set.count = 2;
                set.d_optimum[0] = above;
                set.d_optimum[1] = higher;
                set.offset[0] = normal * above;
                set.offset[1] = normal * higher;
                break;
            }
            const float dist[3] = {above, -above, 0.0F};
            set.count = 3;
            for (int k = 0; k < 3; ++k) {
                set.d_optimum[k] = dist[k];
                set.offset[k] = normal * dist[k];
            }
            break;
        }
    }
    return set;
}

}  // namespace navmap::render::labels
