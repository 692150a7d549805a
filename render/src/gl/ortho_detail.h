// SPDX-License-Identifier: Apache-2.0
#pragma once
// The procedural detail of a synthetic orthoimage (seed 6.7), drawn by OrthoGenerator over the
// basic layer once the network has filled it: field parcels over the farmland (6.7.2, grid from
// ortho/field_grid.h), plant crowns over forest and scrub (6.7.1, ortho/vegetation.h) and building
// roofs with their shadows (6.7.3). Every element takes its main colour from the basic layer at
// its pixel and varies it in pairs, so a region's mean colour stays the network's (6.7.5). The grid
// and the simulation (build) are GL-free and run beside the render thread; draw issues the GL calls.
// Private to render/.

#include <GLES3/gl3.h>

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <vector>

#include <glm/vec2.hpp>
#include <glm/vec4.hpp>

#include "navmap/map/tile.h"
#include "shader_program.h"

namespace navmap::render::gl {

class OrthoDetail {
public:
    OrthoDetail();
    ~OrthoDetail();
    OrthoDetail(const OrthoDetail&) = delete;
    OrthoDetail& operator=(const OrthoDetail&) = delete;

    struct Options {
        bool fields_and_roofs = true;  ///< seed 6.7.2, 6.7.3
        bool vegetation = false;       ///< seed 6.7.1
        bool field_mask_only = false;  ///< tests: the field parcels alone, white (their drawn area)
    };
    struct DetailVertex {
        glm::vec2 position;
        glm::vec4 params;  ///< fields: pattern, variation, hue, angle; roofs: variation, hue, height
    };
    struct PlantVertex {
        glm::vec2 centre;
        glm::vec2 corner;
        glm::vec2 plant;  ///< radius, variation
    };
    /// The detail's vertices in tile-local metres, made on the CPU.
    struct Geometry {
        std::vector<DetailVertex> fields;
        std::vector<std::uint32_t> field_index;
        std::vector<DetailVertex> roofs;
        std::vector<std::uint32_t> roof_index;
        std::vector<PlantVertex> plants;
        std::vector<std::uint32_t> plant_index;
        std::size_t parcels = 0, plant_count = 0, roofs_drawn = 0;
        double cpu_ms = 0;  ///< what building it took
    };
    /// The field grid, the roofs and the vegetation simulation of a tile. GL-free and reentrant: any
    /// thread may call it while the tile lives.
    static Geometry build(const map::Tile& tile, const Options& options);

    struct Target {
        const map::Tile* tile = nullptr;
        glm::vec2 offset{0.0f};  ///< the square [offset, offset + extent] of the tile fills the image (m)
        float extent = 0.0f;
        int size = 0;      ///< pixels per side
        GLuint basic = 0;  ///< the basic layer (RGBA8, at least size^2, row 0 south)
        bool field_mask_only = false;
    };
    /// Draws the geometry into the bound framebuffer (its viewport size^2 set, the basic layer
    /// already copied). Leaves blending off, texture unit 0 active and the vertex array binding at 0.
    /// The same as account() and the three parts below in their order.
    void draw(const Target& target, const Geometry& geometry);

    /// The parts of draw(), for a caller that spreads one image's detail over frames: the fields,
    /// then the plants in slices [first, first + count) of geometry.plant_count (the slice from 0
    /// uploads them; the detail's buffers must not be redrawn with other geometry before the last
    /// slice), then the roofs. Each leaves the state as draw() does.
    void drawFields(const Target& target, const Geometry& geometry);
    void drawPlants(const Target& target, const Geometry& geometry, std::size_t first, std::size_t count);
    void drawRoofs(const Target& target, const Geometry& geometry);
    /// Adds the geometry's counts and CPU time to timings() (once per image).
    void account(const Geometry& geometry);

    struct Timings {
        double cpu_ms = 0;   ///< field grid, vegetation simulation, vertices (beside the render thread)
        double draw_ms = 0;  ///< uploads and draw calls (the GPU work completes later)
        std::size_t parcels = 0, plants = 0, roofs = 0;
    };
    /// Accumulated since construction.
    [[nodiscard]] const Timings& timings() const { return m_timings; }

private:
    bool begin(const Target& target, ShaderProgram& program);
    void end(std::chrono::steady_clock::time_point t0);

    ShaderProgram m_fields, m_roofs, m_plants;
    GLuint m_vao = 0, m_vbo = 0, m_ibo = 0;
    GLuint m_cover = 0;  // R8UI, the tile's super land cover
    Timings m_timings;
};

}  // namespace navmap::render::gl
