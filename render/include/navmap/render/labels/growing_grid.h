// SPDX-License-Identifier: Apache-2.0
#pragma once
// Broad phase for boxes that arrive one at a time between queries: the labels placed so far in
// one layout step (seed 4.4.3 places a bounded number per step, each against those before it).
// SpatialGrid is built once for a fixed set; this one grows. Hand-written like SpatialGrid.

#include <cstdint>
#include <unordered_map>
#include <vector>

#include <glm/vec2.hpp>

namespace navmap::render::labels {

/// Axis-aligned boxes in a uniform grid of buckets keyed by cell. A query reports each box
/// that overlaps or touches the query box once; the order is the order of insertion within a
/// cell, which only matters to callers that stop at the first hit. Not thread-safe.
class GrowingGrid {
public:
    /// Empties the grid and sets the cell size (each component > 0). Keeps the buffers.
    void reset(glm::vec2 cell);
    /// Adds box `index` (indices count up from 0 with each insert).
    void insert(glm::vec2 center, glm::vec2 half);

    /// Calls f(i) for every inserted box that overlaps or touches the query box.
    template <class F>
    void query(glm::vec2 center, glm::vec2 half, F&& f);

    [[nodiscard]] std::size_t size() const { return m_lo.size(); }
    /// Buckets looked at since the last reset (deterministic work counter).
    [[nodiscard]] std::uint64_t cellsVisited() const { return m_cells_visited; }

private:
    [[nodiscard]] std::int64_t cell(float v, float inv) const;
    [[nodiscard]] static std::uint64_t key(std::int64_t x, std::int64_t y) {
        return (static_cast<std::uint64_t>(x) << 32U) ^ static_cast<std::uint64_t>(y & 0xffffffff);
    }

    static constexpr std::int64_t kMaxCellsPerBox = 64;

    glm::vec2 m_inv_cell{1.0F};
    std::unordered_map<std::uint64_t, std::vector<std::uint32_t>> m_buckets;
    std::vector<std::uint64_t> m_used;  ///< keys of the buckets filled since the last reset
    std::vector<glm::vec2> m_lo;
    std::vector<glm::vec2> m_hi;
    std::vector<std::uint32_t> m_large;  ///< boxes over kMaxCellsPerBox cells: every query tests them
    std::vector<std::uint32_t> m_seen;   ///< query stamp per box: reported once per query
    std::uint32_t m_stamp = 0;
    std::uint64_t m_cells_visited = 0;
};

template <class F>
void GrowingGrid::query(glm::vec2 center, glm::vec2 half, F&& f) {
    if (m_lo.empty()) return;
    const glm::vec2 lo = center - half;
    const glm::vec2 hi = center + half;
    const std::int64_t x0 = cell(lo.x, m_inv_cell.x);
    const std::int64_t x1 = cell(hi.x, m_inv_cell.x);
    const std::int64_t y0 = cell(lo.y, m_inv_cell.y);
    const std::int64_t y1 = cell(hi.y, m_inv_cell.y);
    ++m_stamp;
    const auto test = [&](std::uint32_t i) {
        if (m_lo[i].x <= hi.x && lo.x <= m_hi[i].x && m_lo[i].y <= hi.y && lo.y <= m_hi[i].y) f(i);
    };
    for (const std::uint32_t i : m_large) {
        m_seen[i] = m_stamp;
        test(i);
    }
    if ((x1 - x0 + 1) * (y1 - y0 + 1) > kMaxCellsPerBox) {
        // A query box over many cells: test every box instead of walking the cells.
        ++m_cells_visited;
        for (std::uint32_t i = 0; i < m_lo.size(); ++i) {
            if (m_seen[i] != m_stamp) test(i);
        }
        return;
    }
    for (std::int64_t y = y0; y <= y1; ++y) {
        for (std::int64_t x = x0; x <= x1; ++x) {
            ++m_cells_visited;
            const auto it = m_buckets.find(key(x, y));
            if (it == m_buckets.end()) continue;
            for (const std::uint32_t i : it->second) {
                if (m_seen[i] == m_stamp) continue;
                m_seen[i] = m_stamp;
                test(i);
            }
        }
    }
}

}  // namespace navmap::render::labels
