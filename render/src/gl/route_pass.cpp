// SPDX-License-Identifier: Apache-2.0
#include "route_pass.h"

#include <algorithm>
#include <array>
#include <limits>
#include <utility>
#include <vector>

#include <glm/gtc/type_ptr.hpp>

#include "gl/gl_work.h"
#include "map_culling.h"
#include "road_uniforms.h"

namespace navmap::render::gl {

RoutePass::RoutePass()
    : m_program(ShaderProgram::fromEmbedded("roads_geo.vert", "roads_geo.frag", "#define NAVMAP_ROUTE_PROGRESS 1\n")) {}

namespace {

// Screen error allowed to the route's simplification (RouteDrapeOptions::tolerance_m), pixels.
constexpr double kRouteErrorPx = 0.5;
// The tolerances are powers of two from this one up to kCoarsestToleranceM, so that a tile is
// draped again only when a view needs it at least twice as fine.
constexpr double kFinestToleranceM = 1.0 / 32.0;
constexpr double kCoarsestToleranceM = 16.0;

// The tolerance a view needs at a tile: kRouteErrorPx at the nearest point of the tile's square
// (horizontally: never more than at the tile's real distance).
double routeTolerance(const GpuTile& g, const FrameContext& ctx) {
    const double focal_px = double(ctx.projection[1][1]) * 0.5 * ctx.viewport.y;
    const glm::dvec2 eye(ctx.frame.camera.eye - g.origin);
    const glm::dvec2 nearest = glm::clamp(eye, glm::dvec2(0.0), glm::dvec2(double(g.size_m)));
    const double wanted = focal_px > 0.0 ? kRouteErrorPx * glm::length(eye - nearest) / focal_px : 0.0;
    double tolerance = kFinestToleranceM;
    while (tolerance * 2.0 <= std::min(wanted, kCoarsestToleranceM)) tolerance *= 2.0;
    return tolerance;
}

}  // namespace

void RoutePass::update(const FrameContext& ctx) {
    for (GpuTile* g : ctx.tiles) updateTile(*g, ctx);
}

bool RoutePass::routeChanged(const RouteGeometry* route) {
    const std::uint64_t version = route ? route->version : 0;
    if (route == m_route && version == m_route_version) return false;
    m_route = route;
    m_route_version = version;
    return true;
}

void RoutePass::release(GpuTile& g) {
    m_work.bytes_released +=
        g.route_pieces.capacity() * sizeof(RoutePiece) + g.route_instances.capacity() * sizeof(RoadInstance);
    std::vector<RoutePiece>().swap(g.route_pieces);
    std::vector<RoadInstance>().swap(g.route_instances);
    if (g.route_vao) {
        glDeleteVertexArrays(1, &g.route_vao);
        glDeleteBuffers(1, &g.route_vbo);
    }
    g.route_vao = g.route_vbo = 0;
    g.route_source = nullptr;
    g.route_count = 0;
    g.route_in_view = false;
    g.route_stale = true;
}

void RoutePass::drape(GpuTile& g, const RouteGeometry& route, double tolerance_m) {
    g.route_source = &route;
    g.route_version = route.version;
    g.route_points = route.points.size();
    g.route_last_measure = route.measure_m.empty() ? 0.0 : route.measure_m.back();
    g.route_tolerance_m = tolerance_m;
    g.route_pieces.clear();
    if (g.grid_size >= 2) {
        const double spacing = g.size_m / double(g.grid_size - 1);
        std::array<HeightGrid, kMorphLevels> ancestors;
        for (std::size_t j = 0; j < ancestors.size(); ++j)
            ancestors[j] = HeightGrid{g.grid_size, spacing, g.ancestor_heights[j].data()};
        RouteDrapeOptions options;
        options.tolerance_m = tolerance_m;
        RouteDrapeCounts counts;
        g.route_pieces = drapeRoute(route, g.origin, HeightGrid{g.grid_size, spacing, g.heights.data()}, ancestors,
                                    options, &counts);
        ++m_work.tiles_draped;
        m_work.segments_clipped += counts.segments_clipped;
        m_work.segments_draped += counts.segments_draped;
        m_work.segments_left_out += counts.segments_covered + counts.segments_over_limit;
    }
    // Its extent at every level it can morph to, for culling.
    g.route_extent = {glm::vec3(std::numeric_limits<float>::max()), glm::vec3(std::numeric_limits<float>::lowest())};
    for (const RoutePiece& r : g.route_pieces) {
        for (const auto& [p, ancestor_z] : {std::pair{r.p0, r.ancestor_z0}, std::pair{r.p1, r.ancestor_z1}}) {
            const auto [lowest, highest] = std::minmax_element(ancestor_z.begin(), ancestor_z.end());
            g.route_extent.min = glm::min(g.route_extent.min, glm::vec3(glm::vec2(p), std::min(p.z, *lowest)));
            g.route_extent.max = glm::max(g.route_extent.max, glm::vec3(glm::vec2(p), std::max(p.z, *highest)));
        }
    }
    g.route_count = 0;
    g.route_instances.clear();
    g.route_stale = true;
    if (g.route_pieces.empty() || g.route_vao) return;
    glGenVertexArrays(1, &g.route_vao);
    glGenBuffers(1, &g.route_vbo);
    glBindVertexArray(g.route_vao);
    glBindBuffer(GL_ARRAY_BUFFER, g.route_vbo);
    setupRoadAttributes();
    glBindVertexArray(0);
}

void RoutePass::updateTile(GpuTile& g, const FrameContext& ctx) {
    const MapFrame& frame = ctx.frame;
    // Draped per tile against the grid it is drawn with (seed 3.6.1), so the route lies on the
    // terrain at every level of detail; redone when the route or the tile's upload changes, or
    // when this view needs it finer than it was simplified.
    const RouteGeometry& route = *frame.route;
    const double last = route.measure_m.empty() ? 0.0 : route.measure_m.back();
    const double tolerance = routeTolerance(g, ctx);
    const bool same_route = g.route_source == &route && g.route_version == route.version &&
                            g.route_points == route.points.size() && g.route_last_measure == last;
    if (!same_route || tolerance < g.route_tolerance_m) {
        if (m_work.segments_clipped < kRouteSegmentsPerFrame) {
            drape(g, route, tolerance);
            if (g.route_pieces.empty()) return;
        } else {
            // This frame's draping is spent (a route that crosses the drawn tiles again and
            // again): the tile is draped in a later frame, the nearest tiles first. Until then it
            // keeps a coarser draping of the same route, or draws none.
            ++m_work.tiles_deferred;
            if (!same_route) {
                g.route_source = nullptr;
                g.route_pieces.clear();
                g.route_instances.clear();
                g.route_count = 0;
                g.route_in_view = false;
                return;
            }
        }
    }
    m_work.pieces += g.route_pieces.size();
    // Not in view: neither morphed nor drawn this frame (half its outer width around its extent,
    // as roads_geo.vert draws it).
    const glm::vec3 eye(frame.camera.eye - g.origin);
    g.route_in_view =
        !g.route_pieces.empty() &&
        (!frame.layers.cull_blocks ||
         quadsInView(
             g.road_cull, g.route_extent,
             quadReach(eye, g.route_extent, 0.5f * routeOuterWidth(ctx.style.route_width_m), ctx.style.roads).reach_m));
    if (!g.route_in_view) return;
    if (!g.route_stale && g.morph.end_m[0] <= 0.0f && !g.route_morphed) return;  // unmorphed: the buffer is current
    g.route_stale = false;
    g.route_morphed = g.morph.end_m[0] > 0.0f;
    // The pieces follow the terrain's geomorph (the same factor per vertex as terrain_tile.vert).
    morphRoute(g.route_pieces, g.morph, glm::vec2(eye), g.route_instances);
    const auto quads = quadVertices(g.route_instances);
    glBindVertexArray(g.route_vao);
    m_quad_indices.bind(g.route_instances.size());
    glBindBuffer(GL_ARRAY_BUFFER, g.route_vbo);
    countedBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(quads.size() * sizeof(RoadInstance)), quads.data(),
                      GL_STREAM_DRAW);
    glBindVertexArray(0);
    glBindBuffer(GL_ARRAY_BUFFER, 0);
    g.route_count = static_cast<GLsizei>(g.route_instances.size());
    m_work.pieces_uploaded += g.route_instances.size();
}

void RoutePass::draw(const FrameContext& ctx) {
    glUseProgram(m_program.id());
    for (int pass = 0; pass < 2; ++pass) drawWith(m_program, pass, ctx);
}

void RoutePass::drawWith(ShaderProgram& program, int pass, const FrameContext& ctx) {
    setRoadUniforms(program, pass, true, ctx);
    glUniform1f(program.uniform("u_route_progress"), static_cast<float>(ctx.frame.route_progress_m));
    for (const GpuTile* g : ctx.tiles) {
        if (!g->route_count || !g->route_in_view) continue;
        glUniformMatrix4fv(program.uniform("u_view"), 1, GL_FALSE, glm::value_ptr(g->view));
        glUniformMatrix4fv(program.uniform("u_view_projection"), 1, GL_FALSE, glm::value_ptr(g->view_projection));
        glBindVertexArray(g->route_vao);
        m_quad_indices.draw(0, g->route_count);
    }
}

}  // namespace navmap::render::gl
