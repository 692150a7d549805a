// SPDX-License-Identifier: Apache-2.0
#pragma once
// Polygon triangulation (rings with holes) for areas and building roofs, backed by CGAL's
// constrained Delaunay triangulation (libcgal-dev, header-only; no GL library involved).

#include <cstdint>
#include <span>
#include <vector>

#include "navmap/map/projection.h"

namespace navmap::map {

struct Triangulation {
    /// The input ring vertices in order (rings concatenated), followed by any vertices the
    /// triangulator created where edges cross (self-intersecting rings).
    std::vector<PlanarPoint> vertices;
    /// Triangles as vertex indices, three per triangle, counter-clockwise.
    std::vector<std::uint32_t> indices;
    /// false when the input cannot be triangulated (a non-finite coordinate, a failure inside
    /// CGAL); indices are then empty. Input with no area (collinear points) gives ok and no
    /// triangles.
    bool ok = true;
};

/// Triangulates the region enclosed by `rings` with the odd winding rule, so holes may be given
/// in any orientation and in any order; an edge given twice (a zero-width bridge, two rings
/// sharing an edge) encloses nothing. Rings are open (last point != first); rings with fewer
/// than 3 points are ignored, repeated consecutive points are skipped.
Triangulation triangulate(std::span<const std::vector<PlanarPoint>> rings);

/// Total area of the triangles (m^2), for checks.
double triangulatedArea(const Triangulation& t);

}  // namespace navmap::map
