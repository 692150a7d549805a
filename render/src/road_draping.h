// SPDX-License-Identifier: Apache-2.0
#pragma once
// Geometric draping of road centerlines onto a terrain grid (seed 3.6.1): every segment is
// clipped against the terrain triangles in 2D, with a vertex inserted wherever it crosses a
// triangle edge, so each piece lies in one triangle's plane and the road follows the DEM
// exactly as the terrain mesh renders it.

#include <cstdint>
#include <span>
#include <vector>

#include <glm/glm.hpp>

namespace navmap::render {

/// A square height grid in a local metric frame: sample (row, col) sits at
/// (col * spacing, row * spacing); row 0 is the south edge. Each cell is split into two
/// triangles along its south-west -> north-east diagonal; the terrain mesh of a tile uses the
/// same split (gridTriangleIndices), which is what makes draped roads lie on the surface.
struct HeightGrid {
    int size = 0;                    ///< samples per side (>= 2)
    double spacing = 1.0;            ///< metres between samples
    const float* heights = nullptr;  ///< size * size, row-major

    [[nodiscard]] float at(int row, int col) const { return heights[static_cast<std::size_t>(row) * size + col]; }
    [[nodiscard]] double extent() const { return spacing * (size - 1); }
    /// Height of the triangulated surface at (x, y); positions outside clamp to the edge.
    [[nodiscard]] double heightAt(double x, double y) const;
};

/// Triangle indices (counter-clockwise from above) of a size x size grid with the split of
/// HeightGrid; vertex index = row * size + col.
std::vector<std::uint32_t> gridTriangleIndices(int size);

/// Clips a polyline (local metres, clamped into the grid) against the grid triangles with the
/// barycentric tracing of seed 3.6.1 and returns it with heights on the surface. Consecutive
/// duplicates are dropped; the original vertices are kept.
std::vector<glm::dvec3> drapePolyline(const HeightGrid& grid, std::span<const glm::dvec2> polyline);

/// Drops the vertices of a draped polyline that a straight piece can skip: a vertex goes when the
/// 2D path stays put (every skipped vertex within 1 cm of the chord) and the chord stays within
/// `max_height_error_m` of every skipped vertex's height. The surface between two draped vertices
/// is planar, so this bounds the distance to the terrain along the whole piece. Far fewer
/// pieces to draw on gentle terrain, where draping cut a straight road at every triangle edge;
/// the bound stays inside what the view-space offset of seed 3.6.2 absorbs.
std::vector<glm::dvec3> mergeDrapedPieces(std::span<const glm::dvec3> draped, double max_height_error_m);

}  // namespace navmap::render
