// SPDX-License-Identifier: Apache-2.0
#include "terrain_horizon.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

namespace navmap::render {

namespace {

constexpr float kNoFloor = -std::numeric_limits<float>::infinity();

// Drawn tiles by position: a grid of cells of the smallest tile's size, each pointing at the
// tile that covers it (tiles of one level lie on multiples of their size from the quadtree's
// corner, so the grid is laid from the corner of a smallest tile).
class FloorIndex {
public:
    explicit FloorIndex(std::span<const TerrainFloor* const> floors) {
        for (const TerrainFloor* f : floors) {
            if (f && f->cells > 0)
                m_cell = m_cell > 0.0 ? std::min(m_cell, f->cell_m * f->cells) : f->cell_m * f->cells;
        }
        if (!(m_cell > 0.0)) return;
        glm::dvec2 lo(std::numeric_limits<double>::max()), hi(std::numeric_limits<double>::lowest());
        glm::dvec2 ref(0.0);  // the corner of a smallest tile: the index cells are aligned to it
        for (const TerrainFloor* f : floors) {
            if (!f || f->cells <= 0) continue;
            lo = glm::min(lo, f->origin);
            hi = glm::max(hi, f->origin + f->cell_m * f->cells);
            if (f->cell_m * f->cells == m_cell) ref = f->origin;
        }
        // Tile corners lie on multiples of the tile size from the quadtree's corner, which need
        // not be a multiple of the size from the frame's origin.
        m_origin = ref + glm::floor((lo - ref) / m_cell + 1e-9) * m_cell;
        m_nx = static_cast<int>(std::ceil((hi.x - m_origin.x) / m_cell));
        m_ny = static_cast<int>(std::ceil((hi.y - m_origin.y) / m_cell));
        m_at.assign(static_cast<std::size_t>(m_nx) * static_cast<std::size_t>(m_ny), nullptr);
        for (const TerrainFloor* f : floors) {
            if (!f || f->cells <= 0) continue;
            const double size = f->cell_m * f->cells;
            const int x0 = static_cast<int>(std::floor((f->origin.x - m_origin.x) / m_cell + 0.5));
            const int y0 = static_cast<int>(std::floor((f->origin.y - m_origin.y) / m_cell + 0.5));
            const int n = std::max(1, static_cast<int>(std::floor(size / m_cell + 0.5)));
            for (int y = std::max(y0, 0); y < std::min(y0 + n, m_ny); ++y) {
                for (int x = std::max(x0, 0); x < std::min(x0 + n, m_nx); ++x) {
                    const TerrainFloor*& slot = m_at[static_cast<std::size_t>(y) * static_cast<std::size_t>(m_nx) +
                                                     static_cast<std::size_t>(x)];
                    if (!slot) slot = f;
                }
            }
        }
    }

