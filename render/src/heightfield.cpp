// SPDX-License-Identifier: Apache-2.0
#include "navmap/render/heightfield.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "navmap/map/dem.h"
#include "navmap/map/projection.h"

namespace navmap::render {

HeightfieldMesh buildHeightfield(const map::Dem& dem, const map::Projection& projection, int stride) {
    if (stride < 1) stride = 1;
    const int rows = (dem.rows - 1) / stride + 1;
    const int cols = (dem.cols - 1) / stride + 1;
    if (rows < 2 || cols < 2) throw std::invalid_argument("buildHeightfield: grid needs at least 2x2 samples");

    HeightfieldMesh mesh;
    const map::PlanarPoint o = projection.forward(dem.north, dem.west);
    mesh.origin = glm::dvec3(o.x, o.y, 0.0);
    mesh.vertices.resize(static_cast<std::size_t>(rows) * cols);
    mesh.min_height = std::numeric_limits<float>::max();
    mesh.max_height = std::numeric_limits<float>::lowest();
    for (int r = 0; r < rows; ++r) {
        const double lat = dem.north - r * stride * dem.spacing;
        for (int c = 0; c < cols; ++c) {
            const double lon = dem.west + c * stride * dem.spacing;
            const map::PlanarPoint p = projection.forward(lat, lon);
            const float h = dem.at(r * stride, c * stride);
            if (std::isnan(h)) throw std::invalid_argument("buildHeightfield: DEM has unfilled voids");
            mesh.vertices[static_cast<std::size_t>(r) * cols + c].position =
                glm::vec3(static_cast<float>(p.x - o.x), static_cast<float>(p.y - o.y), h);
            mesh.min_height = std::min(mesh.min_height, h);
            mesh.max_height = std::max(mesh.max_height, h);
        }
    }
    auto pos = [&](int r, int c) {
        r = std::clamp(r, 0, rows - 1);
        c = std::clamp(c, 0, cols - 1);
        return mesh.vertices[static_cast<std::size_t>(r) * cols + c].position;
    };
    for (int r = 0; r < rows; ++r) {
        for (int c = 0; c < cols; ++c) {
            const glm::vec3 dx = pos(r, c + 1) - pos(r, c - 1);  // towards east
            const glm::vec3 dy = pos(r - 1, c) - pos(r + 1, c);  // towards north (row 0 is north)
            mesh.vertices[static_cast<std::size_t>(r) * cols + c].normal = glm::normalize(glm::cross(dx, dy));
        }
    }
    mesh.indices.reserve(static_cast<std::size_t>(rows - 1) * (cols - 1) * 6);
    for (int r = 0; r + 1 < rows; ++r) {
        for (int c = 0; c + 1 < cols; ++c) {
            const auto i00 = static_cast<std::uint32_t>(r * cols + c);
            const auto i01 = i00 + 1;
            const auto i10 = static_cast<std::uint32_t>((r + 1) * cols + c);
            const auto i11 = i10 + 1;
            // Counter-clockwise seen from above (z up): row r+1 lies south of row r.
            mesh.indices.insert(mesh.indices.end(), {i00, i10, i11, i00, i11, i01});
        }
    }
    return mesh;
}

}  // namespace navmap::render
