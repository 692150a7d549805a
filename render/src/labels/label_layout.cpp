// SPDX-License-Identifier: Apache-2.0
#include "navmap/render/labels/label_layout.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <numbers>
#include <sstream>

#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include "candidate_positions.h"
#include "collision_force.h"
#include "label_behavior.h"

namespace navmap::render::labels {

namespace {

constexpr float kRadToDeg = 180.0F / std::numbers::pi_v<float>;
constexpr float kDegToRad = std::numbers::pi_v<float> / 180.0F;
constexpr float kAnchorSpeedTau = 0.1F;  // s, low-pass of the measured anchor speed

// Input bounds: far beyond any screen, small enough that sums and squares stay finite.
constexpr float kMaxCoord = 1e6F;
constexpr float kMinSize = 0.5F;
constexpr float kMaxSize = 1e5F;

// Boxes whose bounding boxes are further apart than this skip the separating-axis test; the
// margin stays above the test's own rounding, so the outcome equals testing every pair.
constexpr float kTouchSlack = 0.05F;

bool apart(glm::vec2 ca, glm::vec2 ha, glm::vec2 cb, glm::vec2 hb) {
    const glm::vec2 gap = glm::abs(ca - cb) - ha - hb;
    return gap.x > kTouchSlack || gap.y > kTouchSlack;
}

bool finite(glm::vec2 v) { return std::isfinite(v.x) && std::isfinite(v.y); }

// A finite float as an unsigned key that sorts in the float's descending order (-0 = +0).
std::uint64_t descendingBits(float f) {
    const std::uint32_t u = std::bit_cast<std::uint32_t>(f + 0.0F);
    const std::uint32_t ascending = (u & 0x80000000U) != 0U ? ~u : (u | 0x80000000U);
    return ~ascending;
}
bool inRange(glm::vec2 v, float limit) { return std::abs(v.x) <= limit && std::abs(v.y) <= limit; }  // false for NaN

bool placed(LabelState s) { return s == LabelState::FadingIn || s == LabelState::Visible; }

std::uint64_t splitmix64(std::uint64_t x) {
    x += 0x9E3779B97F4A7C15ULL;
    x = (x ^ (x >> 30U)) * 0xBF58476D1CE4E5B9ULL;
    x = (x ^ (x >> 27U)) * 0x94D049BB133111EBULL;
    return x ^ (x >> 31U);
}

std::string describe(const LabelCandidate& c, const char* what, glm::vec2 v) {
    std::ostringstream s;
    s << "label id " << c.id << ": " << what << " (" << v.x << ", " << v.y << ")";
    return s.str();
}

// Empty when the candidate is usable.
std::string checkCandidate(const LabelCandidate& c) {
    if (!inRange(c.anchor, kMaxCoord)) return describe(c, "non-finite or out-of-range anchor", c.anchor);
    if (!finite(c.size) || c.size.x < kMinSize || c.size.y < kMinSize || c.size.x > kMaxSize || c.size.y > kMaxSize) {
        return describe(c, "size must be within [0.5, 1e5] px", c.size);
    }
    if (!std::isfinite(c.priority)) return describe(c, "non-finite priority", {c.priority, 0.0F});
    if (!std::isfinite(c.depth)) return describe(c, "non-finite depth", {c.depth, 0.0F});
    if (c.kind == LabelKind::Line && (!inRange(c.line_p0, kMaxCoord) || !inRange(c.line_p1, kMaxCoord))) {
        return describe(c, "non-finite or out-of-range line segment start", c.line_p0) + " end (" +
               std::to_string(c.line_p1.x) + ", " + std::to_string(c.line_p1.y) + ")";
    }
    if (!finite(c.axis) || (c.axis != glm::vec2(0.0F) && std::abs(glm::length(c.axis) - 1.0F) > 1e-3F)) {
        return describe(c, "axis must be zero or a unit vector", c.axis);
    }
    if (!(std::abs(c.cap_height) <= kMaxSize)) return describe(c, "non-finite cap height", {c.cap_height, 0.0F});
    if (c.kind == LabelKind::Circle && !(std::abs(c.circle_radius) <= kMaxSize)) {
        return describe(c, "non-finite or out-of-range circle radius", {c.circle_radius, 0.0F});
    }
    if (static_cast<unsigned>(c.kind) > static_cast<unsigned>(LabelKind::Circle)) {
        return describe(c, "unknown kind", {static_cast<float>(c.kind), 0.0F});
    }
    return {};
}

}  // namespace

LabelLayout::LabelLayout(LayoutParams params) : m_params(params) {
    if (std::string err = m_params.validate(); !err.empty()) {
        throw LabelLayoutError("LabelLayout: " + err);
    }
}

FrameReport LabelLayout::setFrame(std::span<const LabelCandidate> candidates, const CameraState& camera) {
    FrameReport report;
    m_camera = camera;
    if (!inRange(m_camera.viewport, kMaxCoord) || m_camera.viewport.x < 0.0F || m_camera.viewport.y < 0.0F) {
        report.first_error = "camera viewport (" + std::to_string(camera.viewport.x) + ", " +
                             std::to_string(camera.viewport.y) + ") must be within [0, 1e6] px; treated as unbounded";
        m_camera.viewport = glm::vec2(0.0F);
    }
    if (!std::isfinite(m_camera.depth_reference_m) || m_camera.depth_reference_m > kMaxCoord) {
        if (report.first_error.empty()) report.first_error = "camera depth_reference_m is not finite";
        m_camera.depth_reference_m = 0.0F;
    }
    if (!std::isfinite(m_camera.tilt_deg)) {
        if (report.first_error.empty()) report.first_error = "camera tilt_deg is not finite";
        m_camera.tilt_deg = 0.0F;
    }

    m_sorted.clear();
    for (const LabelCandidate& c : candidates) {
        if (std::string err = checkCandidate(c); !err.empty()) {
            ++report.rejected;
            if (report.first_error.empty()) report.first_error = std::move(err);
            continue;
        }
        m_sorted.push_back(c);
    }
    const auto by_id = [](const LabelCandidate& a, const LabelCandidate& b) { return a.id < b.id; };
    if (!std::is_sorted(m_sorted.begin(), m_sorted.end(), by_id)) {
        std::stable_sort(m_sorted.begin(), m_sorted.end(), by_id);
    }
    // Duplicate ids: the first one wins.
    const auto dup =
        std::adjacent_find(m_sorted.begin(), m_sorted.end(), [](const auto& a, const auto& b) { return a.id == b.id; });
    if (dup != m_sorted.end()) {
        const std::size_t before = m_sorted.size();
        if (report.first_error.empty()) {
            report.first_error = "label id " + std::to_string(dup->id) + ": duplicate id in one frame";
        }
        m_sorted.erase(
            std::unique(m_sorted.begin(), m_sorted.end(), [](const auto& a, const auto& b) { return a.id == b.id; }),
            m_sorted.end());
        report.rejected += before - m_sorted.size();
    }
    report.accepted = m_sorted.size();
    m_stats.rejected_inputs += report.rejected;

    // Merge the id-sorted input with the id-sorted labels: O(n), no hashing, stable order.
    m_next.clear();
    m_next.reserve(m_labels.size() + m_sorted.size());
    std::size_t i = 0;
    std::size_t j = 0;
    while (i < m_labels.size() || j < m_sorted.size()) {
        if (j == m_sorted.size() || (i < m_labels.size() && m_labels[i].in.id < m_sorted[j].id)) {
            Label l = m_labels[i++];
            l.present = false;
            if (placed(l.state)) {
                l.state = LabelState::FadingOut;  // seed 4.4.3: removed labels fade out
                l.reason = RemovalReason::Gone;
                l.held_by = RemovalReason::Gone;
                ++m_stats.removed_gone;
                l.velocity = glm::vec2(0.0F);
            } else if (l.state != LabelState::FadingOut) {
                continue;  // never shown: forget at once
            }
            m_next.push_back(l);
        } else if (i == m_labels.size() || m_sorted[j].id < m_labels[i].in.id) {
            Label l;
            l.in = m_sorted[j++];
            l.anchor_prev = l.in.anchor;
            m_next.push_back(l);
        } else {
            Label l = m_labels[i++];
            l.in = m_sorted[j++];
            if (!l.present) {
                l.anchor_prev = l.in.anchor;
                l.anchor_velocity = glm::vec2(0.0F);
            }
            l.present = true;
            if (l.state == LabelState::FadingOut && l.reason == RemovalReason::Gone) {
                // Back before it faded away (e.g. culling flicker): fade in from where it is.
                l.state = LabelState::FadingIn;
                l.reason = RemovalReason::None;
            }
            m_next.push_back(l);
        }
    }
    m_labels.swap(m_next);
    return report;
}

int LabelLayout::advance(double dt_s) {
    if (!std::isfinite(dt_s) || dt_s < 0.0) {
        return 0;
    }
    m_pair_tests = 0;
    m_sat_tests = 0;
    m_placed_cells = 0;
    m_grid.resetWork();
    m_fading_grid.resetWork();
    m_rank_grid.resetWork();
    if (dt_s > 0.0) {
        // Anchor speed on screen between frames (optional speed-based removal, seed 4.5.3).
        const float dt = static_cast<float>(dt_s);
        const float k = std::min(1.0F, dt / kAnchorSpeedTau);
        for (Label& l : m_labels) {
            if (!l.present) continue;
            const glm::vec2 v = (l.in.anchor - l.anchor_prev) / dt;
            l.anchor_velocity += (v - l.anchor_velocity) * k;
            const float inst = glm::length(v);
            l.anchor_speed += (inst - l.anchor_speed) * k;
            l.anchor_prev = l.in.anchor;
        }
    }
    // Steps are due at multiples of step_s of accumulated frame time. Counting them from the
    // total (instead of subtracting from a remainder) keeps 2 x 1/120 s or 1/30 s frames on
    // exactly the same steps as 1/60 s frames; the epsilon absorbs the rounding of dt sums.
    m_frame_time_s += std::min(dt_s, 10.0);
    const auto due = static_cast<std::int64_t>(std::floor(m_frame_time_s / m_params.step_s + 1e-6));
    int steps = 0;
    while (m_steps_done < due && steps < m_params.max_steps_per_advance) {
        step();
        ++m_steps_done;
        ++steps;
    }
    m_steps_done = due;  // too far behind: drop the rest instead of spiralling
    resolveOverlaps();
    updateOutput();
    m_stats.last_pair_tests = m_pair_tests;
    m_stats.last_sat_tests = m_sat_tests;
    m_stats.last_grid_cells =
        m_grid.cellsVisited() + m_fading_grid.cellsVisited() + m_rank_grid.cellsVisited() + m_placed_cells;
    return steps;
}

void LabelLayout::step() {
    const float dt = static_cast<float>(m_params.step_s);
    ++m_stats.steps;
    integrate(dt);
    place();
    fade(dt);
    if (std::any_of(m_labels.begin(), m_labels.end(), [](const Label& l) { return l.dead; })) {
        m_labels.erase(std::remove_if(m_labels.begin(), m_labels.end(), [](const Label& l) { return l.dead; }),
                       m_labels.end());
    }
}

void LabelLayout::updateShape(Label& l, bool placing) const {
    const LabelCandidate& in = l.in;
    // seed 4.3.3: scale by depth, but never below a readable size.
    float s = 1.0F;
    if (in.depth > 0.0F) {
        const float reference =
            m_camera.depth_reference_m > 0.0F ? m_camera.depth_reference_m : m_params.depth_reference_m;
        s = std::clamp(reference / in.depth, m_params.min_scale, m_params.max_scale);
        const float cap = in.cap_height > 0.0F ? in.cap_height : 0.7F * in.size.y;
        s = std::max(s, m_params.min_cap_height_px / cap);
    }
    l.scale = s;
    l.half = in.size * (0.5F * s);
    l.mass = massFromPriority(in.priority, m_params.mass_min, m_params.mass_max);

    if (in.axis != glm::vec2(0.0F)) {
        // World-space text: the projection gives the baseline; the box follows it exactly.
        l.rotated = in.kind == LabelKind::Line;
        l.axis = in.axis;
        l.angle = std::atan2(in.axis.y, in.axis.x);
        if (in.kind == LabelKind::Line) {
            const glm::vec2 d = in.line_p1 - in.line_p0;
            const float len = glm::length(d);
            l.dir = len > 1e-3F ? d / len : in.axis;
            if (glm::dot(l.dir, in.axis) < 0.0F) l.dir = -l.dir;
        }
        return;
    }
    if (in.kind != LabelKind::Line) {
        l.rotated = false;
        l.angle = 0.0F;  // points, areas and circles are always horizontal (seed 4.4.2)
        l.axis = {1.0F, 0.0F};
        return;
    }
    glm::vec2 d = in.line_p1 - in.line_p0;
    const float len = glm::length(d);
    d = len > 1e-3F ? d / len : glm::vec2(1.0F, 0.0F);
    if (d.x < 0.0F || (d.x == 0.0F && d.y < 0.0F)) {
        d = -d;  // text reads left to right, never upside down
    }
    l.dir = d;
    const float seg_deg = std::atan2(d.y, d.x) * kRadToDeg;
    // seed 4.3.3/4.4.3: rotated along the segment unless the view (or the segment on screen)
    // is too steep; hysteresis keeps a label from flipping between the two.
    const float h = placing ? 0.0F : (l.rotated ? m_params.rotate_hysteresis_deg : -m_params.rotate_hysteresis_deg);
    l.rotated =
        m_camera.tilt_deg <= m_params.rotate_max_tilt_deg + h && std::abs(seg_deg) <= m_params.max_rotation_deg + h;
    const float target = l.rotated ? seg_deg * kDegToRad : 0.0F;
    const float before = l.angle;
    if (placing) {
        l.angle = target;
    } else {
        const float max_turn = m_params.angular_speed_deg_s * kDegToRad * static_cast<float>(m_params.step_s);
        l.angle += std::clamp(target - l.angle, -max_turn, max_turn);
    }
    if (placing || l.angle != before) {
        l.axis = {std::cos(l.angle), std::sin(l.angle)};  // cached: trig only when it turns
    }
}

OrientedBox LabelLayout::textBox(const Label& l) const { return OrientedBox{l.in.anchor + l.offset, l.half, l.axis}; }

float LabelLayout::retryDelay(std::uint64_t id) const {
    // Stagger retries by id so that removed labels do not all come back in the same step.
    const float u = static_cast<float>(splitmix64(id) >> 40U) / static_cast<float>(1U << 24U);
    return m_params.retry_delay_s * (1.0F + 0.25F * u);
}

bool LabelLayout::established(const Label& l) const {
    return m_params.established_s >= 0.0F && l.state == LabelState::Visible &&
           timeS() - l.placed_at_s >= static_cast<double>(m_params.established_s);
}

bool LabelLayout::yields(const Label& a, const Label& b) const {
    const bool ea = established(a), eb = established(b);
    if (ea != eb) return eb;
    if (a.in.priority != b.in.priority) return a.in.priority < b.in.priority;
    return a.in.id > b.in.id;
}

void LabelLayout::remove(Label& l, RemovalReason why) {
    l.state = LabelState::FadingOut;
    l.reason = why;
    l.held_by = why;
    l.velocity = glm::vec2(0.0F);
    l.timer = retryDelay(l.in.id);  // seed 4.5.3: re-inserted after a given time if there is room
    l.overlap_time = 0.0F;
    l.constricted_time = 0.0F;
    switch (why) {
        case RemovalReason::Speed: ++m_stats.removed_speed; break;
        case RemovalReason::Constricted: ++m_stats.removed_constricted; break;
        case RemovalReason::Overlap: ++m_stats.removed_overlap; break;
        case RemovalReason::OffScreen: ++m_stats.removed_off_screen; break;
        case RemovalReason::KeepOut:
            ++m_stats.removed_overlap;
            ++m_stats.removed_keep_out;
            break;
        case RemovalReason::None:
        case RemovalReason::Gone: break;
    }
}

void LabelLayout::integrate(float dt) {
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

    for (std::size_t a = 0; a < n; ++a) {
        Label& l = m_labels[m_active[a]];
        glm::vec2 f_behavior{0.0F};
        switch (l.in.kind) {
            case LabelKind::Point:
            case LabelKind::Area: {
                const CandidateSet cs =
                    candidatePositions(l.in.kind, l.half, false, l.dir, 0.0F, m_params, l.in.upright);
                f_behavior = freeForce(l.offset, cs.offset[l.candidate], m_params.k_feature);  // eq. 4.7
                break;
            }
            case LabelKind::Line: {
                const CandidateSet cs =
                    candidatePositions(l.in.kind, l.half, l.rotated, l.dir, 0.0F, m_params, l.in.upright);
                f_behavior = l.rotated ? lineForce(l.offset, l.dir, cs.d_optimum[l.candidate], m_params.k_normal,
                                                   m_params.k_tangent)  // eq. 4.10-4.15
                                       : freeForce(l.offset, cs.offset[l.candidate], m_params.k_feature);
                break;
            }
            case LabelKind::Circle:
                f_behavior = circleForce(l.offset, circleRadius(l.in.circle_radius, l.half, m_params),
                                         m_params.k_circle);  // eq. 4.17
                break;
        }
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
            continue;
        }
        const float sum_abs = m_force_abs[a];
        const bool constricted = sum_abs >= m_params.constricted_min_force &&
                                 glm::length(m_force[a]) <= m_params.constricted_ratio * sum_abs;
        l.constricted_time = constricted ? l.constricted_time + dt : 0.0F;
        if (constricted && l.constricted_time > m_params.constricted_time_s) {
            remove(l, RemovalReason::Constricted);
            continue;
        }
        // Text the viewport would cut fades out; it comes back where it fits (placement).
        if (m_camera.viewport.x > 0.0F && m_camera.viewport.y > 0.0F) {
            const OrientedBox box = textBox(l);
            const glm::vec2 h = box.aabbHalfExtents();
            if (box.center.x - h.x < -1.0F || box.center.y - h.y < -1.0F ||
                box.center.x + h.x > m_camera.viewport.x + 1.0F || box.center.y + h.y > m_camera.viewport.y + 1.0F) {
                remove(l, RemovalReason::OffScreen);
                continue;
            }
        }
        // Decays instead of resetting, so an overlap that flickers on and off still counts.
        l.overlap_time = m_overlapped[a] != 0U ? l.overlap_time + dt : std::max(0.0F, l.overlap_time - dt);
        if (m_overlapped[a] != 0U && l.overlap_time > m_params.overlap_removal_s) {
            remove(l, RemovalReason::Overlap);
        }
    }
}

