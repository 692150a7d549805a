// SPDX-License-Identifier: Apache-2.0
// The terrain surface at tile borders and of the geomorph ancestors (tile_mesh.h): the coarser
// levels' heights and normals at a tile's grid vertices, and border normals taken across each edge
// from the tile there, so shading is continuous across tile and level borders.
#include "tile_mesh.h"

#include <algorithm>
#include <array>
#include <cmath>

#include "navmap/render/terrain_lod.h"

namespace navmap::render {

namespace {

// Central-difference normal of a grid sample (one-sided at the border), as the terrain mesh uses.
glm::vec3 gridNormal(const HeightGrid& g, int r, int c) {
    const int n = g.size;
    const int c0 = std::max(c - 1, 0), c1 = std::min(c + 1, n - 1);
    const int r0 = std::max(r - 1, 0), r1 = std::min(r + 1, n - 1);
    const auto dzdx = static_cast<float>((g.at(r, c1) - g.at(r, c0)) / ((c1 - c0) * g.spacing));
    const auto dzdy = static_cast<float>((g.at(r1, c) - g.at(r0, c)) / ((r1 - r0) * g.spacing));
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

void ancestorSurface(const map::Tile& tile, int n, std::span<const float> heights, const map::Tile* ancestor,
                     int levels_up, std::vector<float>& out_heights, std::vector<glm::vec3>& out_normals,
                     const EdgeNeighbours* ancestor_neighbours) {
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
        for (int c = 0; c < ag.size; ++c) an[static_cast<std::size_t>(r) * ag.size + c] = gridNormal(ag, r, c);
    if (has_ancestor && ancestor_neighbours) {
        const glm::dvec2 origin(ancestor->origin_x, ancestor->origin_y);
        for (int r = 0; r < ag.size; ++r) {
            for (int c = 0; c < ag.size; c += (r == 0 || r == ag.size - 1) ? 1 : ag.size - 1)
                an[static_cast<std::size_t>(r) * ag.size + c] = borderNormal(ag, origin, r, c, *ancestor_neighbours);
        }
    }
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

namespace {

bool hasDem(const map::Tile* t) {
    return t && t->dem.size >= 2 && t->size_m > 0 && t->dem.heights.size() == std::size_t{t->dem.size} * t->dem.size;
}

// Height of a tile's surface (as its mesh renders it) at store-frame (x, y); a sample of its grid
// exactly where (x, y) is one (a neighbour of the same level).
float surfaceAt(const map::Tile& t, double x, double y) {
    const HeightGrid g{t.dem.size, t.size_m / (t.dem.size - 1), t.dem.heights.data()};
    const double u = (x - t.origin_x) / g.spacing, v = (y - t.origin_y) / g.spacing;
    const double cu = std::round(u), rv = std::round(v);
    if (std::abs(u - cu) < 1e-6 && std::abs(v - rv) < 1e-6 && cu >= 0 && rv >= 0 && cu < g.size && rv < g.size)
        return g.at(static_cast<int>(rv), static_cast<int>(cu));
    return static_cast<float>(g.heightAt(x - t.origin_x, y - t.origin_y));
}

}  // namespace

glm::vec3 borderNormal(const HeightGrid& g, glm::dvec2 origin, int r, int c, const EdgeNeighbours& across) {
    const int n = g.size;
    const double s = g.spacing;
    const int c0 = std::max(c - 1, 0), c1 = std::min(c + 1, n - 1);
    const int r0 = std::max(r - 1, 0), r1 = std::min(r + 1, n - 1);
    float west = g.at(r, c0), east = g.at(r, c1), south = g.at(r0, c), north = g.at(r1, c);
    double dx = (c1 - c0) * s, dy = (r1 - r0) * s;
    const double x = origin.x + c * s, y = origin.y + r * s;
    auto beyond = [&](std::size_t edge, double bx, double by, float& sample, double& span) {
        if (!hasDem(across[edge])) return;
        sample = surfaceAt(*across[edge], bx, by);
        span += s;
    };
    if (c == 0) beyond(0, x - s, y, west, dx);
    if (c == n - 1) beyond(1, x + s, y, east, dx);
    if (r == 0) beyond(2, x, y - s, south, dy);
    if (r == n - 1) beyond(3, x, y + s, north, dy);
    const float dzdx = (east - west) / static_cast<float>(dx);
    const float dzdy = (north - south) / static_cast<float>(dy);
    return glm::normalize(glm::vec3(-dzdx, -dzdy, 1.0f));
}

void seamlessBorderNormals(TileMesh& mesh, const map::Tile& tile, std::span<const map::Tile* const> ancestors,
                           std::span<const EdgeNeighbours> neighbours) {
    const int n = mesh.grid_size;
    if (!hasDem(&tile) || n != tile.dem.size || neighbours.empty()) return;
    const auto grid_vertices = static_cast<std::size_t>(n) * n;
    const glm::dvec2 origin(tile.origin_x, tile.origin_y);
    const HeightGrid grid = mesh.grid();
    for (int r = 0; r < n; ++r) {
        for (int c = 0; c < n; c += (r == 0 || r == n - 1) ? 1 : n - 1)
            mesh.terrain[static_cast<std::size_t>(r) * n + c].normal = borderNormal(grid, origin, r, c, neighbours[0]);
    }
    // The geomorph targets: an ancestor's border normals change its surface's normals up to one
    // of its cells into the tile.
    std::vector<float> heights;
    std::vector<glm::vec3> normals;
    for (std::size_t j = 0; j < kMorphLevels && j + 1 < neighbours.size(); ++j) {
        const map::Tile* ancestor = j < ancestors.size() ? ancestors[j] : nullptr;
        if (!hasDem(ancestor)) continue;
        ancestorSurface(tile, n, mesh.heights, ancestor, static_cast<int>(j) + 1, heights, normals, &neighbours[j + 1]);
        for (std::size_t i = 0; i < grid_vertices; ++i) mesh.terrain[i].ancestor_normals[j] = glm::vec2(normals[i]);
    }
    // Skirt vertices (after the grid) hang from a border vertex at their x, y and share its normals.
    const double spacing = grid.spacing;
    for (std::size_t i = grid_vertices; i < mesh.terrain.size(); ++i) {
        TerrainVertex& v = mesh.terrain[i];
        const int c = std::clamp(static_cast<int>(std::lround(v.position.x / spacing)), 0, n - 1);
        const int r = std::clamp(static_cast<int>(std::lround(v.position.y / spacing)), 0, n - 1);
        const TerrainVertex& top = mesh.terrain[static_cast<std::size_t>(r) * n + c];
        v.normal = top.normal;
        v.ancestor_normals = top.ancestor_normals;
    }
}

}  // namespace navmap::render
