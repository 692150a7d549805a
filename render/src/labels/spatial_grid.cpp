// SPDX-License-Identifier: Apache-2.0
#include "navmap/render/labels/spatial_grid.h"

#include <cmath>
#include <limits>

#include <glm/common.hpp>

namespace navmap::render::labels {

int SpatialGrid::cellX(float x) const {
    const float c = std::floor((x - m_origin.x) * m_inv_cell.x);
    return static_cast<int>(std::clamp(c, 0.0F, static_cast<float>(m_cols - 1)));
}

int SpatialGrid::cellY(float y) const {
    const float c = std::floor((y - m_origin.y) * m_inv_cell.y);
    return static_cast<int>(std::clamp(c, 0.0F, static_cast<float>(m_rows - 1)));
}

void SpatialGrid::build(std::span<const glm::vec2> centers, std::span<const glm::vec2> halves, glm::vec2 cell,
                        glm::vec2 clip_lo, glm::vec2 clip_hi) {
    const std::size_t n = std::min(centers.size(), halves.size());
    m_lo.resize(n);
    m_hi.resize(n);
    m_range.resize(4 * n);
    glm::vec2 bmin{std::numeric_limits<float>::max()};
    glm::vec2 bmax{std::numeric_limits<float>::lowest()};
    for (std::size_t i = 0; i < n; ++i) {
        m_lo[i] = centers[i] - halves[i];
        m_hi[i] = centers[i] + halves[i];
        bmin = glm::min(bmin, m_lo[i]);
        bmax = glm::max(bmax, m_hi[i]);
    }
    bmin = glm::max(bmin, clip_lo);
    bmax = glm::min(bmax, clip_hi);
    if (n == 0 || bmin.x > bmax.x || bmin.y > bmax.y) {
        bmin = bmax = glm::vec2(0.0F);
    }
    cell = glm::max(cell, glm::vec2(1.0F));
    const glm::vec2 extent = glm::max(bmax - bmin, glm::vec2(1.0F));
    // Bound the cell count (memory and the empty-cell scan) to about 4 per box.
    const double max_cells = 4.0 * static_cast<double>(n) + 16.0;
    double cols = std::ceil(extent.x / cell.x);
    double rows = std::ceil(extent.y / cell.y);
    if (cols * rows > max_cells) {
        cell *= static_cast<float>(std::sqrt(cols * rows / max_cells));
        cols = std::ceil(extent.x / cell.x);
        rows = std::ceil(extent.y / cell.y);
        while (cols * rows > max_cells) {  // ceil() may leave it slightly above
            cell *= 1.05F;
            cols = std::ceil(extent.x / cell.x);
            rows = std::ceil(extent.y / cell.y);
        }
    }
    m_cols = std::max(1, static_cast<int>(cols));
    m_rows = std::max(1, static_cast<int>(rows));
    m_origin = bmin;
    m_cell = cell;
    m_inv_cell = 1.0F / cell;

    const std::size_t cells = static_cast<std::size_t>(m_cols) * static_cast<std::size_t>(m_rows);
    m_cell_start.assign(cells + 1, 0U);
    for (std::size_t i = 0; i < n; ++i) {
        std::int32_t* r = &m_range[4 * i];
        r[0] = cellX(m_lo[i].x);
        r[1] = cellY(m_lo[i].y);
        r[2] = cellX(m_hi[i].x);
        r[3] = cellY(m_hi[i].y);
        for (std::int32_t y = r[1]; y <= r[3]; ++y) {
            for (std::int32_t x = r[0]; x <= r[2]; ++x) {
                ++m_cell_start[static_cast<std::size_t>(y) * static_cast<std::size_t>(m_cols) +
                               static_cast<std::size_t>(x) + 1];
            }
        }
    }
    for (std::size_t c = 0; c < cells; ++c) {
        m_cell_start[c + 1] += m_cell_start[c];
    }
    m_cell_items.resize(m_cell_start[cells]);
    std::vector<std::uint32_t>& fill = m_fill;
    fill.assign(m_cell_start.begin(), m_cell_start.end() - 1);
    for (std::size_t i = 0; i < n; ++i) {
        const std::int32_t* r = &m_range[4 * i];
        for (std::int32_t y = r[1]; y <= r[3]; ++y) {
            for (std::int32_t x = r[0]; x <= r[2]; ++x) {
                const std::size_t c =
                    static_cast<std::size_t>(y) * static_cast<std::size_t>(m_cols) + static_cast<std::size_t>(x);
                m_cell_items[fill[c]++] = static_cast<std::uint32_t>(i);
            }
        }
    }
}

}  // namespace navmap::render::labels
