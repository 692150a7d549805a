// SPDX-License-Identifier: Apache-2.0
#include "ortho_detail.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/vec4.hpp>

#include "frame_context.h"
#include "gl/gl_work.h"
#include "navmap/map/ortho/rng.h"
#include "navmap/map/ortho/super_land_cover.h"
#include "ortho/field_grid.h"
#include "ortho/vegetation.h"
#include "vertex_layout.h"

namespace navmap::render::gl {

namespace {

namespace mo = map::ortho;

constexpr std::uint32_t kQuad[] = {0, 1, 2, 0, 2, 3};
constexpr float kMaxShadowHeightM = 40.0f;
// Light from the north-west: shadows fall to the south-east, 0.35 m per metre of height.
const glm::vec2 kShadowPerMetre = 0.35f * glm::normalize(glm::vec2(1.0f, -1.0f));

template <typename V>
void upload(GLuint vbo, GLuint ibo, const std::vector<V>& vertices, const std::vector<std::uint32_t>& indices) {
    glBindBuffer(GL_ARRAY_BUFFER, vbo);
    countedBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(vertices.size() * sizeof(V)), vertices.data(),
                      GL_STREAM_DRAW);
    glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, ibo);
    countedBufferData(GL_ELEMENT_ARRAY_BUFFER, static_cast<GLsizeiptr>(indices.size() * sizeof(std::uint32_t)),
                      indices.data(), GL_STREAM_DRAW);
}

using DetailVertex = OrthoDetail::DetailVertex;
using PlantVertex = OrthoDetail::PlantVertex;

void detailAttributes() {
    setVertexAttributes(sizeof(DetailVertex), {{0, 2, GL_FLOAT, offsetof(DetailVertex, position)},
                                               {1, 4, GL_FLOAT, offsetof(DetailVertex, params)}});
    glDisableVertexAttribArray(2);
}

void plantAttributes() {
    setVertexAttributes(sizeof(PlantVertex), {{0, 2, GL_FLOAT, offsetof(PlantVertex, centre)},
                                              {1, 2, GL_FLOAT, offsetof(PlantVertex, corner)},
                                              {2, 2, GL_FLOAT, offsetof(PlantVertex, plant)}});
}

}  // namespace

OrthoDetail::OrthoDetail()
    : m_fields(ShaderProgram::fromEmbedded("ortho_detail.vert", "ortho_fields.frag")),
      m_roofs(ShaderProgram::fromEmbedded("ortho_detail.vert", "ortho_roofs.frag")),
      m_plants(ShaderProgram::fromEmbedded("ortho_plants.vert", "ortho_plants.frag")) {
    glGenVertexArrays(1, &m_vao);
    glGenBuffers(1, &m_vbo);
    glGenBuffers(1, &m_ibo);
    glGenTextures(1, &m_cover);
    glBindTexture(GL_TEXTURE_2D, m_cover);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    glBindTexture(GL_TEXTURE_2D, 0);
}

OrthoDetail::~OrthoDetail() {
    glDeleteTextures(1, &m_cover);
    const GLuint buffers[] = {m_vbo, m_ibo};
    glDeleteBuffers(2, buffers);
    glDeleteVertexArrays(1, &m_vao);
}

