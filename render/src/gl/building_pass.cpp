// SPDX-License-Identifier: Apache-2.0
#include "building_pass.h"

#include <cstdint>

#include <glm/gtc/type_ptr.hpp>

#include "gl/gl_work.h"
#include "map_culling.h"

namespace navmap::render::gl {

BuildingPass::BuildingPass() : m_program(ShaderProgram::fromEmbedded("buildings.vert", "buildings.frag")) {}

void BuildingPass::draw(const FrameContext& ctx) {
    glDepthFunc(GL_LESS);
    glEnable(GL_CULL_FACE);
    glUseProgram(m_program.id());
    ctx.stats.building_triangles += drawWith(m_program, ctx);
}

std::size_t BuildingPass::drawWith(ShaderProgram& p, const FrameContext& ctx) {
    const MapStyle& style = ctx.style;
    glUniformMatrix4fv(p.uniform("u_projection"), 1, GL_FALSE, glm::value_ptr(ctx.projection));
    glUniform3fv(p.uniform("u_light_dir"), 1, glm::value_ptr(glm::normalize(style.light_dir)));
    glUniform3fv(p.uniform("u_sky_color"), 1, glm::value_ptr(style.sky_color));
    glUniform2f(p.uniform("u_fog_range"), style.fog_start_m, style.fog_end_m);
    glUniform1f(p.uniform("u_brightness"), style.brightness);
    glUniform1f(p.uniform("u_cull_ratio"), style.building_cull_ratio);
    std::size_t drawn = 0;
    for (const GpuTile* g : ctx.tiles) drawn += drawTile(p, ctx, *g);
    return drawn;
}

std::size_t BuildingPass::drawTile(ShaderProgram& program, const FrameContext& ctx, const GpuTile& g) {
    if (!g.building_index_count) return 0;
    glUniformMatrix4fv(program.uniform("u_view"), 1, GL_FALSE, glm::value_ptr(g.view));
    glBindVertexArray(g.buildings_vao);
    // The blocks in view, consecutive ones in one draw.
    auto visible = [&](const BlockRun& run) {
        const BlockExtent& e = g.building_blocks[run.block];
        return !ctx.layers().cull_blocks || boxInView(g.view_projection, e.min, e.max);
    };
    std::size_t drawn = 0;
    for (std::size_t r = 0; r < g.building_runs.size();) {
        if (!visible(g.building_runs[r++])) continue;
        const std::uint32_t first = g.building_runs[r - 1].first;
        std::uint32_t count = g.building_runs[r - 1].count;
        for (; r < g.building_runs.size() && visible(g.building_runs[r]); ++r) count += g.building_runs[r].count;
        countedDrawElements(GL_TRIANGLES, static_cast<GLsizei>(count), GL_UNSIGNED_INT,
                            reinterpret_cast<const void*>(std::size_t{first} * sizeof(std::uint32_t)));
        drawn += count / 3;
    }
    return drawn;
}

}  // namespace navmap::render::gl
