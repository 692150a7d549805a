// SPDX-License-Identifier: Apache-2.0
#pragma once
// Polygon triangulation (rings with holes) for areas and building roofs, backed by the GLU
// tessellator (libGLU from Mesa; it needs no GL context).

#include <cstdint>
#include <span>
#include <vector>

#include "navmap/map/projection.h"

namespace navmap::map {

struct Triangulation {
    /// The input ring vertices in order (rings concatenated), followed by any vertices the
    /// tessellator created at self-intersections.
    std::vector<PlanarPoint> vertices;
    /// Triangles as vertex indices, three per triangle, counter-clockwise.
    std::vector<std::uint32_t> indices;
    bool ok = true;  ///< false when the tessellator reported an error (indices then empty)
};

/// Triangulates the region enclosed by `rings` with the odd winding rule, so holes may be given
/// in any orientation and in any order. Rings are open (last point != first); rings with fewer
/// than 3 points are ignored.
Triangulation triangulate(std::span<const std::vector<PlanarPoint>> rings);

/// Total area of the triangles (m^2), for checks.
double triangulatedArea(const Triangulation& t);

}  // namespace navmap::map