    /// The lowest the drawn surface lies over the box lo..hi; kNoFloor where part of it has no
    /// drawn tile.
    [[nodiscard]] float lowest(glm::dvec2 lo, glm::dvec2 hi) const {
        if (m_at.empty()) return kNoFloor;
        const int x0 = static_cast<int>(std::floor((lo.x - m_origin.x) / m_cell));
        const int x1 = static_cast<int>(std::floor((hi.x - m_origin.x) / m_cell));
        const int y0 = static_cast<int>(std::floor((lo.y - m_origin.y) / m_cell));
        const int y1 = static_cast<int>(std::floor((hi.y - m_origin.y) / m_cell));
        if (x0 < 0 || y0 < 0 || x1 >= m_nx || y1 >= m_ny) return kNoFloor;
        float low = std::numeric_limits<float>::max();
        for (int y = y0; y <= y1; ++y) {
            for (int x = x0; x <= x1; ++x) {
                const TerrainFloor* f =
                    m_at[static_cast<std::size_t>(y) * static_cast<std::size_t>(m_nx) + static_cast<std::size_t>(x)];
                if (!f) return kNoFloor;
                // The part of the box in this index cell, in the tile's grid cells.
                const glm::dvec2 a = glm::max(lo, m_origin + glm::dvec2(x, y) * m_cell) - f->origin;
                const glm::dvec2 b = glm::min(hi, m_origin + glm::dvec2(x + 1, y + 1) * m_cell) - f->origin;
                const int c0 = std::clamp(static_cast<int>(std::floor(a.x / f->cell_m)), 0, f->cells - 1);
                const int c1 = std::clamp(static_cast<int>(std::floor(b.x / f->cell_m)), 0, f->cells - 1);
                const int r0 = std::clamp(static_cast<int>(std::floor(a.y / f->cell_m)), 0, f->cells - 1);
                const int r1 = std::clamp(static_cast<int>(std::floor(b.y / f->cell_m)), 0, f->cells - 1);
                for (int r = r0; r <= r1; ++r) {
                    for (int c = c0; c <= c1; ++c)
                        low = std::min(low, f->low[static_cast<std::size_t>(r * f->cells + c)]);
                }
            }
        }
        return low;
    }

private:
    double m_cell = 0.0;
    glm::dvec2 m_origin{0.0};
    int m_nx = 0, m_ny = 0;
    std::vector<const TerrainFloor*> m_at;
};

// Angle wrapped into [0, 2 pi).
double wrapPositive(double a) {
    constexpr double k2Pi = 2.0 * std::numbers::pi;
    a = std::fmod(a, k2Pi);
    return a < 0.0 ? a + k2Pi : a;
}

}  // namespace

TerrainFloor terrainFloor(glm::dvec2 origin, double size_m, int grid_size, std::span<const float> heights,
                          std::span<const std::vector<float>> ancestor_heights) {
    TerrainFloor f;
    const auto n = static_cast<std::size_t>(grid_size);
    if (grid_size < 2 || heights.size() < n * n) return f;
    f.origin = origin;
    f.cells = grid_size - 1;
    f.cell_m = size_m / f.cells;
    // Per vertex: the least of its own height and its geomorph targets'.
    std::vector<float> vlow(heights.begin(), heights.begin() + static_cast<std::ptrdiff_t>(n * n));
    for (const std::vector<float>& a : ancestor_heights) {
        if (a.size() < n * n) continue;
        for (std::size_t i = 0; i < n * n; ++i) vlow[i] = std::min(vlow[i], a[i]);
    }
    const auto cells = static_cast<std::size_t>(f.cells);
    f.low.resize(cells * cells);
    for (std::size_t r = 0; r < cells; ++r) {
        for (std::size_t c = 0; c < cells; ++c) {
            const std::size_t v = r * n + c;
            f.low[r * cells + c] = std::min({vlow[v], vlow[v + 1], vlow[v + n], vlow[v + n + 1]});
        }
    }
    return f;
}

void TerrainHorizon::build(glm::dvec3 eye, double ground_m, std::span<const TerrainFloor* const> floors, double az_from,
                           double az_to, int bins, double last_m) {
    m_bins = 0;
    m_radius.clear();
    m_slope.clear();
    // The eye must be above the surface drawn under it: a line of sight that is below the
    // surface farther on has then met it on the way.
    if (!(eye.z > ground_m) || bins <= 0 || !(az_to > az_from)) return;
    const FloorIndex index(floors);
    for (double r = kFirstM; r <= last_m; r *= kStepRatio) m_radius.push_back(r);
    if (m_radius.empty()) return;
    m_eye = eye;
    m_az_from = az_from;
    m_bins = bins;
    m_bin_rad = std::min(az_to - az_from, 2.0 * std::numbers::pi) / bins;
    const std::size_t steps = m_radius.size();
    m_slope.assign(static_cast<std::size_t>(bins) * steps, -std::numeric_limits<float>::infinity());
    const double sagitta = 1.0 - std::cos(0.5 * m_bin_rad);
    for (int b = 0; b < bins; ++b) {
        const double a0 = az_from + b * m_bin_rad, a1 = a0 + m_bin_rad;
        const glm::dvec2 d0(std::cos(a0), std::sin(a0)), d1(std::cos(a1), std::sin(a1));
        float run = -std::numeric_limits<float>::infinity();
        for (std::size_t j = 0; j < steps; ++j) {
            // Every line of sight in the bin crosses this arc at distance r.
            const double r = m_radius[j];
            const glm::dvec2 p0 = glm::dvec2(eye) + r * d0, p1 = glm::dvec2(eye) + r * d1;
            const double grow = r * sagitta + 0.01;
            const float low = index.lowest(glm::min(p0, p1) - grow, glm::max(p0, p1) + grow);
            // Beyond ground with no drawn tile, a line of sight below the surface farther on
            // need not have met it: nothing from here on counts.
            if (low == kNoFloor) break;
            run = std::max(run, static_cast<float>((low - eye.z) / r));
            m_slope[static_cast<std::size_t>(b) * steps + j] = run;
        }
        // Steps past a gap keep what was found before it.
        for (std::size_t j = 1; j < steps; ++j) {
            float& s = m_slope[static_cast<std::size_t>(b) * steps + j];
            s = std::max(s, m_slope[static_cast<std::size_t>(b) * steps + j - 1]);
        }
    }
}

bool TerrainHorizon::hides(glm::dvec3 lo, glm::dvec3 hi, double keep) const {
    if (m_bins == 0) return false;
    const glm::dvec2 e(m_eye);
    if (e.x >= lo.x && e.x <= hi.x && e.y >= lo.y && e.y <= hi.y) return false;  // above or in it
    // The azimuths the box spans (less than half a turn, as the eye is outside it).
    const glm::dvec2 centre = 0.5 * (glm::dvec2(lo) + glm::dvec2(hi)) - e;
    const double mid = std::atan2(centre.y, centre.x);
    double from = 0.0, to = 0.0, r_max = 0.0;
    for (int c = 0; c < 4; ++c) {
        const glm::dvec2 d = glm::dvec2((c & 1) ? hi.x : lo.x, (c & 2) ? hi.y : lo.y) - e;
        double rel = std::atan2(d.y, d.x) - mid;
        rel = std::remainder(rel, 2.0 * std::numbers::pi);
        from = std::min(from, rel);
        to = std::max(to, rel);
        r_max = std::max(r_max, glm::length(d));
    }
    const double start = wrapPositive(mid + from - m_az_from);
    const double end = start + (to - from);
    if (end >= m_bins * m_bin_rad) return false;  // not all within the horizon's azimuths
    const glm::dvec2 gap = glm::max(glm::max(glm::dvec2(lo) - e, e - glm::dvec2(hi)), glm::dvec2(0.0));
    const double r_min = glm::length(gap);
    // The last step nearer than the nearest point of the box as drawn.
    const auto after = std::upper_bound(m_radius.begin(), m_radius.end(), keep * r_min);
    if (after == m_radius.begin()) return false;
    const auto j = static_cast<std::size_t>(after - m_radius.begin() - 1);
    // The steepest line of sight to the box: to its top, nearest where it rises above the eye.
    const double slope = hi.z >= m_eye.z ? (hi.z - m_eye.z) / r_min : (hi.z - m_eye.z) / r_max;
    const auto b0 = static_cast<std::size_t>(start / m_bin_rad), b1 = static_cast<std::size_t>(end / m_bin_rad);
    for (std::size_t b = b0; b <= b1; ++b) {
        if (!(m_slope[b * m_radius.size() + j] > slope)) return false;
    }
    return true;
}

}  // namespace navmap::render
