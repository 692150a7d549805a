// SPDX-License-Identifier: Apache-2.0
#include "layout_metrics.h"

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>

namespace navmap::render::labels {

namespace {

bool isVisible(const PlacedLabel& l) { return l.state == LabelState::FadingIn || l.state == LabelState::Visible; }

}  // namespace

std::size_t LayoutMetrics::countOverlaps(std::span<const PlacedLabel> labels, float tolerance) {
    struct Item {
        float lo;
        float hi;
        std::size_t index;
    };
    std::vector<Item> items;
    items.reserve(labels.size());
    for (std::size_t i = 0; i < labels.size(); ++i) {
        if (!isVisible(labels[i])) continue;
        const float h = labels[i].box.aabbHalfExtents().x;
        items.push_back({labels[i].box.center.x - h, labels[i].box.center.x + h, i});
    }
    std::sort(items.begin(), items.end(),
              [](const Item& a, const Item& b) { return a.lo != b.lo ? a.lo < b.lo : a.index < b.index; });
    std::size_t count = 0;
    for (std::size_t a = 0; a < items.size(); ++a) {
        for (std::size_t b = a + 1; b < items.size() && items[b].lo <= items[a].hi; ++b) {
            if (labels[items[a].index].box.overlaps(labels[items[b].index].box, tolerance)) {
                ++count;
            }
        }
    }
    return count;
}

void LayoutMetrics::addFrame(std::span<const PlacedLabel> labels, double dt_s) {
    m_curr.assign(labels.begin(), labels.end());
    const auto by_id = [](const PlacedLabel& a, const PlacedLabel& b) { return a.id < b.id; };
    if (!std::is_sorted(m_curr.begin(), m_curr.end(), by_id)) {
        std::sort(m_curr.begin(), m_curr.end(), by_id);
    }
    const std::size_t visible = static_cast<std::size_t>(std::count_if(m_curr.begin(), m_curr.end(), isVisible));
    const std::size_t overlaps = countOverlaps(m_curr);
    const bool first = m_q.frames == 0;
    ++m_q.frames;
    if (std::isfinite(dt_s) && dt_s > 0.0) {
        m_q.seconds += dt_s;
    }
    m_visible_sum += static_cast<double>(visible);
    m_q.last_visible = visible;
    m_q.last_overlaps = overlaps;
    m_q.max_overlaps = std::max(m_q.max_overlaps, overlaps);

    if (!first) {
        // Merge previous and current frames by id.
        std::size_t i = 0;
        std::size_t j = 0;
        while (i < m_prev.size() || j < m_curr.size()) {
            if (j == m_curr.size() || (i < m_prev.size() && m_prev[i].id < m_curr[j].id)) {
                if (m_prev[i].alpha > m_params.pop_alpha) ++m_q.pops;  // vanished without fading
                ++i;
            } else if (i == m_prev.size() || m_curr[j].id < m_prev[i].id) {
                if (m_curr[j].alpha > m_params.pop_alpha) ++m_q.pops;  // appeared without fading
                ++j;
            } else {
                const PlacedLabel& a = m_prev[i++];
                const PlacedLabel& b = m_curr[j++];
                if (std::abs(b.alpha - a.alpha) > m_params.pop_alpha) {
                    ++m_q.pops;
                    continue;
                }
                if (!isVisible(a) || !isVisible(b)) continue;
                // Jitter: motion relative to the anchor, so camera motion does not count.
                const float move = glm::length((b.box.center - b.anchor) - (a.box.center - a.anchor));
                if (move > m_params.pop_jump_px) {
                    ++m_q.pops;
                    continue;
                }
                m_jitter_sum += static_cast<double>(move);
                ++m_q.jitter_samples;
                const auto bin = static_cast<std::size_t>(move / kBinPx);
                ++m_hist[std::min(bin, kBins - 1)];
            }
        }
    }
    m_prev.swap(m_curr);
}

LayoutQuality LayoutMetrics::summary() const {
    LayoutQuality q = m_q;
    if (q.frames > 0) q.mean_visible = m_visible_sum / static_cast<double>(q.frames);
    if (q.seconds > 0.0) q.pops_per_s = static_cast<double>(q.pops) / q.seconds;
    if (q.jitter_samples > 0) {
        q.mean_jitter_px = m_jitter_sum / static_cast<double>(q.jitter_samples);
        const auto want = static_cast<std::uint64_t>(std::ceil(0.95 * static_cast<double>(q.jitter_samples)));
        std::uint64_t seen = 0;
        for (std::size_t b = 0; b < kBins; ++b) {
            seen += m_hist[b];
            if (seen >= want) {
                q.p95_jitter_px = static_cast<double>(b) * static_cast<double>(kBinPx);  // bin lower edge
                break;
            }
        }
    }
    return q;
}

void LayoutMetrics::reset() {
    m_prev.clear();
    m_curr.clear();
    m_q = LayoutQuality{};
    m_visible_sum = 0.0;
    m_jitter_sum = 0.0;
    m_hist.fill(0);
}

}  // namespace navmap::render::labels
