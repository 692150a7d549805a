// SPDX-License-Identifier: Apache-2.0
#include "shader_program.h"

#include <regex>
#include <string>
#include <vector>

#include "navmap/render/renderer.h"
#include "navmap_shaders.h"
#include "program_binary_cache.h"

namespace navmap::render::gl {

namespace {

// shaders/ files carry no #version line: the preamble adds it (and a variant's defines), then
// resets the line counter so the driver's line numbers are the file's own (STYLE.md: #line kept
// for error messages).
constexpr std::string_view kPreamble =
    "#version 300 es\n"
    "precision highp float;\n"
    "precision highp int;\n";
constexpr std::string_view kLineReset = "#line 1 0\n";

std::string_view findEmbedded(std::string_view file) {
    for (const auto& s : shaders::all()) {
        if (s.name == file) return s.text;
    }
    throw RenderError(std::string("shader '") + std::string(file) + "' is not among the embedded shaders/ files");
}

// The info log of a shader or program object (glGetShaderiv/glGetShaderInfoLog or the Program pair).
template <typename GetIv, typename GetLog>
std::string infoLog(GLuint object, GetIv get_iv, GetLog get_log) {
    GLint len = 0;
    get_iv(object, GL_INFO_LOG_LENGTH, &len);
    std::string log(static_cast<std::size_t>(len > 0 ? len : 1), '\0');
    get_log(object, len, nullptr, log.data());
    return log.c_str();
}

// A stage's whole source: the preamble, the variant's defines, then the file.
std::string stageSource(std::string_view text, std::string_view defines) {
    return std::string(kPreamble) + std::string(defines) + std::string(kLineReset) + std::string(text);
}

GLuint compile(GLenum stage, std::string_view file, const std::string& source) {
    const GLuint shader = glCreateShader(stage);
    const char* ptr = source.c_str();
    glShaderSource(shader, 1, &ptr, nullptr);
    glCompileShader(shader);
    GLint ok = GL_FALSE;
    glGetShaderiv(shader, GL_COMPILE_STATUS, &ok);
    if (ok != GL_TRUE) {
        const std::string log = infoLog(shader, glGetShaderiv, glGetShaderInfoLog);
        glDeleteShader(shader);
        throw RenderError("shader compile failed:\n" + annotateShaderLog(log, file));
    }
    return shader;
}

}  // namespace

std::string annotateShaderLog(std::string_view log, std::string_view file) {
    static const std::regex kMesa(R"((^|\n)\s*0:(\d+)\((\d+)\))");           // 0:12(5)
    static const std::regex kNvidia(R"((^|\n)\s*0\((\d+)\))");               // 0(12)
    static const std::regex kAngle(R"((^|\n)\s*(ERROR|WARNING): 0:(\d+))");  // ERROR: 0:12
    const std::string f(file);
    std::string out(log);
    out = std::regex_replace(out, kMesa, "$1" + f + ":$2:$3");
    out = std::regex_replace(out, kNvidia, "$1" + f + ":$2");
    out = std::regex_replace(out, kAngle, "$1" + f + ":$3: $2");
    while (!out.empty() && (out.back() == '\n' || out.back() == '\0')) out.pop_back();
    return out;
}

ShaderProgram ShaderProgram::fromEmbedded(std::string_view vertex_file, std::string_view fragment_file,
                                          std::string_view defines) {
    return fromSources(vertex_file, findEmbedded(vertex_file), fragment_file, findEmbedded(fragment_file), defines);
}

ShaderProgram ShaderProgram::fromSources(std::string_view vertex_file, std::string_view vertex_text,
                                         std::string_view fragment_file, std::string_view fragment_text,
                                         std::string_view defines) {
    const std::string vertex_source = stageSource(vertex_text, defines);
    const std::string fragment_source = stageSource(fragment_text, defines);
    // A cached binary of exactly these sources on this driver skips compiling and linking.
    ProgramBinaryCache* cache = ProgramBinaryCache::current();
    if (cache && !cache->usable()) cache = nullptr;
    std::string key;
    if (cache) {
        key = vertex_source + '\0' + fragment_source;
        if (const GLuint cached = cache->load(key)) return ShaderProgram(cached);
        cache->countCompiled();
    }
    const GLuint vs = compile(GL_VERTEX_SHADER, vertex_file, vertex_source);
    GLuint fs = 0;
    try {
        fs = compile(GL_FRAGMENT_SHADER, fragment_file, fragment_source);
    } catch (...) {
        glDeleteShader(vs);
        throw;
    }
    const GLuint program = glCreateProgram();
    if (cache) glProgramParameteri(program, GL_PROGRAM_BINARY_RETRIEVABLE_HINT, GL_TRUE);
    glAttachShader(program, vs);
    glAttachShader(program, fs);
    glLinkProgram(program);
    glDeleteShader(vs);
    glDeleteShader(fs);
    GLint ok = GL_FALSE;
    glGetProgramiv(program, GL_LINK_STATUS, &ok);
    if (ok != GL_TRUE) {
        const std::string log = infoLog(program, glGetProgramiv, glGetProgramInfoLog);
        glDeleteProgram(program);
        throw RenderError("shader link failed (" + std::string(vertex_file) + " + " + std::string(fragment_file) +
                          "):\n" + log);
    }
    if (cache) cache->store(key, program);
    return ShaderProgram(program);
}

ShaderProgram::~ShaderProgram() {
    if (m_program) glDeleteProgram(m_program);
}

ShaderProgram::ShaderProgram(ShaderProgram&& other) noexcept
    : m_program(other.m_program), m_uniforms(std::move(other.m_uniforms)) {
    other.m_program = 0;
}

ShaderProgram& ShaderProgram::operator=(ShaderProgram&& other) noexcept {
    if (this != &other) {
        if (m_program) glDeleteProgram(m_program);
        m_program = other.m_program;
        m_uniforms = std::move(other.m_uniforms);
        other.m_program = 0;
    }
    return *this;
}

GLint ShaderProgram::uniform(const char* name) {
    auto it = m_uniforms.find(name);
    if (it != m_uniforms.end()) return it->second;
    const GLint loc = glGetUniformLocation(m_program, name);
    m_uniforms.emplace(name, loc);
    return loc;
}

}  // namespace navmap::render::gl
