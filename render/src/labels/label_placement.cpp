// SPDX-License-Identifier: Apache-2.0
// Initial placement of LabelLayout (seed 4.4.3, 4.5.3): the queued labels by priority, each at
// the first of its candidates whose placement zone is free of the placed labels, the labels
// fading out and the keep-out areas, now and (look-ahead) a moment from now.
#include <algorithm>

#include <glm/common.hpp>

#include "candidate_positions.h"
#include "layout_internal.h"
#include "navmap/render/labels/label_layout.h"

namespace navmap::render::labels {

/// What place() knows while it tries the candidates of the queued labels.
struct LabelLayout::Placement {
    bool bounded = false;     ///< the viewport bounds the labels
    float zone_extra = 0.0F;  ///< placement zone beyond the force buffer
    /// The look-ahead asks the grid of placed labels (built at their current places) for those
    /// that come within reach: each moves by at most max |anchor velocity| * t per axis.
    glm::vec2 max_speed{-1.0F};  ///< found when the first candidate gets that far
    // Of the label being placed: why its candidates were not free.
    bool in_view = false;
    bool kept_out = false;
    bool leaves_view = false;  ///< a candidate in the view now would leave it straight away
};

void LabelLayout::place() {
    const std::size_t k = queuePlacements();
    if (k == 0) {
        return;
    }
    Placement p;
    p.bounded = m_camera.viewport.x > 0.0F && m_camera.viewport.y > 0.0F;
    collectFading();
    // seed 4.5.3: new labels keep a larger zone around placed ones than the force buffer.
    p.zone_extra = m_params.placement_zone_px - m_params.buffer_px;
    m_placed_now.clear();
    m_placed_grid.reset(m_grid.cellSize());
    for (std::size_t q = 0; q < k; ++q) {
        placeLabel(m_labels[m_queue[q]], p);
    }
    m_placed_cells += m_placed_grid.cellsVisited();
}

std::size_t LabelLayout::queuePlacements() {
    m_queue.clear();
    for (std::size_t i = 0; i < m_labels.size(); ++i) {
        const Label& l = m_labels[i];
        if (l.present && (l.state == LabelState::Pending || (l.state == LabelState::Waiting && l.timer <= 0.0F))) {
            m_queue.push_back(static_cast<std::uint32_t>(i));
        }
    }
    if (m_queue.empty() || m_params.max_placements_per_step == 0) {
        return 0;
    }
    // seed 4.4.3: placement ordered by priority (ties by id), a fixed number per step (4.5).
    const std::size_t k = std::min(m_queue.size(), static_cast<std::size_t>(m_params.max_placements_per_step));
    std::partial_sort(m_queue.begin(), m_queue.begin() + static_cast<std::ptrdiff_t>(k), m_queue.end(),
                      [this](std::uint32_t a, std::uint32_t b) {
                          const LabelCandidate& x = m_labels[a].in;
                          const LabelCandidate& y = m_labels[b].in;
                          return x.priority != y.priority ? x.priority > y.priority : x.id < y.id;
                      });
    return k;
}

void LabelLayout::collectFading() {
    // Labels still fading out are drawn: a new one must not appear on top of them either.
    m_fading_boxes.clear();
    m_fading_centers.clear();
    m_fading_aabb.clear();
    for (const Label& f : m_labels) {
        if (f.state == LabelState::FadingOut && f.alpha > 0.0F) {
            const OrientedBox box = textBox(f).inflated(m_params.buffer_px);
            m_fading_boxes.push_back(box);
            m_fading_centers.push_back(box.center);
            m_fading_aabb.push_back(box.aabbHalfExtents());
        }
    }
    m_fading_grid.build(m_fading_centers, m_fading_aabb, m_grid.cellSize());
}

void LabelLayout::placeLabel(Label& l, Placement& p) {
    updateShape(l, true);
    const CandidateSet cs =
        candidatePositions(l.in.kind, l.half, l.rotated, l.dir, l.in.circle_radius, m_params, l.in.upright);
    const glm::vec2 axis = l.axis;
    int chosen = -1;
    p.in_view = false;
    p.kept_out = false;
    p.leaves_view = false;
    for (int c = 0; c < cs.count && chosen < 0; ++c) {
        if (candidateFree(l, OrientedBox{l.in.anchor + cs.offset[c], l.half, axis}, p)) {
            chosen = c;  // the first free one has the best visual association [Yoe72]
        }
    }
    if (chosen < 0) {
        // seed 4.4.3: not added; a timer re-evaluates the placement later.
        l.state = LabelState::Waiting;
        l.timer = retryDelay(l.in.id);
        ++m_stats.placement_failures;
        const bool off_screen = !p.in_view || (p.leaves_view && !p.kept_out);
        l.held_by = off_screen   ? RemovalReason::OffScreen
                    : p.kept_out ? RemovalReason::KeepOut
                                 : RemovalReason::Overlap;
        ++(off_screen ? m_stats.failures_off_screen : p.kept_out ? m_stats.failures_keep_out : m_stats.failures_labels);
        return;
    }
    l.state = LabelState::FadingIn;
    l.reason = RemovalReason::None;
    l.placed_at_s = timeS();
    l.candidate = static_cast<std::uint8_t>(chosen);
    l.offset = cs.offset[chosen];
    l.velocity = glm::vec2(0.0F);
    l.overlap_time = 0.0F;
    l.constricted_time = 0.0F;
    ++m_stats.placed;
    m_placed_now.push_back(textBox(l).inflated(m_params.buffer_px));
    m_placed_grid.insert(m_placed_now.back().center, m_placed_now.back().aabbHalfExtents());
}

bool LabelLayout::candidateFree(const Label& l, const OrientedBox& text, Placement& p) {
    if (p.bounded) {
        const glm::vec2 h = text.aabbHalfExtents();
        const glm::vec2 lo = text.center - h;
        const glm::vec2 hi = text.center + h;
        if (lo.x < 0.0F || lo.y < 0.0F || hi.x > m_camera.viewport.x || hi.y > m_camera.viewport.y) {
            return false;
        }
    }
    p.in_view = true;
    const OrientedBox zone = text.inflated(p.zone_extra);
    const glm::vec2 zone_h = zone.aabbHalfExtents();
    bool free = true;
    m_grid.query(zone.center, zone_h + kTouchSlack, [&](std::uint32_t a) {
        if (!free || !placed(m_labels[m_active[a]].state)) return;
        ++m_pair_tests;
        free = satDepth(zone, m_boxes[a]) < 0.0F;
    });
    if (free) {
        m_placed_grid.query(zone.center, zone_h + kTouchSlack, [&](std::uint32_t o) {
            if (!free) return;
            ++m_pair_tests;
            free = satDepth(zone, m_placed_now[o]) < 0.0F;
        });
    }
    if (free && touchesAny(zone, m_keep_out, m_keep_out_aabb)) {
        free = false;
        p.kept_out = true;
    }
    if (free) {
        m_fading_grid.query(zone.center, zone_h + kTouchSlack, [&](std::uint32_t f) {
            if (!free) return;
            ++m_pair_tests;
            free = satDepth(zone, m_fading_boxes[f]) < 0.0F;
        });
    }
    if (free && m_params.placement_lookahead_s > 0.0F) {
        free = freeAhead(l, text, p);
    }
    return free;
}

bool LabelLayout::freeAhead(const Label& l, const OrientedBox& text, Placement& p) {
    // Where the anchors' motion carries it and the placed labels a moment from now.
    bool free = true;
    for (int n = 1; n <= 3 && free; ++n) {
        const float t = m_params.placement_lookahead_s * static_cast<float>(n) / 3.0F;
        const OrientedBox later{text.center + l.anchor_velocity * t, text.half_extents, text.axis};
        if (p.bounded) {
            const glm::vec2 h = later.aabbHalfExtents();
            if (later.center.x - h.x < 0.0F || later.center.y - h.y < 0.0F ||
                later.center.x + h.x > m_camera.viewport.x || later.center.y + h.y > m_camera.viewport.y) {
                p.leaves_view = true;
                return false;
            }
        }
        if (p.max_speed.x < 0.0F) {
            p.max_speed = maxPlacedAnchorSpeed();
        }
        const OrientedBox later_zone = later.inflated(m_params.buffer_px);
        const glm::vec2 later_h = later_zone.aabbHalfExtents();
        m_grid.query(later_zone.center, later_h + p.max_speed * t + kTouchSlack, [&](std::uint32_t a) {
            const Label& o = m_labels[m_active[a]];
            if (!free || !placed(o.state)) return;
            ++m_pair_tests;
            const glm::vec2 oc = m_boxes[a].center + o.anchor_velocity * t;
            const glm::vec2 gap = glm::abs(oc - later_zone.center) - m_aabb[a] - later_h;
            if (gap.x > 0.0F || gap.y > 0.0F) return;  // bounding boxes apart: no SAT
            free = satDepth(later_zone, OrientedBox{oc, m_boxes[a].half_extents, m_boxes[a].axis}) < 0.0F;
        });
        if (free && touchesAny(later_zone, m_keep_out, m_keep_out_aabb)) {
            free = false;
            p.kept_out = true;
        }
    }
    return free;
}

glm::vec2 LabelLayout::maxPlacedAnchorSpeed() const {
    glm::vec2 max_speed{0.0F};
    for (const std::uint32_t i : m_active) {
        if (placed(m_labels[i].state)) {
            max_speed = glm::max(max_speed, glm::abs(m_labels[i].anchor_velocity));
        }
    }
    return max_speed;
}

}  // namespace navmap::render::labels
