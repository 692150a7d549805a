// SPDX-License-Identifier: Apache-2.0
// LabelLayout: input (setFrame, setKeepOut), the fixed steps of advance(), a label's shape and
// state changes, fading and the output. The steps' parts are in label_forces.cpp (forces and
// motion), label_placement.cpp (initial placement) and label_overlaps.cpp (the drawn frame).
#include "navmap/render/labels/label_layout.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <sstream>

#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include "label_behavior.h"
#include "layout_internal.h"

namespace navmap::render::labels {

namespace {

constexpr float kRadToDeg = 180.0F / std::numbers::pi_v<float>;
constexpr float kDegToRad = std::numbers::pi_v<float> / 180.0F;
constexpr float kAnchorSpeedTau = 0.1F;  // s, low-pass of the measured anchor speed

// Input bounds: far beyond any screen, small enough that sums and squares stay finite.
constexpr float kMaxCoord = 1e6F;
constexpr float kMinSize = 0.5F;
constexpr float kMaxSize = 1e5F;

bool finite(glm::vec2 v) { return std::isfinite(v.x) && std::isfinite(v.y); }

bool inRange(glm::vec2 v, float limit) { return std::abs(v.x) <= limit && std::abs(v.y) <= limit; }  // false for NaN

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