OrthoDetail::Geometry OrthoDetail::build(const map::Tile& tile, const Options& options) {
    Geometry g;
    if (tile.ortho.empty()) return g;
    const auto t0 = Clock::now();
    auto& fields = g.fields;
    auto& roofs = g.roofs;
    auto& field_index = g.field_index;
    auto& roof_index = g.roof_index;
    // The field grid (seed 6.7.2), the roofs (6.7.3), the vegetation simulation (6.7.1).
    if (options.fields_and_roofs) {
        const ortho::FieldGrid grid = ortho::buildFieldGrid(tile);
        g.parcels = grid.parcels.size();
        for (const auto& p : grid.parcels) {
            const auto base = static_cast<std::uint32_t>(fields.size());
            for (const glm::vec2& c : p.corners) {
                fields.push_back({c, glm::vec4(static_cast<float>(p.pattern), p.variation, p.hue, p.angle)});
            }
            for (std::uint32_t i : kQuad) field_index.push_back(base + i);
        }
        // Roofs: slight brightness and hue changes in pairs, weighted by footprint area (seed 6.7.5).
        if (!options.field_mask_only) {
            mo::Rng rng(mo::mixSeed(0x726f6f66ULL, tile.id.key()));
            std::vector<float> areas(tile.buildings.size(), 0.0f);
            for (std::size_t b = 0; b < tile.buildings.size(); ++b) {
                const auto& f = tile.buildings[b].footprint;
                for (std::size_t k = 0; k + 2 < f.indices.size(); k += 3) {
                    const auto &a = f.vertices[f.indices[k]], &bb = f.vertices[f.indices[k + 1]],
                               &c = f.vertices[f.indices[k + 2]];
                    areas[b] += 0.5f * std::abs((bb.x - a.x) * (c.y - a.y) - (c.x - a.x) * (bb.y - a.y));
                }
            }
            float v = 0.0f, h = 0.0f;
            for (std::size_t b = 0; b < tile.buildings.size(); ++b) {
                // Buildings 2k and 2k + 1 change by the same amount in opposite directions, the larger
                // footprint by less.
                if (b % 2 == 0) {
                    v = static_cast<float>(rng.uniform(0.03, 0.1));
                    h = static_cast<float>(rng.uniform(-0.06, 0.06));
                }
                const std::size_t other = b % 2 == 0 ? b + 1 : b - 1;
                float scale = b % 2 == 0 ? 1.0f : -1.0f;
                if (other < tile.buildings.size()) {
                    const float mine = std::max(areas[b], 1.0f), theirs = std::max(areas[other], 1.0f);
                    scale *= theirs / std::max(mine, theirs);
                }
                const float variation = v * scale, hue = h * scale;
                const auto& building = tile.buildings[b];
                const auto base = static_cast<std::uint32_t>(roofs.size());
                const float height = std::clamp(building.height_m, 0.0f, kMaxShadowHeightM);
                for (const auto& corner : building.footprint.vertices) {
                    roofs.push_back({{corner.x, corner.y}, glm::vec4(variation, hue, height, 0.0f)});
                }
                for (std::uint32_t i : building.footprint.indices) roof_index.push_back(base + i);
            }
            g.roofs_drawn = tile.buildings.size();
        }
    }
    auto& plants = g.plants;
    auto& plant_index = g.plant_index;
    if (options.vegetation && !options.field_mask_only) {
        const ortho::VegetationResult veg = ortho::simulateVegetation(tile);
        g.plant_count = veg.plants.size();
        for (const auto& p : veg.plants) {
            const auto base = static_cast<std::uint32_t>(plants.size());
            for (const glm::vec2 corner : {glm::vec2(-1, -1), glm::vec2(1, -1), glm::vec2(1, 1), glm::vec2(-1, 1)}) {
                plants.push_back({p.position, corner, glm::vec2(p.radius_m, p.variation)});
            }
            for (std::uint32_t i : kQuad) plant_index.push_back(base + i);
        }
    }
    g.cpu_ms = msSince(t0);
    return g;
}

void OrthoDetail::account(const Geometry& g) {
    m_timings.cpu_ms += g.cpu_ms;
    m_timings.parcels += g.parcels;
    m_timings.plants += g.plant_count;
    m_timings.roofs += g.roofs_drawn;
}

bool OrthoDetail::begin(const Target& t, ShaderProgram& p) {
    if (t.tile == nullptr || t.tile->ortho.empty() || t.extent <= 0.0f) return false;
    glDisable(GL_BLEND);
    glActiveTexture(GL_TEXTURE0);
    glBindTexture(GL_TEXTURE_2D, t.basic);
    glBindVertexArray(m_vao);
    glUseProgram(p.id());
    glUniform2f(p.uniform("u_offset"), t.offset.x, t.offset.y);
    glUniform1f(p.uniform("u_extent"), t.extent);
    glUniform1i(p.uniform("u_basic"), 0);
    return true;
}

void OrthoDetail::end(Clock::time_point t0) {
    glBindVertexArray(0);
    glBindBuffer(GL_ARRAY_BUFFER, 0);
    glBindTexture(GL_TEXTURE_2D, 0);
    m_timings.draw_ms += msSince(t0);
}

void OrthoDetail::draw(const Target& t, const Geometry& g) {
    account(g);
    drawFields(t, g);
    drawPlants(t, g, 0, g.plant_count);
    drawRoofs(t, g);
}

