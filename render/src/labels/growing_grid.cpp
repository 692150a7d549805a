// SPDX-License-Identifier: Apache-2.0
#include "navmap/render/labels/growing_grid.h"

#include <algorithm>
#include <cmath>

#include <glm/common.hpp>

namespace navmap::render::labels {

namespace {
// Cells far outside any screen clamp to one border cell: a huge box costs a bounded walk.
constexpr float kMaxCell = 1e5F;
constexpr std::size_t kMaxBuckets = 16384;
}  // namespace

void GrowingGrid::reset(glm::vec2 cell) {
    m_inv_cell = 1.0F / glm::max(cell, glm::vec2(1.0F));
    if (m_buckets.size() > kMaxBuckets) {
        m_buckets.clear();  // keys of cells long left behind: start over
    } else {
        for (const std::uint64_t k : m_used) m_buckets[k].clear();
    }
    m_used.clear();
    m_lo.clear();
    m_hi.clear();
    m_large.clear();
    m_seen.clear();
    m_stamp = 0;
    m_cells_visited = 0;
}

std::int64_t GrowingGrid::cell(float v, float inv) const {
    const float c = std::floor(v * inv);
    return static_cast<std::int64_t>(std::clamp(std::isnan(c) ? 0.0F : c, -kMaxCell, kMaxCell));
}

void GrowingGrid::insert(glm::vec2 center, glm::vec2 half) {
    const auto index = static_cast<std::uint32_t>(m_lo.size());
    m_lo.push_back(center - half);
    m_hi.push_back(center + half);
    m_seen.push_back(0);
    const std::int64_t x0 = cell(m_lo.back().x, m_inv_cell.x);
    const std::int64_t x1 = cell(m_hi.back().x, m_inv_cell.x);
    const std::int64_t y0 = cell(m_lo.back().y, m_inv_cell.y);
    const std::int64_t y1 = cell(m_hi.back().y, m_inv_cell.y);
    if ((x1 - x0 + 1) * (y1 - y0 + 1) > kMaxCellsPerBox) {
        m_large.push_back(index);
        return;
    }
    for (std::int64_t y = y0; y <= y1; ++y) {
        for (std::int64_t x = x0; x <= x1; ++x) {
            std::vector<std::uint32_t>& bucket = m_buckets[key(x, y)];
            if (bucket.empty()) m_used.push_back(key(x, y));
            bucket.push_back(index);
        }
    }
}

}  // namespace navmap::render::labels
