// SPDX-License-Identifier: Apache-2.0
#pragma once
// One index buffer shared by many vertex arrays that repeat a fixed shape per primitive (a road
// quad: 4 vertices, 6 indices; a shadow-volume box: 8 vertices, 36 indices). Drawing them indexed
// instead of instanced matters on llvmpipe, which runs an instanced draw as one small draw per
// instance. Private to render/.

#include <GLES3/gl3.h>

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>
#include "gl/gl_work.h"

namespace navmap::render::gl {

class RepeatedIndices {
public:
    /// `pattern`: the indices of one shape over its `vertices_per_shape` vertices.
    RepeatedIndices(std::span<const std::uint32_t> pattern, std::uint32_t vertices_per_shape)
        : m_pattern(pattern.begin(), pattern.end()), m_vertices(vertices_per_shape) {}
    ~RepeatedIndices() { glDeleteBuffers(1, &m_buffer); }
    RepeatedIndices(const RepeatedIndices&) = delete;
    RepeatedIndices& operator=(const RepeatedIndices&) = delete;

    /// Binds the buffer to the bound vertex array, grown to hold `shapes` shapes. It grows in
    /// place under the same name, so vertex arrays bound to it before keep working.
    void bind(std::size_t shapes) {
        if (!m_buffer) glGenBuffers(1, &m_buffer);
        glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, m_buffer);
        if (shapes <= m_capacity) return;
        m_capacity = shapes > 2 * m_capacity ? shapes : 2 * m_capacity;
        std::vector<std::uint32_t> indices;
        indices.reserve(m_capacity * m_pattern.size());
        for (std::uint32_t s = 0; s < m_capacity; ++s) {
            for (const std::uint32_t i : m_pattern) indices.push_back(s * m_vertices + i);
        }
        countedBufferData(GL_ELEMENT_ARRAY_BUFFER, static_cast<GLsizeiptr>(indices.size() * sizeof(std::uint32_t)),
                          indices.data(), GL_STATIC_DRAW);
    }

    /// Draws shapes [first, first + count) of the bound vertex array.
    void draw(GLsizei first, GLsizei count) const {
        const auto per_shape = static_cast<GLsizei>(m_pattern.size());
        const auto offset = static_cast<std::size_t>(first) * m_pattern.size() * sizeof(std::uint32_t);
        countedDrawElements(GL_TRIANGLES, count * per_shape, GL_UNSIGNED_INT, reinterpret_cast<const void*>(offset));
    }

private:
    std::vector<std::uint32_t> m_pattern;
    std::uint32_t m_vertices;
    GLuint m_buffer = 0;
    std::size_t m_capacity = 0;
};

}  // namespace navmap::render::gl
