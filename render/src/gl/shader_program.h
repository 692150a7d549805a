// SPDX-License-Identifier: Apache-2.0
#pragma once
// GLSL ES programs compiled from the embedded shaders/ sources. Private to render/.

#include <GLES3/gl3.h>

#include <string>
#include <string_view>
#include <unordered_map>

namespace navmap::render::gl {

/// Rewrites a driver's compile log so every "0:LINE" location reads "<file>:LINE" (Mesa
/// "0:12(5): error", NVIDIA "0(12) : error", ANGLE "ERROR: 0:12:").
std::string annotateShaderLog(std::string_view log, std::string_view file);

/// A linked vertex + fragment program. Move-only; deletes the GL program on destruction.
class ShaderProgram {
public:
    /// Compiles the named files of shaders/ (e.g. "terrain_heightfield.vert"). Throws RenderError
    /// naming the file and line of any compile error, or the pair on a link error.
    /// `defines` (e.g. "#define NAVMAP_X 1\n") goes before both stages' text: program variants.
    static ShaderProgram fromEmbedded(std::string_view vertex_file, std::string_view fragment_file,
                                      std::string_view defines = {});
    /// Same from explicit sources (tests).
    static ShaderProgram fromSources(std::string_view vertex_file, std::string_view vertex_text,
                                     std::string_view fragment_file, std::string_view fragment_text,
                                     std::string_view defines = {});

    ShaderProgram() = default;
    ~ShaderProgram();
    ShaderProgram(ShaderProgram&& other) noexcept;
    ShaderProgram& operator=(ShaderProgram&& other) noexcept;

    [[nodiscard]] GLuint id() const { return m_program; }
    /// Location of a uniform (-1 when the driver optimised it away); cached.
    GLint uniform(const char* name);

private:
    explicit ShaderProgram(GLuint program) : m_program(program) {}
    GLuint m_program = 0;
    std::unordered_map<std::string, GLint> m_uniforms;
};

}  // namespace navmap::render::gl
