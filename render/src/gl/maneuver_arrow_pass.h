// SPDX-License-Identifier: Apache-2.0
#pragma once
// The manoeuvre arrows of a map frame (MapFrame::arrows) and the roads at the next junction that
// the HUD style shows (MapFrame::guidance_roads): draped onto every drawn tile as the route is
// (seed 3.6.1, with the tile's geomorph), drawn above the route with a dark casing, the arrow head
// a wide triangle on the terrain, and, with glowing roads on, shining through buildings (seed
// 5.5.2). The map renderer hands over its tiles as ArrowTile; this class owns its programs and
// buffers. Private to render/.

#include <GLES3/gl3.h>

#include <array>
#include <cstddef>
#include <span>
#include <vector>

#include <glm/mat4x4.hpp>

#include "navmap/render/map_frame.h"
#include "quad_indices.h"
#include "render_target.h"
#include "road_draping.h"
#include "shader_program.h"
#include "tile_mesh.h"

namespace navmap::render::gl {

/// One drawn tile as the arrows need it: its grid (the route's draping grid) and this frame's
/// geomorph and view.
struct ArrowTile {
    glm::dvec3 origin{0.0};                            ///< store-frame metres of its south-west corner
    HeightGrid grid;                                   ///< its heights as drawn (size 0: nothing is draped onto it)
    std::array<HeightGrid, kMorphLevels> ancestors{};  ///< the geomorph targets' heights on its grid
    TileMorph morph;                                   ///< this frame's geomorph ranges (ancestors unused)
    glm::mat4 view{1.0f};                              ///< this frame's camera relative to origin
};

/// Needs a current GLES 3 context (create, use, destroy on its thread).
class ManeuverArrowPass {
public:
    /// Compiles arrow_geo.{vert,frag}; throws RenderError.
    ManeuverArrowPass();
    ~ManeuverArrowPass();
    ManeuverArrowPass(const ManeuverArrowPass&) = delete;
    ManeuverArrowPass& operator=(const ManeuverArrowPass&) = delete;

    /// Whether `frame` has anything for this pass.
    [[nodiscard]] static bool wanted(const MapFrame& frame) {
        return !frame.guidance_roads.empty() || !frame.arrows.empty();
    }

    /// Draws the guidance roads, then the arrows (least emphasis first), into `target` with its
    /// scene depth (LEQUAL, no depth writes), after the route and its glow. `terrain_depth`: the
    /// terrain-only depth texture of the occlusion effects (0: no glow), used when the frame has
    /// glowing roads. Leaves `target` bound for drawing and the GL state as it found it.
    void draw(const MapFrame& frame, const MapStyle& style, const RenderTarget& target, const glm::mat4& projection,
              std::span<const ArrowTile> tiles, GLuint terrain_depth);

private:
    /// One arrow or road draped onto the tiles: its quads per tile in m_vertices.
    struct Stroke {
        glm::vec4 shape{0.0f};                ///< arrow_geo.vert u_shape
        glm::vec2 widths{0.0f};               ///< u_widths
        glm::vec4 fill{0.0f}, casing{0.0f};   ///< colours (casing alpha 0: no casing pass)
        bool glows = false;                   ///< shines through buildings (arrows)
        std::size_t first_run = 0, runs = 0;  ///< into m_runs
    };
    struct Run {
        std::size_t tile = 0;          ///< index into the tiles
        GLsizei first = 0, count = 0;  ///< quads in m_vertices
    };
    void addStroke(const RouteGeometry& line, const Stroke& stroke, std::span<const ArrowTile> tiles, glm::dvec3 eye);

    ShaderProgram m_program;
    ShaderProgram m_glow;
    GLuint m_vao = 0, m_vbo = 0;
    RepeatedIndices m_quad_indices;
    std::vector<Stroke> m_strokes;
    std::vector<Run> m_runs;
    std::vector<RoutePiece> m_pieces;       // scratch
    std::vector<RoadInstance> m_instances;  // scratch
    std::vector<RoadInstance> m_vertices;   // this frame's quads, four vertices each
};

}  // namespace navmap::render::gl
