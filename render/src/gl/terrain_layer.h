// SPDX-License-Identifier: Apache-2.0
#pragma once
// Draws a heightfield mesh. Private to render/.

#include <GLES3/gl3.h>

#include "navmap/render/renderer.h"
#include "shader_program.h"

namespace navmap::render::gl {

class TerrainLayer {
public:
    TerrainLayer();
    ~TerrainLayer();
    TerrainLayer(const TerrainLayer&) = delete;
    TerrainLayer& operator=(const TerrainLayer&) = delete;

    void upload(const HeightfieldMesh& mesh);
    void draw(const Camera& camera, double aspect, const TerrainStyle& style);

private:
    ShaderProgram m_program;
    GLuint m_vao = 0;
    GLuint m_vbo = 0;
    GLuint m_ibo = 0;
    GLsizei m_index_count = 0;
    glm::dvec3 m_origin{0.0};
};

}  // namespace navmap::render::gl
