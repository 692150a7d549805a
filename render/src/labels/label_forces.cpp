// SPDX-License-Identifier: Apache-2.0
// One step of the force simulation of LabelLayout (seed 4.4.4-4.5.3): collision forces between
// the placed labels' buffered boxes on the grid, behavior forces, Euler step, and the removal
// of labels that move too fast, are constricted, overlap a more important one or leave the view.
#include <algorithm>

#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include "candidate_positions.h"
#include "collision_force.h"
#include "label_behavior.h"
#include "layout_internal.h"
#include "navmap/render/labels/label_layout.h"

namespace navmap::render::labels {

void LabelLayout::integrate(float dt) {
    collectActive();
    buildForceGrid();
    collisionForces();
    keepOutForces();
    for (std::size_t a = 0; a < m_active.size(); ++a) {
        moveLabel(a, dt);
    }
}

void LabelLayout::collectActive() {
    m_active.clear();
    for (std::size_t i = 0; i < m_labels.size(); ++i) {
        Label& l = m_labels[i];
        if (placed(l.state)) {
            updateShape(l, false);
            m_active.push_back(static_cast<std::uint32_t>(i));
        } else if (l.state == LabelState::FadingOut && l.present) {
            updateShape(l, false);  // keeps following depth and segment while it fades
        }
    }
}

void LabelLayout::buildForceGrid() {
    const std::size_t n = m_active.size();
    m_boxes.resize(n);
    m_centers.resize(n);
    m_aabb.resize(n);
    m_force.assign(n, glm::vec2(0.0F));
    m_force_abs.assign(n, 0.0F);
    m_overlapped.assign(n, 0U);

    // seed 4.5.3: forces act on slightly enlarged OOBBs (buffer zone).
    glm::vec2 extent_sum{0.0F};
    for (std::size_t a = 0; a < n; ++a) {
        const OrientedBox box = textBox(m_labels[m_active[a]]).inflated(m_params.buffer_px);
        m_boxes[a] = box;
        m_centers[a] = box.center;
        m_aabb[a] = box.aabbHalfExtents();
        extent_sum += m_aabb[a];
    }
    glm::vec2 cell{m_params.grid_cell_px};
    if (m_params.grid_cell_px <= 0.0F) {
        // Cells the size of a mean label (2 x mean half extent): a box covers about 4 cells.
        cell = n > 0 ? glm::max(extent_sum * (2.0F / static_cast<float>(n)), glm::vec2(8.0F)) : glm::vec2(64.0F);
    }
    glm::vec2 clip_lo{-1e7F};
    glm::vec2 clip_hi{1e7F};
    if (m_camera.viewport.x > 0.0F && m_camera.viewport.y > 0.0F) {
        clip_lo = -0.5F * m_camera.viewport;
        clip_hi = 1.5F * m_camera.viewport;
    }
    m_grid.build(m_centers, m_aabb, cell, clip_lo, clip_hi);
}

void LabelLayout::collisionForces() {
    // Broad phase on the grid, narrow phase SAT (seed 4.4.4), force eq. 4.5 summed per label
    // (eq. 4.6). The pair order is fixed by the grid, so the float sums are reproducible.
    std::size_t pairs = 0;
    std::size_t collisions = 0;
    // Inflating both boxes adds at least 2 * buffer to the depth: beyond `pressing_depth` the
    // text boxes are closer than one buffer width. A label held there by its spring against a
    // more important one for overlap_removal_s fades out before the two can overlap (the hard
    // rule of resolveOverlaps() would then drop it at once).
    const float pressing_depth = m_params.buffer_px;
    m_grid.forEachPair([&](std::uint32_t a, std::uint32_t b) {
        ++pairs;
        // a < b in id order; on coincident centers the lower id goes up.
        const Collision hit = collide(m_boxes[a], m_boxes[b], -1.0F);
        if (!hit.hit) {
            return;
        }
        ++collisions;
        const float depth = hit.depth;
        const glm::vec2 f = hit.force;
        m_force[a] += f;
        m_force[b] -= f;  // f^(k,n) = -f^(n,k) (Table 4.1)
        const float mag = glm::length(f);
        m_force_abs[a] += mag;
        m_force_abs[b] += mag;
        if (depth > pressing_depth) {
            const Label& la = m_labels[m_active[a]];
            const Label& lb = m_labels[m_active[b]];
            m_overlapped[yields(la, lb) ? a : b] = 1U;
        }
    });
    m_stats.last_pairs = pairs;
    m_stats.last_collisions = collisions;
    m_pair_tests += pairs;
    m_sat_tests += pairs;
}

void LabelLayout::keepOutForces() {
    // Keep-out areas (the vehicle marker, the route ahead) push like a label that never moves.
    for (const OrientedBox& k : m_keep_out) {
        const OrientedBox zone = k.inflated(m_params.buffer_px);
        m_grid.query(zone.center, zone.aabbHalfExtents(), [&](std::uint32_t a) {
            ++m_pair_tests;
            ++m_sat_tests;
            const Collision hit = collide(m_boxes[a], zone, -1.0F);
            if (!hit.hit) return;
            m_force[a] += hit.force;
            m_force_abs[a] += glm::length(hit.force);
        });
    }
}

glm::vec2 LabelLayout::behaviorForce(const Label& l) const {
    switch (l.in.kind) {
        case LabelKind::Point:
        case LabelKind::Area: {
            const CandidateSet cs = candidatePositions(l.in.kind, l.half, false, l.dir, 0.0F, m_params, l.in.upright);
            return freeForce(l.offset, cs.offset[l.candidate], m_params.k_feature);  // eq. 4.7
        }
        case LabelKind::Line: {
            const CandidateSet cs =
                candidatePositions(l.in.kind, l.half, l.rotated, l.dir, 0.0F, m_params, l.in.upright);
            return l.rotated ? lineForce(l.offset, l.dir, cs.d_optimum[l.candidate], m_params.k_normal,
                                         m_params.k_tangent)  // eq. 4.10-4.15
                             : freeForce(l.offset, cs.offset[l.candidate], m_params.k_feature);
        }
        case LabelKind::Circle:
            return circleForce(l.offset, circleRadius(l.in.circle_radius, l.half, m_params),
                               m_params.k_circle);  // eq. 4.17
    }
    return glm::vec2{0.0F};
}

void LabelLayout::moveLabel(std::size_t a, float dt) {
    Label& l = m_labels[m_active[a]];
    const glm::vec2 f_behavior = behaviorForce(l);
    // eq. 4.9 / 4.16 / 4.18: collision + behavior + friction.
    const glm::vec2 total =
        m_params.collision_gain * m_force[a] + f_behavior + frictionForce(l.velocity, m_params.friction);
    const Motion m = eulerStep({l.offset, l.velocity}, total, l.mass, m_params.max_accel, dt);
    l.offset = m.offset;
    l.velocity = m.velocity;

    // seed 4.5.3: speed-based removal (relative to the anchor; optionally the anchor's own
    // screen speed too), removal of constricted labels, and of labels stuck on a more
    // important one.
    if (glm::length(l.velocity) > m_params.removal_speed_px_s ||
        (m_params.max_anchor_speed_px_s > 0.0F && l.anchor_speed > m_params.max_anchor_speed_px_s)) {
        remove(l, RemovalReason::Speed);
        return;
    }
    const float sum_abs = m_force_abs[a];
    const bool constricted =
        sum_abs >= m_params.constricted_min_force && glm::length(m_force[a]) <= m_params.constricted_ratio * sum_abs;
    l.constricted_time = constricted ? l.constricted_time + dt : 0.0F;
    if (constricted && l.constricted_time > m_params.constricted_time_s) {
        remove(l, RemovalReason::Constricted);
        return;
    }
    // Text the viewport would cut fades out; it comes back where it fits (placement).
    if (m_camera.viewport.x > 0.0F && m_camera.viewport.y > 0.0F) {
        const OrientedBox box = textBox(l);
        const glm::vec2 h = box.aabbHalfExtents();
        if (box.center.x - h.x < -1.0F || box.center.y - h.y < -1.0F ||
            box.center.x + h.x > m_camera.viewport.x + 1.0F || box.center.y + h.y > m_camera.viewport.y + 1.0F) {
            remove(l, RemovalReason::OffScreen);
            return;
        }
    }
    // Decays instead of resetting, so an overlap that flickers on and off still counts.
    l.overlap_time = m_overlapped[a] != 0U ? l.overlap_time + dt : std::max(0.0F, l.overlap_time - dt);
    if (m_overlapped[a] != 0U && l.overlap_time > m_params.overlap_removal_s) {
        remove(l, RemovalReason::Overlap);
    }
}

}  // namespace navmap::render::labels
