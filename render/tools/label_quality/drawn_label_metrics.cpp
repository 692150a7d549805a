// SPDX-License-Identifier: Apache-2.0
#include "drawn_label_metrics.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <glm/geometric.hpp>

namespace navmap::render::labels {

namespace {

struct Range {
    float lo = std::numeric_limits<float>::max();
    float hi = std::numeric_limits<float>::lowest();
};

Range project(std::span<const glm::vec2> poly, glm::vec2 axis) {
    Range r;
    for (const glm::vec2 p : poly) {
        const float d = glm::dot(p, axis);
        r.lo = std::min(r.lo, d);
        r.hi = std::max(r.hi, d);
    }
    return r;
}

void boundsOf(std::span<const glm::vec2> poly, glm::vec2& lo, glm::vec2& hi) {
    lo = glm::vec2(std::numeric_limits<float>::max());
    hi = glm::vec2(std::numeric_limits<float>::lowest());
    for (const glm::vec2 p : poly) {
        lo = glm::min(lo, p);
        hi = glm::max(hi, p);
    }
}

// Interiors of two bounding boxes overlap by more than `tolerance` on both axes. The SAT depth
// of two convex polygons is their smallest projection overlap over all directions, so it never
// exceeds the overlap along x or y: boxes that fail this cannot overlap by more either.
bool boundsOverlap(glm::vec2 alo, glm::vec2 ahi, glm::vec2 blo, glm::vec2 bhi, float tolerance) {
    return std::min(ahi.x, bhi.x) - std::max(alo.x, blo.x) > tolerance &&
           std::min(ahi.y, bhi.y) - std::max(alo.y, blo.y) > tolerance;
}

}  // namespace

DrawnLabelMetrics::DrawnLabelMetrics(DrawnMetricsParams params) : m_params(params) {}

float DrawnLabelMetrics::penetrationDepth(std::span<const glm::vec2> a, std::span<const glm::vec2> b) {
    constexpr float kNone = -std::numeric_limits<float>::infinity();
    if (a.size() < 3 || b.size() < 3) return kNone;
    float depth = std::numeric_limits<float>::infinity();
    bool any_axis = false;
    for (const std::span<const glm::vec2> poly : {a, b}) {
        for (std::size_t i = 0; i < poly.size(); ++i) {
            const glm::vec2 e = poly[(i + 1) % poly.size()] - poly[i];
            const float len = glm::length(e);
            if (!(len > 1e-6F)) continue;  // repeated corner
            const glm::vec2 n(-e.y / len, e.x / len);
            const Range ra = project(a, n);
            const Range rb = project(b, n);
            depth = std::min(depth, std::min(ra.hi, rb.hi) - std::max(ra.lo, rb.lo));
            any_axis = true;
        }
    }
    return any_axis ? depth : kNone;
}

bool DrawnLabelMetrics::interiorPoint(const DrawnLabel& l, glm::vec2 viewport) const {
    if (l.kind != LabelKind::Point && l.kind != LabelKind::Area) return false;
    const float m = m_params.interior_margin_px;
    return l.anchor.x >= m && l.anchor.x <= viewport.x - m && l.anchor.y >= m && l.anchor.y <= viewport.y - m;
}

bool DrawnLabelMetrics::glyphsOverlap(const Visible& a, const Visible& b) const {
    const float tol = m_params.overlap_tolerance_px;
    for (const ScreenQuad* qa : a.boxes) {
        glm::vec2 alo, ahi;
        boundsOf(*qa, alo, ahi);
        for (const ScreenQuad* qb : b.boxes) {
            glm::vec2 blo, bhi;
            boundsOf(*qb, blo, bhi);
            if (!boundsOverlap(alo, ahi, blo, bhi, tol)) continue;
            if (penetrationDepth(*qa, *qb) > tol) return true;
        }
    }
    return false;
}

DrawnFrameFigures DrawnLabelMetrics::addFrame(std::span<const DrawnLabel> labels, const DrawnMarker& marker,
                                              glm::vec2 viewport, double dt_s) {
    DrawnFrameFigures f;
    const bool first = m_q.frames == 0;
    ++m_q.frames;
    if (std::isfinite(dt_s) && dt_s > 0.0) m_q.seconds += dt_s;

    // Visible labels, one per id (sorted by id so duplicates sit together).
    std::vector<const DrawnLabel*> order;
    order.reserve(labels.size());
    for (const DrawnLabel& l : labels) order.push_back(&l);
    std::stable_sort(order.begin(), order.end(),
                     [](const DrawnLabel* x, const DrawnLabel* y) { return x->id < y->id; });
    std::vector<Visible> visible;
    for (std::size_t i = 0; i < order.size();) {
        std::size_t j = i;
        const DrawnLabel* best = order[i];
        Visible v;
        v.id = order[i]->id;
        for (; j < order.size() && order[j]->id == v.id; ++j) {
            const DrawnLabel* l = order[j];
            if (l->opacity > best->opacity) best = l;
            if (l->opacity >= m_params.visible_opacity) {
                for (const ScreenQuad& q : l->glyph_boxes) v.boxes.push_back(&q);
            }
        }
        m_q.duplicate_ids += j - i - 1;
        i = j;
        if (!(best->opacity >= m_params.visible_opacity)) continue;
        v.label = best;
        v.lo = glm::vec2(std::numeric_limits<float>::max());
        v.hi = glm::vec2(std::numeric_limits<float>::lowest());
        for (const ScreenQuad* q : v.boxes) {
            glm::vec2 lo, hi;
            boundsOf(*q, lo, hi);
            v.lo = glm::min(v.lo, lo);
            v.hi = glm::max(v.hi, hi);
        }
        visible.push_back(std::move(v));
    }
    f.visible = visible.size();
    m_visible_counts.push_back(f.visible);
    m_q.visible_label_frames += f.visible;

    // Overlapping glyph boxes between pairs of visible labels: sweep along x over the labels'
    // bounds, then SAT on the glyph quads of the candidate pairs.
    std::vector<std::size_t> by_x(visible.size());
    for (std::size_t i = 0; i < by_x.size(); ++i) by_x[i] = i;
    std::sort(by_x.begin(), by_x.end(), [&](std::size_t x, std::size_t y) {
        return visible[x].lo.x != visible[y].lo.x ? visible[x].lo.x < visible[y].lo.x : visible[x].id < visible[y].id;
    });
    const float tol = m_params.overlap_tolerance_px;
    for (std::size_t i = 0; i < by_x.size(); ++i) {
        const Visible& a = visible[by_x[i]];
        for (std::size_t k = i + 1; k < by_x.size() && visible[by_x[k]].lo.x < a.hi.x - tol; ++k) {
            const Visible& b = visible[by_x[k]];
            if (!boundsOverlap(a.lo, a.hi, b.lo, b.hi, tol)) continue;
            if (glyphsOverlap(a, b)) ++f.overlap_pairs;
        }
    }
    m_q.overlap_pairs_max = std::max(m_q.overlap_pairs_max, f.overlap_pairs);
    m_q.overlap_pairs_sum += f.overlap_pairs;
    if (f.overlap_pairs > 0) ++m_q.overlap_frames;

    // Per visible label: occlusion, size, marker.
    const bool has_marker = marker.outline.size() >= 3;
    glm::vec2 mlo{0.0F}, mhi{0.0F};
    if (has_marker) {
        ++m_q.marker_frames;
        boundsOf(marker.outline, mlo, mhi);
    }
    for (const Visible& v : visible) {
        const DrawnLabel& l = *v.label;
        m_seen.insert(v.id);
        if (l.occluded_fraction < 0.0F) {
            ++m_q.occlusion_unmeasured_label_frames;
        } else {
            ++m_q.occlusion_measured_label_frames;
            if (l.occluded_fraction > m_params.occluded_fraction) ++m_q.occluded_label_frames;
        }
        if (l.cap_height_px < m_params.min_cap_height_px) {
            ++m_q.too_small_label_frames;
            m_too_small.insert(v.id);
        }
        if (has_marker && boundsOverlap(v.lo, v.hi, mlo, mhi, m_params.marker_tolerance_px)) {
            const bool over = std::any_of(v.boxes.begin(), v.boxes.end(), [&](const ScreenQuad* q) {
                return penetrationDepth(*q, marker.outline) > m_params.marker_tolerance_px;
            });
            if (over) {
                ++f.marker_overlaps;
                m_over_marker.insert(v.id);
            }
        }
    }
    m_q.marker_overlap_label_frames += f.marker_overlaps;
    if (f.marker_overlaps > 0) ++m_q.marker_overlap_frames;

    // Pops: ids entering or leaving the visible set (a label counts where it is visible: the
    // current frame for one entering, the previous frame for one leaving), and texts likewise.
    std::unordered_map<std::uint64_t, Previous> now;
    std::unordered_set<std::string> texts;
    now.reserve(visible.size());
    for (const Visible& v : visible) {
        const DrawnLabel& l = *v.label;
        const Previous p{l.center - l.anchor, interiorPoint(l, viewport)};
        now.emplace(v.id, p);
        texts.insert(l.text);
        if (first) continue;
        const auto it = m_prev.find(v.id);
        if (it == m_prev.end()) {
            ++f.pops;
            if (p.interior_point) ++f.interior_point_pops;
        } else {
            // Jitter: motion relative to the anchor, so camera motion does not count.
            const float move = glm::length(p.offset - it->second.offset);
            m_jitter.push_back(move);
            m_jitter_sum += static_cast<double>(move);
        }
    }
    if (!first) {
        for (const auto& [id, p] : m_prev) {
            if (now.contains(id)) continue;
            ++f.pops;
            if (p.interior_point) ++f.interior_point_pops;
        }
        for (const std::string& t : texts) f.text_pops += m_prev_texts.contains(t) ? 0 : 1;
        for (const std::string& t : m_prev_texts) f.text_pops += texts.contains(t) ? 0 : 1;
        m_q.pops += f.pops;
        m_q.interior_point_pops += f.interior_point_pops;
        m_q.text_pops += f.text_pops;
        if (f.pops > 0) ++m_q.frames_with_pop;
    }
    m_prev.swap(now);
    m_prev_texts.swap(texts);
    return f;
}

DrawnLabelQuality DrawnLabelMetrics::summary() const {
    DrawnLabelQuality q = m_q;
    if (q.frames > 0) {
        std::vector<std::size_t> counts = m_visible_counts;
        std::sort(counts.begin(), counts.end());
        const std::size_t n = counts.size();
        q.visible_median = n % 2 == 1 ? static_cast<double>(counts[n / 2])
                                      : 0.5 * static_cast<double>(counts[n / 2 - 1] + counts[n / 2]);
        q.visible_mean = static_cast<double>(q.visible_label_frames) / static_cast<double>(n);
        q.visible_min = counts.front();
        q.visible_max = counts.back();
    }
    q.distinct_visible_labels = m_seen.size();
    q.too_small_labels = m_too_small.size();
    q.marker_overlap_labels = m_over_marker.size();
    if (q.occlusion_measured_label_frames > 0) {
        q.occluded_share =
            static_cast<double>(q.occluded_label_frames) / static_cast<double>(q.occlusion_measured_label_frames);
    }
    if (q.visible_label_frames > 0) {
        q.too_small_share = static_cast<double>(q.too_small_label_frames) / static_cast<double>(q.visible_label_frames);
    }
    if (q.seconds > 0.0) {
        q.pops_per_s = static_cast<double>(q.pops) / q.seconds;
        q.interior_point_pops_per_s = static_cast<double>(q.interior_point_pops) / q.seconds;
        q.text_pops_per_s = static_cast<double>(q.text_pops) / q.seconds;
    }
    if (q.frames > 1) q.pop_frame_share = static_cast<double>(q.frames_with_pop) / static_cast<double>(q.frames - 1);
    q.jitter_samples = m_jitter.size();
    if (!m_jitter.empty()) {
        std::vector<float> sorted = m_jitter;
        std::sort(sorted.begin(), sorted.end());
        q.jitter_mean_px = m_jitter_sum / static_cast<double>(sorted.size());
        // Nearest rank: the smallest sample with at least 95 % of the samples at or below it.
        const auto rank = static_cast<std::size_t>(std::ceil(0.95 * static_cast<double>(sorted.size())));
        q.jitter_p95_px = static_cast<double>(sorted[std::max<std::size_t>(rank, 1) - 1]);
        q.jitter_max_px = static_cast<double>(sorted.back());
    }
    return q;
}

void DrawnLabelMetrics::reset() {
    m_q = DrawnLabelQuality{};
    m_visible_counts.clear();
    m_prev.clear();
    m_prev_texts.clear();
    m_seen.clear();
    m_too_small.clear();
    m_over_marker.clear();
    m_jitter.clear();
    m_jitter_sum = 0.0;
}

}  // namespace navmap::render::labels
