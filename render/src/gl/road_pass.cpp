// SPDX-License-Identifier: Apache-2.0
#include "road_pass.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <numbers>
#include <span>
#include <vector>

#include <glm/gtc/type_ptr.hpp>

#include "gl/gl_work.h"
#include "gpu_tile.h"
#include "map_culling.h"
#include "road_uniforms.h"

namespace navmap::render::gl {

namespace {

// Screen error allowed to the road levels of detail (TileMesh, kRoadLodTolerance), pixels.
constexpr float kRoadLodErrorPx = 0.5f;

}  // namespace

RoadPass::RoadPass(GLuint index_buffer)
    : m_program(ShaderProgram::fromEmbedded("roads_geo.vert", "roads_geo.frag")), m_index_buffer(index_buffer) {}

void RoadPass::buildHorizon(const FrameContext& ctx) {
    const auto t0 = Clock::now();
    const glm::dvec3 eye = ctx.frame.camera.eye;
    // The azimuths of the view's corner rays around the view's own. A view that looks down on
    // the ground below the eye spans every azimuth and sees little hidden (the bird's-eye view):
    // no horizon then.
    const glm::mat4 view_projection = ctx.projection * ctx.frame.camera.viewRelativeTo(eye);
    const glm::vec4 below = view_projection * glm::vec4(0.0f, 0.0f, -1.0f, 1.0f);
    m_horizon = {};
    if (below.w > 0.0f && std::abs(below.x) < below.w && std::abs(below.y) < below.w) return;
    const glm::mat4 to_world = glm::inverse(view_projection);
    const glm::vec4 ahead = to_world * glm::vec4(0.0f, 0.0f, 1.0f, 1.0f);
    {
        // A view looking down steeply (the bird's-eye view, 50 degrees) sees little hidden behind
        // the terrain; the snail's views look down 14 degrees.
        const glm::dvec3 forward = glm::dvec3(ahead) / double(ahead.w);
        constexpr double kSteepest = 0.6;  // radians down, about 35 degrees
        if (std::atan2(-forward.z, glm::length(glm::dvec2(forward))) > kSteepest) return;
    }
    const double mid = std::atan2(double(ahead.y / ahead.w), double(ahead.x / ahead.w));
    double from = 0.0, to = 0.0;
    for (const glm::vec2 c : {glm::vec2(-1, -1), glm::vec2(1, -1), glm::vec2(-1, 1), glm::vec2(1, 1)}) {
        const glm::vec4 p = to_world * glm::vec4(c, 1.0f, 1.0f);
        const double rel =
            std::remainder(std::atan2(double(p.y / p.w), double(p.x / p.w)) - mid, 2.0 * std::numbers::pi);
        from = std::min(from, rel);
        to = std::max(to, rel);
    }
    constexpr double kMargin = 0.05;  // radians
    const double az_from = mid + from - kMargin, az_to = mid + to + kMargin;
    // Lines of sight out to the farthest tile corner. Under the eye: the highest vertex of its
    // cell as drawn (geomorphed, as terrain_tile.vert does), which the two triangles between
    // them do not exceed.
    double last_m = 0.0;
    double ground_m = std::numeric_limits<double>::infinity();  // no tile under the eye: no horizon
    m_floors.clear();
    for (GpuTile* g : ctx.tiles) {
        const glm::dvec2 at = glm::dvec2(eye) - glm::dvec2(g->origin);  // the eye, tile-local
        const double farthest = glm::length(glm::max(glm::abs(at), glm::abs(at - double(g->size_m))));
        last_m = std::max(last_m, farthest);
        // terrain_lod.cpp morphedHeight(): level j + 1 counts where slots 0..j can morph.
        const double morph_farthest = std::sqrt(farthest * farthest + double(g->morph.eye_dz_m) * g->morph.eye_dz_m);
        int levels = 0;
        while (levels < kMorphLevels && g->morph.end_m[levels] > g->morph.start_m[levels] &&
               morph_farthest > g->morph.start_m[levels]) {
            ++levels;
        }
        if (levels != g->floor_levels) {
            g->floor = terrainFloor(glm::dvec2(g->origin), g->size_m, g->grid_size, g->heights,
                                    std::span(g->ancestor_heights).first(static_cast<std::size_t>(levels)));
            g->floor_levels = levels;
        }
        m_floors.push_back(&g->floor);
        if (g->grid_size >= 2 && at.x >= 0.0 && at.y >= 0.0 && at.x <= g->size_m && at.y <= g->size_m) {
            ground_m = g->highestDrawnAround(at) + 0.5;  // float rounding in the shader
        }
    }
    constexpr int kBins = 160;
    m_horizon.build(eye, ground_m, m_floors, az_from, az_to, kBins, last_m);
    ctx.stats.horizon_ms = msSince(t0);
}

void RoadPass::cull(const FrameContext& ctx, bool hidden) {
    const MapFrame& frame = ctx.frame;
    // A quad reaches at most half the widest footprint (casing included) beyond its end points.
    const RoadStyle& rs = ctx.style.roads;
    const float half_width = widestHalfWidth(rs);
    const float focal_px = ctx.projection[1][1] * 0.5f * static_cast<float>(ctx.target.height());
    if (hidden) buildHorizon(ctx);
    const bool test_hidden = hidden && !m_horizon.empty();
    const float widening_px = roadWideningPx(ctx.style);
    const double keep = 1.0 - rs.z_offset_alpha;  // the roads' view-space scale (seed 3.6.2)
    std::size_t blocks_hidden = 0;
    // Whether a piece's quads can show: not left out of this view (seed 7.3: from where
    // roads_geo.vert narrows its class to nothing, measured at the piece's middle as there), and
    // in it.
    std::array<float, kStyledRoadClasses> gone_m2{};
    for (std::size_t c = 0; c < gone_m2.size(); ++c)
        gone_m2[c] = ctx.selection[c].goneFromM() * ctx.selection[c].goneFromM();
    auto shows = [&](const RoadInstance& r, glm::vec3 eye, const PieceFrustum& frustum) {
        const glm::vec3 d = 0.5f * (r.p0 + r.p1) - eye;
        const auto c = static_cast<std::size_t>(
            std::clamp(static_cast<int>(std::lround(r.road_class)), 0, kStyledRoadClasses - 1));
        return glm::dot(d, d) < gone_m2[c] && frustum.holds(r, eye, half_width, rs);
    };
    m_indices.clear();
    std::vector<std::uint32_t> drawn;  // per block: the road level bit, 0 outside the view
    for (GpuTile* g : ctx.tiles) {
        g->visible_first = g->visible_casing_first = static_cast<GLsizei>(m_indices.size() / 6);
        g->visible_count = 0;
        if (g->road_pieces.empty()) continue;
        const glm::vec3 eye(frame.camera.eye - g->origin);
        const PieceFrustum frustum(g->road_cull);
        drawn.assign(g->road_blocks.size(), 0u);
        for (std::size_t b = 0; b < g->road_blocks.size(); ++b) {
            const BlockExtent& e = g->road_blocks[b];
            const QuadReach quads = quadReach(eye, e, half_width, rs);
            if (frame.layers.cull_blocks && !quadsInView(g->road_cull, e, quads.reach_m)) continue;
            if (test_hidden) {
                // Every quad drawn from the block's pieces lies in its extent grown by their
                // reach, the least-width widening (pixels at the farthest distance) and a metre.
                const double reach = quads.reach_m + widening_px * quads.farthest_m / focal_px + 1.0f;
                if (m_horizon.hides(g->origin + glm::dvec3(e.min) - reach, g->origin + glm::dvec3(e.max) + reach,
                                    keep)) {
                    ++blocks_hidden;
                    continue;
                }
            }
            // The level from the block's nearest point (its extent holds every level's pieces).
            const float distance = glm::length(eye - glm::clamp(eye, e.min, e.max));
            drawn[b] = 1u << (frame.layers.road_lod ? roadLodLevel(distance, focal_px, kRoadLodErrorPx) : 0);
        }
        // The casing pass starts at the first class that has a casing (bridges always have one).
        GLsizei casing_from = g->bridge_first;
        for (int c = 0; c < kStyledRoadClasses; ++c) {
            if (rs.classes[c].casing_m > 0.0f) casing_from = std::min(casing_from, g->class_first[c]);
        }
        bool casing_found = false;
        for (const BlockRun& run : g->road_runs) {
            if (!(drawn[run.block] & run.lods)) continue;
            if (!casing_found && static_cast<GLsizei>(run.first) >= casing_from) {
                casing_found = true;
                g->visible_casing_first = g->visible_first + g->visible_count;
            }
            for (std::uint32_t q = run.first; q < run.first + run.count; ++q) {
                if (frame.layers.cull_blocks && !shows(g->road_pieces[q], eye, frustum)) continue;
                for (const std::uint32_t i : kQuadIndices) m_indices.push_back(4 * q + i);
                ++g->visible_count;
            }
        }
        if (!casing_found) g->visible_casing_first = g->visible_first + g->visible_count;
    }
    ctx.stats.road_blocks_hidden = blocks_hidden;
}

void RoadPass::uploadIndices() {
    // Every road vertex array has this buffer bound (GpuTileCache); new storage each frame.
    glBindVertexArray(0);
    glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, m_index_buffer);
    countedBufferData(GL_ELEMENT_ARRAY_BUFFER, static_cast<GLsizeiptr>(m_indices.size() * sizeof(std::uint32_t)),
                      m_indices.data(), GL_STREAM_DRAW);
}

