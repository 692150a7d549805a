// SPDX-License-Identifier: Apache-2.0
#include "maneuver_arrow_pass.h"

#include "gl_state_scope.h"
#include "vertex_layout.h"

#include <algorithm>
#include <cstddef>
#include <numeric>

#include <glm/gtc/type_ptr.hpp>

#include "gl/gl_work.h"
#include "navmap/render/maneuver_arrow.h"

namespace navmap::render::gl {

namespace {

constexpr std::uint32_t kQuad[6] = {0, 1, 2, 2, 1, 3};
// Stencil bit the arrows' glow uses so that overlapping pieces blend once (the roads' glow uses
// it the same way before, occlusion_effects.cpp; cleared here before use).
constexpr GLuint kGlowStencilBit = 0x80;
// A measure no stroke reaches: guidance roads have no head.
constexpr float kNoHead = 1e9f;
// The arrows lie above the route: a larger view-space offset (seed 3.6.2; the route takes 1.5
// times the roads', map_renderer.cpp).
constexpr float kArrowOffsetFactor = 2.0f;

}  // namespace

ManeuverArrowPass::ManeuverArrowPass()
    : m_program(ShaderProgram::fromEmbedded("arrow_geo.vert", "arrow_geo.frag")),
      m_glow(ShaderProgram::fromEmbedded("arrow_geo.vert", "arrow_geo.frag", "#define NAVMAP_ARROW_GLOW 1\n")),
      m_quad_indices(kQuad, 4) {
    glGenVertexArrays(1, &m_vao);
    glGenBuffers(1, &m_vbo);
    glBindVertexArray(m_vao);
    glBindBuffer(GL_ARRAY_BUFFER, m_vbo);
    // The route's vertex layout (RoadInstance per quad corner); arrow_geo.vert reads p0, p1 and
    // the measures.
    setVertexAttributes(sizeof(RoadInstance), {{0, 3, GL_FLOAT, offsetof(RoadInstance, p0)},
                                               {1, 3, GL_FLOAT, offsetof(RoadInstance, p1)},
                                               {4, 2, GL_FLOAT, offsetof(RoadInstance, measure0)}});
    glBindVertexArray(0);
    glBindBuffer(GL_ARRAY_BUFFER, 0);
}

ManeuverArrowPass::~ManeuverArrowPass() {
    glDeleteVertexArrays(1, &m_vao);
    glDeleteBuffers(1, &m_vbo);
}

void ManeuverArrowPass::addStroke(const RouteGeometry& line, const Stroke& stroke, std::span<const ArrowTile> tiles,
                                  glm::dvec3 eye) {
    Stroke s = stroke;
    s.first_run = m_runs.size();
    for (std::size_t ti = 0; ti < tiles.size(); ++ti) {
        const ArrowTile& t = tiles[ti];
        if (t.grid.size < 2) continue;
        // seed 3.6.1: draped per tile against the grid it is drawn with, following its geomorph.
        m_pieces = drapeRoute(line, t.origin, t.grid, t.ancestors);
        if (m_pieces.empty()) continue;
        morphRoute(m_pieces, t.morph, glm::vec2(eye - t.origin), m_instances);
        const auto first = static_cast<GLsizei>(m_vertices.size() / 4);
        for (const RoadInstance& r : m_instances) m_vertices.insert(m_vertices.end(), 4, r);
        m_runs.push_back({ti, first, static_cast<GLsizei>(m_instances.size())});
    }
    s.runs = m_runs.size() - s.first_run;
    if (s.runs > 0) m_strokes.push_back(s);
}

void ManeuverArrowPass::draw(const MapFrame& frame, const MapStyle& style, const RenderTarget& target,
                             const glm::mat4& projection, std::span<const ArrowTile> tiles, GLuint terrain_depth) {
    m_strokes.clear();
    m_runs.clear();
    m_vertices.clear();
    const glm::dvec3 eye = frame.camera.eye;
    // Guidance roads first: under the arrows.
    for (const std::vector<glm::dvec3>& road : frame.guidance_roads) {
        RouteGeometry line;
        double m = 0.0;
        for (std::size_t i = 0; i < road.size(); ++i) {
            if (i > 0) m += glm::length(glm::dvec2(road[i]) - glm::dvec2(road[i - 1]));
            line.points.push_back(road[i]);
            line.measure_m.push_back(m);
        }
        Stroke s;
        s.shape = {kNoHead, kNoHead, kNoHead, 0.0f};
        s.widths = glm::vec2(0.5f * style.guidance_road_width_m);
        s.fill = glm::vec4(style.guidance_road_color, 1.0f);
        addStroke(line, s, tiles, eye);
    }
    // Arrows, least emphasis first, so the next manoeuvre's lies on top.
    std::vector<std::size_t> order(frame.arrows.size());
    std::iota(order.begin(), order.end(), std::size_t{0});
    std::stable_sort(order.begin(), order.end(),
                     [&](std::size_t a, std::size_t b) { return frame.arrows[a].emphasis < frame.arrows[b].emphasis; });
    for (std::size_t i : order) {
        const ManeuverArrow& arrow = frame.arrows[i];
        if (arrow.emphasis <= 0.0f) continue;
        // The arrow points carry no height: taken at the ground the camera looks at.
        const float grow = arrowScale(arrow, style, eye, frame.camera.target.z,
                                      projection[1][1] * 0.5f * static_cast<float>(target.height()));
        const ArrowShape shape = arrowShape(arrow, style, grow);
        if (shape.line.points.size() < 2) continue;
        const float e = std::min(arrow.emphasis, 1.0f);
        Stroke s;
        s.shape = {static_cast<float>(shape.head_m), static_cast<float>(shape.tip_m),
                   static_cast<float>(shape.casing_tip_m), shape.casing_m};
        s.widths = {shape.half_width_m, shape.head_half_width_m};
        // Fainter: towards the route's colours, which the arrow lies on.
        s.fill = glm::vec4(glm::mix(style.route_color, style.arrow_fill, e), 1.0f);
        s.casing = glm::vec4(glm::mix(style.route_casing, style.arrow_casing, e), shape.casing_m > 0.0f ? 1.0f : 0.0f);
        s.glows = true;
        addStroke(shape.line, s, tiles, eye);
    }
    if (m_strokes.empty()) return;

    const GlStateScope saved;
    target.bindForDrawing(false);
    glBindVertexArray(m_vao);
    m_quad_indices.bind(m_vertices.size() / 4);
    glBindBuffer(GL_ARRAY_BUFFER, m_vbo);
    countedBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(m_vertices.size() * sizeof(RoadInstance)),
                      m_vertices.data(), GL_STREAM_DRAW);
    glBindBuffer(GL_ARRAY_BUFFER, 0);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LEQUAL);
    glDepthMask(GL_FALSE);
    glDisable(GL_CULL_FACE);
    glDisable(GL_BLEND);
    glDisable(GL_STENCIL_TEST);
    glUseProgram(m_program.id());
    // Per stroke its casing, then its fill: a later stroke lies wholly on an earlier one.
    for (const Stroke& s : m_strokes) {
        for (int pass = s.casing.a > 0.0f ? 0 : 1; pass < 2; ++pass) {
            glUniform4fv(m_program.uniform("u_color"), 1, glm::value_ptr(pass == 0 ? s.casing : s.fill));
            glUniform1i(m_program.uniform("u_pass"), pass);
            glUniform4fv(m_program.uniform("u_shape"), 1, glm::value_ptr(s.shape));
            glUniform2fv(m_program.uniform("u_widths"), 1, glm::value_ptr(s.widths));
            glUniform1f(m_program.uniform("u_z_offset"), kArrowOffsetFactor * style.roads.z_offset_alpha);
            glUniformMatrix4fv(m_program.uniform("u_projection"), 1, GL_FALSE, glm::value_ptr(projection));
            for (std::size_t r = s.first_run; r < s.first_run + s.runs; ++r) {
                glUniformMatrix4fv(m_program.uniform("u_view"), 1, GL_FALSE,
                                   glm::value_ptr(tiles[m_runs[r].tile].view));
                m_quad_indices.draw(m_runs[r].first, m_runs[r].count);
            }
        }
    }

    // seed 5.5.2: the arrows' hidden fill shines through buildings where the roads glow, in the
    // arrow's own colour (the single glow colour would merge it with the route's glow).
    const MapLayers& l = frame.layers;
    const bool glow = terrain_depth != 0 && l.glow_roads && l.buildings;
    if (glow) {
        const float strength = std::clamp(style.glow_strength, 0.0f, 1.0f);
        glDepthFunc(GL_GREATER);
        glEnable(GL_BLEND);
        glBlendFuncSeparate(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA, GL_ZERO, GL_ONE);  // the frame stays opaque
        glUseProgram(m_glow.id());
        glActiveTexture(GL_TEXTURE1);
        glBindTexture(GL_TEXTURE_2D, terrain_depth);
        glUniform1i(m_glow.uniform("u_terrain_depth"), 1);
        glActiveTexture(GL_TEXTURE0);
        glUniform1i(m_glow.uniform("u_pass"), 1);
        glUniform1f(m_glow.uniform("u_z_offset"), kArrowOffsetFactor * style.roads.z_offset_alpha);
        glUniformMatrix4fv(m_glow.uniform("u_projection"), 1, GL_FALSE, glm::value_ptr(projection));
        glEnable(GL_STENCIL_TEST);
        glStencilMask(kGlowStencilBit);
        for (const Stroke& s : m_strokes) {
            if (!s.glows) continue;
            // Overlapping pieces of one arrow blend once: the stencil bit, cleared per arrow.
            const GLint zero = 0;
            glClearBufferiv(GL_STENCIL, 0, &zero);
            glStencilFunc(GL_NOTEQUAL, kGlowStencilBit, kGlowStencilBit);
            glStencilOp(GL_KEEP, GL_KEEP, GL_REPLACE);
            glUniform4fv(m_glow.uniform("u_color"), 1, glm::value_ptr(glm::vec4(glm::vec3(s.fill), strength)));
            glUniform4fv(m_glow.uniform("u_shape"), 1, glm::value_ptr(s.shape));
            glUniform2fv(m_glow.uniform("u_widths"), 1, glm::value_ptr(s.widths));
            for (std::size_t r = s.first_run; r < s.first_run + s.runs; ++r) {
                glUniformMatrix4fv(m_glow.uniform("u_view"), 1, GL_FALSE, glm::value_ptr(tiles[m_runs[r].tile].view));
                m_quad_indices.draw(m_runs[r].first, m_runs[r].count);
            }
        }
        glActiveTexture(GL_TEXTURE1);
        glBindTexture(GL_TEXTURE_2D, 0);
        glActiveTexture(GL_TEXTURE0);
    }
    glUseProgram(0);
}

}  // namespace navmap::render::gl