void LabelLayout::place() {
    m_queue.clear();
    for (std::size_t i = 0; i < m_labels.size(); ++i) {
        const Label& l = m_labels[i];
        if (l.present && (l.state == LabelState::Pending || (l.state == LabelState::Waiting && l.timer <= 0.0F))) {
            m_queue.push_back(static_cast<std::uint32_t>(i));
        }
    }
    if (m_queue.empty() || m_params.max_placements_per_step == 0) {
        return;
    }
    // seed 4.4.3: placement ordered by priority (ties by id), a fixed number per step (4.5).
    const std::size_t k = std::min(m_queue.size(), static_cast<std::size_t>(m_params.max_placements_per_step));
    std::partial_sort(m_queue.begin(), m_queue.begin() + static_cast<std::ptrdiff_t>(k), m_queue.end(),
                      [this](std::uint32_t a, std::uint32_t b) {
                          const LabelCandidate& x = m_labels[a].in;
                          const LabelCandidate& y = m_labels[b].in;
                          return x.priority != y.priority ? x.priority > y.priority : x.id < y.id;
                      });
    const bool bounded = m_camera.viewport.x > 0.0F && m_camera.viewport.y > 0.0F;
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
    // The look-ahead asks the grid of placed labels (built at their current places) for those
    // that come within reach: each moves by at most max |anchor velocity| * t per axis.
    glm::vec2 max_speed{-1.0F};  // found when the first candidate gets that far
    // seed 4.5.3: new labels keep a larger zone around placed ones than the force buffer.
    const float zone_extra = m_params.placement_zone_px - m_params.buffer_px;
    m_placed_now.clear();
    m_placed_grid.reset(m_grid.cellSize());
    for (std::size_t q = 0; q < k; ++q) {
        Label& l = m_labels[m_queue[q]];
        updateShape(l, true);
        const CandidateSet cs =
            candidatePositions(l.in.kind, l.half, l.rotated, l.dir, l.in.circle_radius, m_params, l.in.upright);
        const glm::vec2 axis = l.axis;
        int chosen = -1;
        bool in_view = false;
        bool kept_out = false;
        bool leaves_view = false;  // a candidate in the view now would leave it straight away
        for (int c = 0; c < cs.count && chosen < 0; ++c) {
            const OrientedBox text{l.in.anchor + cs.offset[c], l.half, axis};
            if (bounded) {
                const glm::vec2 h = text.aabbHalfExtents();
                const glm::vec2 lo = text.center - h;
                const glm::vec2 hi = text.center + h;
                if (lo.x < 0.0F || lo.y < 0.0F || hi.x > m_camera.viewport.x || hi.y > m_camera.viewport.y) {
                    continue;
                }
            }
            in_view = true;
            const OrientedBox zone = text.inflated(zone_extra);
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
                kept_out = true;
            }
            if (free) {
                m_fading_grid.query(zone.center, zone_h + kTouchSlack, [&](std::uint32_t f) {
                    if (!free) return;
                    ++m_pair_tests;
                    free = satDepth(zone, m_fading_boxes[f]) < 0.0F;
                });
            }
            if (free && m_params.placement_lookahead_s > 0.0F) {
                // Where the anchors' motion carries it and the placed labels a moment from now.
                for (int n = 1; n <= 3 && free; ++n) {
                    const float t = m_params.placement_lookahead_s * static_cast<float>(n) / 3.0F;
                    const OrientedBox later{text.center + l.anchor_velocity * t, text.half_extents, text.axis};
                    if (bounded) {
                        const glm::vec2 h = later.aabbHalfExtents();
                        if (later.center.x - h.x < 0.0F || later.center.y - h.y < 0.0F ||
                            later.center.x + h.x > m_camera.viewport.x || later.center.y + h.y > m_camera.viewport.y) {
                            free = false;
                            leaves_view = true;
                            break;
                        }
                    }
                    if (max_speed.x < 0.0F) {
                        max_speed = glm::vec2(0.0F);
                        for (const std::uint32_t i : m_active) {
                            if (placed(m_labels[i].state)) {
                                max_speed = glm::max(max_speed, glm::abs(m_labels[i].anchor_velocity));
                            }
                        }
                    }
                    const OrientedBox later_zone = later.inflated(m_params.buffer_px);
                    const glm::vec2 later_h = later_zone.aabbHalfExtents();
                    m_grid.query(later_zone.center, later_h + max_speed * t + kTouchSlack, [&](std::uint32_t a) {
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
                        kept_out = true;
                    }
                }
            }
            if (free) {
                chosen = c;  // the first free one has the best visual association [Yoe72]
            }
        }
        if (chosen < 0) {
            // seed 4.4.3: not added; a timer re-evaluates the placement later.
            l.state = LabelState::Waiting;
            l.timer = retryDelay(l.in.id);
            ++m_stats.placement_failures;
            const bool off_screen = !in_view || (leaves_view && !kept_out);
            l.held_by = off_screen ? RemovalReason::OffScreen
                        : kept_out ? RemovalReason::KeepOut
                                   : RemovalReason::Overlap;
            ++(off_screen ? m_stats.failures_off_screen
               : kept_out ? m_stats.failures_keep_out
                          : m_stats.failures_labels);
            continue;
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
    m_placed_cells += m_placed_grid.cellsVisited();
}

void LabelLayout::fade(float dt) {
    const float in_rate = m_params.fade_in_s > 0.0F ? dt / m_params.fade_in_s : 1.0F;
    const float out_rate = m_params.fade_out_s > 0.0F ? dt / m_params.fade_out_s : 1.0F;
    for (Label& l : m_labels) {
        switch (l.state) {
            case LabelState::FadingIn:
                l.alpha = std::min(1.0F, l.alpha + in_rate);
                if (l.alpha >= 1.0F) l.state = LabelState::Visible;
                break;
            case LabelState::FadingOut:
                l.alpha = std::max(0.0F, l.alpha - out_rate);
                l.timer -= dt;
                if (l.alpha <= 0.0F) {
                    if (l.present) {
                        l.state = LabelState::Waiting;
                    } else {
                        l.dead = true;
                    }
                }
                break;
            case LabelState::Waiting: l.timer -= dt; break;
            case LabelState::Pending:
            case LabelState::Visible: break;
        }
    }
}

void LabelLayout::setKeepOut(std::span<const OrientedBox> areas) {
    m_keep_out.clear();
    m_keep_out_aabb.clear();
    for (const OrientedBox& b : areas) {
        if (inRange(b.center, kMaxCoord) && finite(b.half_extents) && b.half_extents.x >= 0.0F &&
            b.half_extents.y >= 0.0F && b.half_extents.x <= kMaxSize && b.half_extents.y <= kMaxSize &&
            finite(b.axis) && std::abs(glm::length(b.axis) - 1.0F) <= 1e-3F) {
            m_keep_out.push_back(b);
            m_keep_out_aabb.push_back(b.aabbHalfExtents());
        } else {
            ++m_stats.rejected_inputs;
        }
    }
}

void LabelLayout::resolveOverlaps() {
    // No drawn frame shows two labels over each other, or a label over a keep-out area: in rank
    // order (placed labels by priority, then those fading out), a label whose text box overlaps
    // one kept before it, or a keep-out area, goes below the visible opacity at once. A placed
    // one is removed and fades out from there (re-inserted later, seed 4.5.3).
    //
    // Only labels that overlap something take part: a grid finds them, and the rank order is
    // needed among them alone. A label that overlaps nothing is kept whatever the order.
    m_rank_labels.clear();
    for (std::uint32_t i = 0; i < m_labels.size(); ++i) {
        if (m_labels[i].alpha >= m_params.visible_alpha) m_rank_labels.push_back(i);
    }
    const std::size_t r = m_rank_labels.size();
    m_rank_boxes.resize(r);
    m_rank_centers.resize(r);
    m_rank_aabb.resize(r);
    m_rank_state.assign(r, 0U);
    glm::vec2 extent_sum{0.0F};
    for (std::size_t j = 0; j < r; ++j) {
        m_rank_boxes[j] = textBox(m_labels[m_rank_labels[j]]);
        m_rank_centers[j] = m_rank_boxes[j].center;
        m_rank_aabb[j] = m_rank_boxes[j].aabbHalfExtents();
        extent_sum += m_rank_aabb[j];
    }
    const glm::vec2 cell =
        r > 0 ? glm::max(extent_sum * (2.0F / static_cast<float>(r)), glm::vec2(8.0F)) : glm::vec2(64.0F);
    m_rank_grid.build(m_rank_centers, m_rank_aabb, cell);
    constexpr std::uint8_t kInvolved = 1U;
    constexpr std::uint8_t kKept = 2U;
    const float hard = m_params.hard_overlap_px;
    for (std::size_t k = 0; k < m_keep_out.size(); ++k) {
        m_rank_grid.query(m_keep_out[k].center, m_keep_out_aabb[k] + kTouchSlack, [&](std::uint32_t j) {
            ++m_pair_tests;
            if (satDepth(m_rank_boxes[j], m_keep_out[k]) > hard) m_rank_state[j] = kInvolved;
        });
    }
    // The separating-axis test takes the first box's axes for near-parallel boxes: both
    // orders are asked, so the set is never smaller than the ranked test below needs.
    m_rank_grid.forEachPair([&](std::uint32_t a, std::uint32_t b) {
        ++m_pair_tests;
        if (satDepth(m_rank_boxes[a], m_rank_boxes[b]) > hard || satDepth(m_rank_boxes[b], m_rank_boxes[a]) > hard) {
            m_rank_state[a] = kInvolved;
            m_rank_state[b] = kInvolved;
        }
    });
    // The rank as one integer key per label: placed before fading out, established before new,
    // then priority (descending) and id (m_labels is sorted by id): the order of yields().
    m_rank_keys.clear();
    for (std::uint32_t j = 0; j < r; ++j) {
        if (m_rank_state[j] == 0U) continue;
        const Label& l = m_labels[m_rank_labels[j]];
        const std::uint64_t group = !placed(l.state) ? 2U : established(l) ? 0U : 1U;
        m_rank_keys.push_back({(group << 32U) | descendingBits(l.in.priority), j});
    }
    std::sort(m_rank_keys.begin(), m_rank_keys.end(), [this](const auto& x, const auto& y) {
        return x.first != y.first ? x.first < y.first : m_rank_labels[x.second] < m_rank_labels[y.second];
    });
    m_rank_pos.resize(r);
    for (std::uint32_t p = 0; p < m_rank_keys.size(); ++p) m_rank_pos[m_rank_keys[p].second] = p;
    const float below = std::nextafter(m_params.visible_alpha, 0.0F);
    for (const auto& [key, j] : m_rank_keys) {
        Label& l = m_labels[m_rank_labels[j]];
        const OrientedBox& box = m_rank_boxes[j];
        bool kept_out = false;
        for (std::size_t k = 0; k < m_keep_out.size() && !kept_out; ++k) {
            ++m_pair_tests;
            if (apart(box.center, m_rank_aabb[j], m_keep_out[k].center, m_keep_out_aabb[k])) continue;
            kept_out = satDepth(box, m_keep_out[k]) > hard;
        }
        bool clash = kept_out;
        if (!clash) {
            const std::uint32_t pos = m_rank_pos[j];
            m_rank_grid.query(box.center, m_rank_aabb[j] + kTouchSlack, [&](std::uint32_t o) {
                if (clash || m_rank_state[o] != kKept || m_rank_pos[o] >= pos) return;
                ++m_pair_tests;
                clash = satDepth(box, m_rank_boxes[o]) > hard;
            });
        }
        if (!clash) {
            m_rank_state[j] = kKept;
            continue;
        }
        if (placed(l.state)) remove(l, kept_out ? RemovalReason::KeepOut : RemovalReason::Overlap);
        l.alpha = std::min(l.alpha, below);
    }
}

float LabelLayout::satDepth(const OrientedBox& a, const OrientedBox& b) {
    ++m_sat_tests;
    return a.overlapDepth(b);
}

bool LabelLayout::touchesAny(const OrientedBox& box, std::span<const OrientedBox> boxes,
                             std::span<const glm::vec2> aabbs) {
    const glm::vec2 h = box.aabbHalfExtents();
    for (std::size_t i = 0; i < boxes.size(); ++i) {
        ++m_pair_tests;
        if (apart(box.center, h, boxes[i].center, aabbs[i])) continue;
        if (satDepth(box, boxes[i]) >= 0.0F) return true;
    }
    return false;
}

void LabelLayout::updateOutput() {
    m_output.clear();
    for (const Label& l : m_labels) {
        if (!placed(l.state) && l.state != LabelState::FadingOut) {
            continue;
        }
        PlacedLabel p;
        p.id = l.in.id;
        p.kind = l.in.kind;
        p.state = l.state;
        p.box = textBox(l);
        p.anchor = l.in.anchor;
        p.alpha = l.alpha;
        p.scale = l.scale;
        p.candidate = l.candidate;
        p.reason = l.state == LabelState::FadingOut ? l.reason : RemovalReason::None;
        p.held_by = l.state == LabelState::FadingOut ? RemovalReason::None : l.held_by;
        m_output.push_back(p);
    }
}

LayoutStats LabelLayout::stats() const {
    LayoutStats s = m_stats;
    for (const Label& l : m_labels) {
        switch (l.state) {
            case LabelState::Pending: ++s.pending; break;
            case LabelState::Waiting: ++s.waiting; break;
            case LabelState::FadingIn: ++s.fading_in; break;
            case LabelState::Visible: ++s.visible; break;
            case LabelState::FadingOut: ++s.fading_out; break;
        }
    }
    return s;
}

}  // namespace navmap::render::labels
