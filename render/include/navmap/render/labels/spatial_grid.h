// SPDX-License-Identifier: Apache-2.0
#pragma once
// Uniform grid broad phase for the label layout. The seed (4.5.1, 4.6.1) tests all label
// pairs on the GPU and names a uniform grid as the way past ~2000 labels; this is that grid.
// Hand-written: no Debian package provides a small deterministic 2D broad phase.

#include <algorithm>
#include <cstdint>
#include <span>
#include <vector>

#include <glm/vec2.hpp>

namespace navmap::render::labels {

/// Axis-aligned boxes binned into a uniform grid of cells (counting sort, no hashing), so
/// pair and range queries touch only neighbours. Visiting order depends only on the input
/// order, which keeps the layout deterministic. Not thread-safe; reuse one instance to keep
/// its buffers.
class SpatialGrid {
public:
    /// Bins n boxes given by centers and half extents. `cell` is the cell size in pixels
    /// (each component > 0); it grows when the grid would exceed about 4 cells per box.
    /// The grid spans the boxes' bounds clipped to [clip_lo, clip_hi]; boxes outside the
    /// clip land in the border cells, so far outliers cannot coarsen the grid.
    void build(std::span<const glm::vec2> centers, std::span<const glm::vec2> halves, glm::vec2 cell,
               glm::vec2 clip_lo = glm::vec2(-1e7F), glm::vec2 clip_hi = glm::vec2(1e7F));

    /// Calls f(i, j) with i < j once for every pair whose boxes overlap or touch.
    template <class F>
    void forEachPair(F&& f) const;

    /// Calls f(i) once for every box that overlaps or touches the query box.
    template <class F>
    void query(glm::vec2 center, glm::vec2 half, F&& f) const;

    [[nodiscard]] std::size_t size() const { return m_lo.size(); }
    [[nodiscard]] int columns() const { return m_cols; }
    [[nodiscard]] int rows() const { return m_rows; }
    [[nodiscard]] glm::vec2 cellSize() const { return m_cell; }
    /// Cells visited by forEachPair() and query() since the last resetWork(): a deterministic
    /// measure of the broad phase's work (tests assert how it grows with the box count).
    [[nodiscard]] std::uint64_t cellsVisited() const { return m_cells_visited; }
    void resetWork() const { m_cells_visited = 0; }

private:
    [[nodiscard]] int cellX(float x) const;
    [[nodiscard]] int cellY(float y) const;
    [[nodiscard]] bool touches(std::uint32_t a, std::uint32_t b) const {
        return m_lo[a].x <= m_hi[b].x && m_lo[b].x <= m_hi[a].x && m_lo[a].y <= m_hi[b].y && m_lo[b].y <= m_hi[a].y;
    }

    glm::vec2 m_origin{0.0F};
    glm::vec2 m_cell{1.0F};
    glm::vec2 m_inv_cell{1.0F};
    int m_cols = 0;
    int m_rows = 0;
    std::vector<glm::vec2> m_lo;
    std::vector<glm::vec2> m_hi;
    std::vector<std::int32_t> m_range;  ///< per box: x0, y0, x1, y1 (inclusive cells)
    std::vector<std::uint32_t> m_cell_start;
    std::vector<std::uint32_t> m_cell_items;
    std::vector<std::uint32_t> m_fill;  ///< scratch for build()
    mutable std::uint64_t m_cells_visited = 0;
};

template <class F>
void SpatialGrid::forEachPair(F&& f) const {
    m_cells_visited += static_cast<std::uint64_t>(m_rows) * static_cast<std::uint64_t>(m_cols);
    for (int cy = 0; cy < m_rows; ++cy) {
        for (int cx = 0; cx < m_cols; ++cx) {
            const std::size_t c =
                static_cast<std::size_t>(cy) * static_cast<std::size_t>(m_cols) + static_cast<std::size_t>(cx);
            const std::uint32_t begin = m_cell_start[c];
            const std::uint32_t end = m_cell_start[c + 1];
            for (std::uint32_t p = begin; p < end; ++p) {
                const std::uint32_t a = m_cell_items[p];
                const std::int32_t* ra = &m_range[4U * a];
                for (std::uint32_t q = p + 1; q < end; ++q) {
                    const std::uint32_t b = m_cell_items[q];
                    const std::int32_t* rb = &m_range[4U * b];
                    // Report a pair only in the first cell both boxes share.
                    if (std::max(ra[0], rb[0]) != cx || std::max(ra[1], rb[1]) != cy) {
                        continue;
                    }
                    if (touches(a, b)) {
                        f(a, b);  // a < b: cell lists are in input order
                    }
                }
            }
        }
    }
}

template <class F>
void SpatialGrid::query(glm::vec2 center, glm::vec2 half, F&& f) const {
    if (m_lo.empty()) {
        return;
    }
    const glm::vec2 lo = center - half;
    const glm::vec2 hi = center + half;
    // Cell indices clamp to the border, where boxes outside the grid are binned too.
    const int x0 = cellX(lo.x);
    const int y0 = cellY(lo.y);
    const int x1 = cellX(hi.x);
    const int y1 = cellY(hi.y);
    m_cells_visited += static_cast<std::uint64_t>(y1 - y0 + 1) * static_cast<std::uint64_t>(x1 - x0 + 1);
    for (int cy = y0; cy <= y1; ++cy) {
        for (int cx = x0; cx <= x1; ++cx) {
            const std::size_t c =
                static_cast<std::size_t>(cy) * static_cast<std::size_t>(m_cols) + static_cast<std::size_t>(cx);
            for (std::uint32_t p = m_cell_start[c]; p < m_cell_start[c + 1]; ++p) {
                const std::uint32_t i = m_cell_items[p];
                const std::int32_t* r = &m_range[4U * i];
                if (std::max(r[0], x0) != cx || std::max(r[1], y0) != cy) {
                    continue;
                }
                if (m_lo[i].x <= hi.x && lo.x <= m_hi[i].x && m_lo[i].y <= hi.y && lo.y <= m_hi[i].y) {
                    f(i);
                }
            }
        }
    }
}

}  // namespace navmap::render::labels
