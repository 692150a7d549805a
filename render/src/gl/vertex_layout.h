// SPDX-License-Identifier: Apache-2.0
#pragma once
// Vertex attribute layouts as tables: one call enables and points every attribute of a vertex
// struct at the bound GL_ARRAY_BUFFER. Private to render/.

#include <GLES3/gl3.h>

#include <cstddef>
#include <initializer_list>

namespace navmap::render::gl {

struct VertexAttribute {
    GLuint location;
    GLint components;
    GLenum type;         ///< GL_FLOAT, or GL_SHORT etc. read as normalized values
    std::size_t offset;  ///< offsetof(Vertex, member)
};

/// Enables `attributes` with `stride` bytes per vertex (or per instance with divisor 1). Integer
/// types are read as normalized fixed point ([-1, 1] for signed).
inline void setVertexAttributes(GLsizei stride, std::initializer_list<VertexAttribute> attributes, GLuint divisor = 0) {
    for (const VertexAttribute& a : attributes) {
        glEnableVertexAttribArray(a.location);
        glVertexAttribPointer(a.location, a.components, a.type, a.type == GL_FLOAT ? GL_FALSE : GL_TRUE, stride,
                              reinterpret_cast<const void*>(a.offset));
        if (divisor) glVertexAttribDivisor(a.location, divisor);
    }
}

}  // namespace navmap::render::gl
