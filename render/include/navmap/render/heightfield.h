// SPDX-License-Identifier: Apache-2.0
#pragma once
// A terrain mesh built from a DEM grid on the CPU (GL-free, so it is unit-testable).

#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

namespace navmap::map {
struct Dem;
class Projection;
}  // namespace navmap::map

namespace navmap::render {

/// Interleaved vertices (position relative to `origin`, unit normal) and triangle indices.
struct HeightfieldMesh {
    struct Vertex {
        glm::vec3 position;  ///< metres, relative to origin (x east, y north, z up)
        glm::vec3 normal;
    };
    glm::dvec3 origin{0.0};  ///< planar metres of the first vertex's frame
    std::vector<Vertex> vertices;
    std::vector<std::uint32_t> indices;
    float min_height = 0.0f;
    float max_height = 0.0f;
};

/// Builds a regular triangulated grid from `dem` (which must not contain voids: fill them
/// first), projecting every sample with `projection`. `stride` > 1 takes every stride-th
/// sample. Normals come from central differences of the projected positions.
HeightfieldMesh buildHeightfield(const map::Dem& dem, const map::Projection& projection, int stride = 1);

}  // namespace navmap::render
