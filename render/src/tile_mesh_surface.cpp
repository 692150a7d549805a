// SPDX-License-Identifier: Apache-2.0
// The terrain surface of the geomorph ancestors (tile_mesh.h): the coarser levels' heights and
// normals at a tile's grid vertices; the normals' samples around a grid vertex, across the
// tile's border with the heights beyond it.
#include "tile_mesh.h"

#include <algorithm>
#include <array>
#include <cmath>

#include "navmap/render/terrain_lod.h"

namespace navmap::render {

namespace {

// Central-difference normal of a grid sample, across the border with the samples beyond it
// where `dem` has them (normalStencil), as the terrain mesh uses.
glm::vec3 gridNormal(const HeightGrid& g, int r, int c, const map::TileDem* dem) {
    const NormalStencil s = normalStencil(g, r, c, dem);
    const auto dzdx = static_cast<float>((s.east - s.west) / (s.dx_cells * g.spacing));
    const auto dzdy = static_cast<float>((s.north - s.south) / (s.dy_cells * g.spacing));
    return glm::normalize(glm::vec3(-dzdx, -dzdy, 1.0f));
}

// Barycentric weights of (x, y) in the grid triangle containing it (HeightGrid's split along
// the cell's south-west -> north-east diagonal), with the three sample indices.
struct GridWeights {
    std::array<std::size_t, 3> index;
    std::array<double, 3> weight;
};

GridWeights gridWeights(const HeightGrid& g, double x, double y) {
    const int cells = g.size - 1;
    const double u = std::clamp(x / g.spacing, 0.0, double(cells)), v = std::clamp(y / g.spacing, 0.0, double(cells));
    const int col = std::clamp(static_cast<int>(std::floor(u)), 0, cells - 1);
    const int row = std::clamp(static_cast<int>(std::floor(v)), 0, cells - 1);
    const double fx = u - col, fy = v - row;
    const auto at = [&](int r, int c) { return static_cast<std::size_t>(r) * g.size + c; };
    if (fy <= fx) return {{at(row, col), at(row, col + 1), at(row + 1, col + 1)}, {1.0 - fx, fx - fy, fy}};  // SW SE NE
    return {{at(row, col), at(row + 1, col + 1), at(row + 1, col)}, {1.0 - fy, fx, fy - fx}};                // SW NE NW
}

}  // namespace

NormalStencil normalStencil(const HeightGrid& g, int r, int c, const map::TileDem* dem) {
    const int n = g.size;
    const int c0 = std::max(c - 1, 0), c1 = std::min(c + 1, n - 1);
    const int r0 = std::max(r - 1, 0), r1 = std::min(r + 1, n - 1);
    NormalStencil s{g.at(r, c0), g.at(r, c1), g.at(r0, c), g.at(r1, c), c1 - c0, r1 - r0};
    // The sample beyond an edge, i along it, where `dem` has one: the difference spans a cell more.
    const auto beyond = [&](map::DemEdge edge, int i, float& sample, int& cells) {
        if (!dem) return;
        const std::vector<float>& along = dem->beyond[edge];
        if (along.size() != static_cast<std::size_t>(n)) return;
        sample = along[static_cast<std::size_t>(i)];
        ++cells;
    };
    if (c == 0) beyond(map::kDemWest, r, s.west, s.dx_cells);
    if (c == n - 1) beyond(map::kDemEast, r, s.east, s.dx_cells);
    if (r == 0) beyond(map::kDemSouth, c, s.south, s.dy_cells);
    if (r == n - 1) beyond(map::kDemNorth, c, s.north, s.dy_cells);
    return s;
}

void ancestorSurface(const map::Tile& tile, int n, std::span<const float> heights, const map::Tile* ancestor,
                     int levels_up, std::vector<float>& out_heights, std::vector<glm::vec3>& out_normals) {
    const std::size_t count = static_cast<std::size_t>(n) * n;
    out_heights.assign(count, 0.0f);
    out_normals.assign(count, glm::vec3(0.0f, 0.0f, 1.0f));
    if (n < 2 || heights.size() != count) return;
    const double spacing = tile.size_m / (n - 1);
    const int stride = 1 << std::clamp(levels_up, 0, 16);
    // The ancestor's grid and where the tile's south-west corner sits in it.
    std::vector<float> decimated;
    HeightGrid ag;
    glm::dvec2 offset(0.0);
    const bool has_ancestor = ancestor && ancestor->dem.size >= 2 && ancestor->size_m > 0 &&
                              ancestor->dem.heights.size() == std::size_t{ancestor->dem.size} * ancestor->dem.size;
    if (has_ancestor) {
        ag = HeightGrid{ancestor->dem.size, ancestor->size_m / (ancestor->dem.size - 1), ancestor->dem.heights.data()};
        offset = {tile.origin_x - ancestor->origin_x, tile.origin_y - ancestor->origin_y};
    } else if ((n - 1) % stride == 0 && n > stride) {
        // Not at hand: the coarser grid of every stride-th own sample (CDLOD's usual target).
        const int m = (n - 1) / stride + 1;
        decimated.resize(static_cast<std::size_t>(m) * m);
        for (int r = 0; r < m; ++r)
            for (int c = 0; c < m; ++c)
                decimated[static_cast<std::size_t>(r) * m + c] =
                    heights[static_cast<std::size_t>(stride * r) * n + stride * c];
        ag = HeightGrid{m, stride * spacing, decimated.data()};
    } else {
        ag = HeightGrid{n, spacing, heights.data()};  // too coarse a grid to decimate: its own surface
    }
    std::vector<glm::vec3> an(static_cast<std::size_t>(ag.size) * ag.size);
    for (int r = 0; r < ag.size; ++r)
        for (int c = 0; c < ag.size; ++c)
            an[static_cast<std::size_t>(r) * ag.size + c] =
                gridNormal(ag, r, c, has_ancestor ? &ancestor->dem : nullptr);
    for (int r = 0; r < n; ++r) {
        for (int c = 0; c < n; ++c) {
            const GridWeights w = gridWeights(ag, offset.x + c * spacing, offset.y + r * spacing);
            double h = 0.0;
            glm::vec3 nrm(0.0f);
            for (std::size_t k = 0; k < 3; ++k) {
                h += w.weight[k] * ag.heights[w.index[k]];
                nrm += static_cast<float>(w.weight[k]) * an[w.index[k]];
            }
            const std::size_t i = static_cast<std::size_t>(r) * n + c;
            out_heights[i] = static_cast<float>(h);
            out_normals[i] = glm::normalize(nrm);
        }
    }
}

}  // namespace navmap::render