std::size_t RoadPass::draw(const FrameContext& ctx) {
    glUseProgram(m_program.id());
    drawWith(m_program, 0, ctx);
    return drawWith(m_program, 1, ctx);
}

std::size_t RoadPass::drawWith(ShaderProgram& program, int pass, const FrameContext& ctx) {
    setRoadUniforms(program, pass, false, ctx);
    std::size_t drawn = 0;
    for (const GpuTile* g : ctx.tiles) {
        const GLsizei first = pass == 0 ? g->visible_casing_first : g->visible_first;
        const GLsizei count = g->visible_first + g->visible_count - first;
        if (count <= 0) continue;
        glUniformMatrix4fv(program.uniform("u_view"), 1, GL_FALSE, glm::value_ptr(g->view));
        glUniformMatrix4fv(program.uniform("u_view_projection"), 1, GL_FALSE, glm::value_ptr(g->view_projection));
        glBindVertexArray(g->roads_vao);
        countedDrawElements(GL_TRIANGLES, 6 * count, GL_UNSIGNED_INT,
                            reinterpret_cast<const void*>(static_cast<std::size_t>(first) * 6 * sizeof(std::uint32_t)));
        drawn += static_cast<std::size_t>(count);
    }
    return drawn;
}

}  // namespace navmap::render::gl
