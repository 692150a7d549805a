// SPDX-License-Identifier: Apache-2.0
#include "terrain_pass.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <numeric>

#include <glm/gtc/type_ptr.hpp>

#include "gl/gl_work.h"
#include "gpu_tile.h"
#include "map_culling.h"

namespace navmap::render::gl {

namespace {

// The land-cover levels a tile's pixels reach this frame (0 its own raster, 1 the parent's, 2 the
// grandparent's; terrain_tile.frag): from the finest some vertex has not morphed away from to the
// coarsest some vertex morphs into. Distances are measured as the geomorph measures them
// (terrain_lod.h: horizontal, plus the camera's distance from the LOD height band); the slots'
// ranges are disjoint and increasing (morph_start > 0.5).
struct CoverLevels {
    int finest = 0, coarsest = 0;
};
bool operator==(CoverLevels a, CoverLevels b) { return a.finest == b.finest && a.coarsest == b.coarsest; }
/// For the part [lo, hi] (tile-local x, y) of a tile seen from tile-local `eye`.
CoverLevels coverLevels(const TileMorph& m, glm::vec2 eye, glm::vec2 lo, glm::vec2 hi) {
    const glm::vec2 near = glm::max(glm::max(lo - eye, eye - hi), glm::vec2(0.0f));
    const glm::vec2 far = glm::max(glm::abs(eye - lo), glm::abs(eye - hi));
    const float nx = near.x, ny = near.y, fx = far.x, fy = far.y;
    const float dz2 = m.eye_dz_m * m.eye_dz_m;
    const float nearest = std::sqrt(nx * nx + ny * ny + dz2), farthest = std::sqrt(fx * fx + fy * fy + dz2);
    CoverLevels c;
    for (int j = 0; j < 2; ++j) {
        const auto k = static_cast<std::size_t>(j);
        if (m.end_m[k] <= m.start_m[k]) break;  // no morph in this slot (the shader's test)
        if (c.finest == j && nearest >= m.end_m[k]) c.finest = j + 1;
        if (farthest > m.start_m[k]) c.coarsest = j + 1;
    }
    return c;
}

std::size_t indexBytes(GLenum type) {
    return type == GL_UNSIGNED_SHORT ? sizeof(std::uint16_t) : sizeof(std::uint32_t);
}

}  // namespace

TerrainPass::TerrainPass()
    : m_plain(ShaderProgram::fromEmbedded("terrain_tile.vert", "terrain_tile.frag")),
      m_cover{
          ShaderProgram::fromEmbedded("terrain_tile.vert", "terrain_tile.frag", "#define NAVMAP_COVER_LEVELS 2\n"),
          ShaderProgram::fromEmbedded("terrain_tile.vert", "terrain_tile.frag", "#define NAVMAP_COVER_LEVELS 3\n")} {
    const std::uint8_t transparent[4] = {0, 0, 0, 0};
    glGenTextures(1, &m_empty_texture);
    glBindTexture(GL_TEXTURE_2D, m_empty_texture);
    countedTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, 1, 1, 0, GL_RGBA, GL_UNSIGNED_BYTE, transparent);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    glBindTexture(GL_TEXTURE_2D, 0);
}

TerrainPass::~TerrainPass() { glDeleteTextures(1, &m_empty_texture); }

