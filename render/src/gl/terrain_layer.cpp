// SPDX-License-Identifier: Apache-2.0
#include "terrain_layer.h"
#include "vertex_layout.h"

#include <algorithm>
#include <cstddef>

#include <glm/gtc/type_ptr.hpp>

#include "gl/gl_work.h"
#include "navmap/common/check.h"

namespace navmap::render::gl {

TerrainLayer::TerrainLayer()
    : m_program(ShaderProgram::fromEmbedded("terrain_heightfield.vert", "terrain_heightfield.frag")) {
    glGenVertexArrays(1, &m_vao);
    glGenBuffers(1, &m_vbo);
    glGenBuffers(1, &m_ibo);
}

TerrainLayer::~TerrainLayer() {
    glDeleteBuffers(1, &m_ibo);
    glDeleteBuffers(1, &m_vbo);
    glDeleteVertexArrays(1, &m_vao);
}

void TerrainLayer::upload(const HeightfieldMesh& mesh) {
    using Vertex = HeightfieldMesh::Vertex;
    NAVMAP_CHECK(mesh.indices.empty() || std::ranges::max(mesh.indices) < mesh.vertices.size(),
                 "terrain index past its vertices");
    glBindVertexArray(m_vao);
    glBindBuffer(GL_ARRAY_BUFFER, m_vbo);
    countedBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(mesh.vertices.size() * sizeof(Vertex)),
                      mesh.vertices.data(), GL_STATIC_DRAW);
    setVertexAttributes(sizeof(Vertex),
                        {{0, 3, GL_FLOAT, offsetof(Vertex, position)}, {1, 3, GL_FLOAT, offsetof(Vertex, normal)}});
    glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, m_ibo);
    countedBufferData(GL_ELEMENT_ARRAY_BUFFER, static_cast<GLsizeiptr>(mesh.indices.size() * sizeof(std::uint32_t)),
                      mesh.indices.data(), GL_STATIC_DRAW);
    glBindVertexArray(0);
    m_index_count = static_cast<GLsizei>(mesh.indices.size());
    m_origin = mesh.origin;
}

void TerrainLayer::draw(const Camera& camera, double aspect, const TerrainStyle& style) {
    if (m_index_count == 0) return;
    glUseProgram(m_program.id());
    const glm::mat4 view = camera.viewRelativeTo(m_origin);
    const glm::mat4 proj = camera.projection(aspect);
    glUniformMatrix4fv(m_program.uniform("u_view"), 1, GL_FALSE, glm::value_ptr(view));
    glUniformMatrix4fv(m_program.uniform("u_projection"), 1, GL_FALSE, glm::value_ptr(proj));
    const glm::vec3 light = glm::normalize(style.light_dir);
    glUniform3fv(m_program.uniform("u_light_dir"), 1, glm::value_ptr(light));
    glUniform3fv(m_program.uniform("u_sky_color"), 1, glm::value_ptr(style.sky_color));
    glUniform2f(m_program.uniform("u_fog_range"), style.fog_start_m, style.fog_end_m);
    glBindVertexArray(m_vao);
    countedDrawElements(GL_TRIANGLES, m_index_count, GL_UNSIGNED_INT, nullptr);
    glBindVertexArray(0);
}

}  // namespace navmap::render::gl
