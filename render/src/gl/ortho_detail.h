// SPDX-License-Identifier: Apache-2.0
#pragma once
// The procedural detail of a synthetic orthoimage (seed 6.7), drawn by OrthoGenerator over the
// basic layer once the network has filled it: field parcels over the farmland (6.7.2, grid from
// ortho/field_grid.h), plant crowns over forest and scrub (6.7.1, ortho/vegetation.h) and building
// roofs with their shadows (6.7.3). Every element takes its main colour from the basic layer at
// its pixel and varies it in pairs, so a region's mean colour stays the network's (6.7.5). The
// grid and the simulation run on the CPU of the calling (render) thread. Private to render/.

#include <GLES3/gl3.h>

#include <cstddef>

#include <glm/vec2.hpp>

#include "navmap/map/tile.h"
#include "shader_program.h"

namespace navmap::render::gl {

class OrthoDetail {
public:
    OrthoDetail();
    ~OrthoDetail();
    OrthoDetail(const OrthoDetail&) = delete;
    OrthoDetail& operator=(const OrthoDetail&) = delete;

    struct Target {
        const map::Tile* tile = nullptr;
        glm::vec2 offset{0.0f};  ///< the square [offset, offset + extent] of the tile fills the image (m)
        float extent = 0.0f;
        int size = 0;      ///< pixels per side
        GLuint basic = 0;  ///< the basic layer (RGBA8, at least size^2, row 0 south)
        bool fields_and_roofs = true;
        bool vegetation = false;
    };
    /// Draws into the bound framebuffer (its viewport size^2 set, the basic layer already copied).
    /// Leaves blending off, texture unit 0 active and the vertex array binding at 0.
    void draw(const Target& target);

    /// Tests: draw the field parcels alone, white (their drawn area), and nothing else.
    void setFieldMaskOnly(bool on) { m_field_mask_only = on; }

    struct Timings {
        double cpu_ms = 0;   ///< field grid, vegetation simulation, vertices
        double draw_ms = 0;  ///< uploads and draw calls (the GPU work completes later)
        std::size_t parcels = 0, plants = 0, roofs = 0;
    };
    /// Accumulated since construction.
    [[nodiscard]] const Timings& timings() const { return m_timings; }

private:
    ShaderProgram m_fields, m_roofs, m_plants;
    GLuint m_vao = 0, m_vbo = 0, m_ibo = 0;
    GLuint m_cover = 0;  // R8UI, the tile's super land cover
    bool m_field_mask_only = false;
    Timings m_timings;
};

}  // namespace navmap::render::gl