void TerrainPass::draw(const FrameContext& ctx) {
    const MapFrame& frame = ctx.frame;
    const MapStyle& style = ctx.style;
    const glm::vec3 light = glm::normalize(style.light_dir);
    for (ShaderProgram* p : {&m_plain, &m_cover[0], &m_cover[1]}) {
        glUseProgram(p->id());
        glUniformMatrix4fv(p->uniform("u_projection"), 1, GL_FALSE, glm::value_ptr(ctx.projection));
        glUniform3fv(p->uniform("u_light_dir"), 1, glm::value_ptr(light));
        glUniform3fv(p->uniform("u_sky_color"), 1, glm::value_ptr(style.sky_color));
        glUniform2f(p->uniform("u_fog_range"), style.fog_start_m, style.fog_end_m);
        glUniform1f(p->uniform("u_brightness"), style.brightness);
        glUniform1i(p->uniform("u_land_cover"), 0);
        glUniform1i(p->uniform("u_cover1"), 1);
        glUniform1i(p->uniform("u_cover2"), 2);
    }
    const ShaderProgram* bound = nullptr;
    for (const GpuTile* g : ctx.tiles) {
        const glm::vec2 eye(static_cast<float>(frame.camera.eye.x - g->origin.x),
                            static_cast<float>(frame.camera.eye.y - g->origin.y));
        // Land cover of the levels each block of the tile reaches (morphing with the surface);
        // an ancestor with no land cover here shows none, one not resident is stood in for by
        // the next finer level.
        std::array<GLuint, 3> cover{m_empty_texture, m_empty_texture, m_empty_texture};
        // The orthoimage (seed ch. 6) takes the land cover's place once it is ready: opaque, so
        // the hypsometric tint does not show through (terrain_tile.frag). One level: the tile's
        // own image, also where the surface morphs towards its ancestors (their images are made
        // when they are drawn themselves).
        const bool ortho = frame.layers.land_cover && style.ground == Ground::Orthoimage && g->ortho_ready;
        const bool morph_cover = frame.layers.land_cover && g->morph_ancestors[0] && !ortho;
        if (ortho) {
            cover.fill(g->ortho);
        } else if (frame.layers.land_cover) {
            if (g->land_cover) cover[0] = g->land_cover;
            if (g->ancestor_cover[0]) cover[1] = g->ancestor_cover[0];
            cover[2] =
                !g->morph_ancestors[1] ? cover[1] : (g->ancestor_cover[1] ? g->ancestor_cover[1] : m_empty_texture);
        }
        glBindVertexArray(g->terrain_vao);
        std::array<bool, 3> has_tile_uniforms{};  // per program: plain, 2 levels, 3 levels
        // Blocks outside the view are skipped; consecutive ones that need the same land-cover
        // levels are one draw.
        auto visible = [&](const TerrainBlock& k) { return boxInView(g->view_projection, k); };
        auto levels_of = [&](const TerrainBlock& k) {
            return morph_cover ? coverLevels(g->morph, eye, k.min, k.max) : CoverLevels{};
        };
        // Nearest blocks first, like the tiles (a tile's hills hide its farther blocks before
        // they are shaded); a block that follows its predecessor in the index buffer and needs
        // the same levels joins its draw.
        m_block_order.resize(g->terrain_blocks.size());
        std::iota(m_block_order.begin(), m_block_order.end(), std::size_t{0});
        auto distance2 = [&](std::size_t i) {
            const glm::vec2 d = 0.5f * (g->terrain_blocks[i].min + g->terrain_blocks[i].max) - eye;
            return glm::dot(d, d);
        };
        std::sort(m_block_order.begin(), m_block_order.end(),
                  [&](std::size_t a, std::size_t c) { return distance2(a) < distance2(c); });
        for (std::size_t b = 0; b < m_block_order.size();) {
            const std::size_t first_index = m_block_order[b++];
            const TerrainBlock& first = g->terrain_blocks[first_index];
            if (!visible(first)) continue;
            const CoverLevels levels = levels_of(first);
            std::uint32_t count = first.count;
            for (std::size_t last = first_index; b < m_block_order.size() && m_block_order[b] == last + 1;
                 ++b, ++last) {
                const TerrainBlock& next = g->terrain_blocks[m_block_order[b]];
                if (!visible(next) || !(levels_of(next) == levels)) break;
                count += next.count;
            }
            ctx.stats.terrain_triangles += count / 3;
            const int n = levels.coarsest - levels.finest + 1;
            ShaderProgram& p = n == 1 ? m_plain : m_cover[n - 2];
            if (bound != &p) {
                glUseProgram(p.id());
                bound = &p;
            }
            if (!has_tile_uniforms[static_cast<std::size_t>(n - 1)]) {
                has_tile_uniforms[static_cast<std::size_t>(n - 1)] = true;
                glUniformMatrix4fv(p.uniform("u_view"), 1, GL_FALSE, glm::value_ptr(g->view));
                glUniform1f(p.uniform("u_tile_size"), g->size_m);
                glUniform4fv(p.uniform("u_morph_start"), 1, g->morph.start_m.data());
                glUniform4fv(p.uniform("u_morph_end"), 1, g->morph.end_m.data());
                glUniform1f(p.uniform("u_morph_eye_dz"), g->morph.eye_dz_m);
                glUniform2fv(p.uniform("u_morph_eye"), 1, glm::value_ptr(eye));
            }
            if (n > 1)
                glUniform2f(p.uniform("u_cover_slot"), levels.finest == 0 ? 1.0f : 0.0f,
                            levels.finest == 0 ? 0.0f : 1.0f);
            for (int k = n - 1; k >= 0; --k) {
                glActiveTexture(static_cast<GLenum>(GL_TEXTURE0 + k));
                glBindTexture(GL_TEXTURE_2D, cover[static_cast<std::size_t>(levels.finest + k)]);
            }
            countedDrawElements(
                GL_TRIANGLES, static_cast<GLsizei>(count), g->terrain_index_type,
                reinterpret_cast<const void*>(std::size_t{first.first} * indexBytes(g->terrain_index_type)));
        }
    }
}

}  // namespace navmap::render::gl
