// SPDX-License-Identifier: Apache-2.0
// The hard rule of a drawn frame (LabelLayout::resolveOverlaps): no two labels over each other,
// no label over a keep-out area; and the box tests the layout counts as its work.
#include <algorithm>
#include <bit>
#include <cmath>

#include <glm/common.hpp>

#include "layout_internal.h"
#include "navmap/render/labels/label_layout.h"

namespace navmap::render::labels {

namespace {

// A finite float as an unsigned key that sorts in the float's descending order (-0 = +0).
std::uint64_t descendingBits(float f) {
    const std::uint32_t u = std::bit_cast<std::uint32_t>(f + 0.0F);
    const std::uint32_t ascending = (u & 0x80000000U) != 0U ? ~u : (u | 0x80000000U);
    return ~ascending;
}

}  // namespace

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

}  // namespace navmap::render::labels