void OrthoDetail::drawFields(const Target& t, const Geometry& g) {
    if (g.field_index.empty()) return;
    const auto t0 = Clock::now();
    if (!begin(t, m_fields)) return;
    const map::Tile& tile = *t.tile;
    // The farmland mask (seed: "we create a stencil mask"): the fragment shader looks up the tile's
    // cover texel and draws only on farmland.
    glActiveTexture(GL_TEXTURE1);
    glBindTexture(GL_TEXTURE_2D, m_cover);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    countedTexImage2D(GL_TEXTURE_2D, 0, GL_R8UI, tile.ortho.cover_size, tile.ortho.cover_size, 0, GL_RED_INTEGER,
                      GL_UNSIGNED_BYTE, tile.ortho.cover.data());
    glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
    glActiveTexture(GL_TEXTURE0);
    glUniform2f(m_fields.uniform("u_shift"), 0.0f, 0.0f);
    glUniform1i(m_fields.uniform("u_cover"), 1);
    glUniform1f(m_fields.uniform("u_tile_size"), static_cast<float>(tile.size_m));
    glUniform1ui(m_fields.uniform("u_farmland"), static_cast<GLuint>(mo::SuperLandCover::Farmland));
    glUniform1f(m_fields.uniform("u_mask_only"), t.field_mask_only ? 1.0f : 0.0f);
    glUniform1f(m_fields.uniform("u_pixel_m"), t.extent / static_cast<float>(std::max(t.size, 1)));
    upload(m_vbo, m_ibo, g.fields, g.field_index);
    detailAttributes();
    countedDrawElements(GL_TRIANGLES, static_cast<GLsizei>(g.field_index.size()), GL_UNSIGNED_INT, nullptr);
    glActiveTexture(GL_TEXTURE1);
    glBindTexture(GL_TEXTURE_2D, 0);
    glActiveTexture(GL_TEXTURE0);
    end(t0);
}

void OrthoDetail::drawPlants(const Target& t, const Geometry& g, std::size_t first, std::size_t count) {
    const std::size_t plants = g.plant_index.size() / 6;  // one quad each
    if (first >= plants || count == 0) return;
    count = std::min(count, plants - first);
    const auto t0 = Clock::now();
    if (!begin(t, m_plants)) return;
    // The buffers are filled by the first slice and drawn from by the later ones (the generator
    // draws nothing else with them in between).
    if (first == 0) upload(m_vbo, m_ibo, g.plants, g.plant_index);
    glBindBuffer(GL_ARRAY_BUFFER, m_vbo);
    glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, m_ibo);
    plantAttributes();
    countedDrawElements(GL_TRIANGLES, static_cast<GLsizei>(count * 6), GL_UNSIGNED_INT,
                        reinterpret_cast<const void*>(first * 6 * sizeof(std::uint32_t)));  // NOLINT: a buffer offset
    end(t0);
}

void OrthoDetail::drawRoofs(const Target& t, const Geometry& g) {
    if (g.roof_index.empty()) return;
    const auto t0 = Clock::now();
    if (!begin(t, m_roofs)) return;
    // Shadows first (seed 6.7.3: "a preliminary pass where all buildings are slightly offset and
    // rendered in black", here blended), then the roofs over them.
    upload(m_vbo, m_ibo, g.roofs, g.roof_index);
    detailAttributes();
    glEnable(GL_BLEND);
    glBlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA);
    glUniform1f(m_roofs.uniform("u_shadow"), 1.0f);
    glUniform2f(m_roofs.uniform("u_shift"), kShadowPerMetre.x, kShadowPerMetre.y);
    countedDrawElements(GL_TRIANGLES, static_cast<GLsizei>(g.roof_index.size()), GL_UNSIGNED_INT, nullptr);
    glDisable(GL_BLEND);
    glUniform1f(m_roofs.uniform("u_shadow"), 0.0f);
    glUniform2f(m_roofs.uniform("u_shift"), 0.0f, 0.0f);
    countedDrawElements(GL_TRIANGLES, static_cast<GLsizei>(g.roof_index.size()), GL_UNSIGNED_INT, nullptr);
    end(t0);
}

}  // namespace navmap::render::gl
