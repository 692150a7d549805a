// SPDX-License-Identifier: Apache-2.0
#include "program_binary_cache.h"

#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <iterator>
#include <system_error>
#include <vector>

namespace navmap::render::gl {

namespace {

// File layout: magic, a second hash of the key (a collision check), the binary format, the
// binary's size, then the binary. Host byte order: the files never leave the machine.
constexpr char kMagic[8] = {'N', 'M', 'P', 'R', 'O', 'G', '1', '\n'};
struct FileHeader {
    char magic[8];
    std::uint64_t check;
    std::uint32_t format;
    std::uint32_t size;
};

thread_local ProgramBinaryCache* t_current = nullptr;

std::string glString(GLenum name) {
    const auto* s = reinterpret_cast<const char*>(glGetString(name));
    return s ? s : "";
}

}  // namespace

ProgramBinaryCache::ProgramBinaryCache(std::filesystem::path dir) : m_dir(std::move(dir)) {
    m_stats.dir = m_dir.string();
    m_driver = glString(GL_VENDOR) + '\n' + glString(GL_RENDERER) + '\n' + glString(GL_VERSION) + '\n' +
               glString(GL_SHADING_LANGUAGE_VERSION) + '\n';
    GLint formats = 0;
    glGetIntegerv(GL_NUM_PROGRAM_BINARY_FORMATS, &formats);
    if (formats <= 0) {
        m_stats.problem = "the driver offers no program binary format";
        return;
    }
    std::error_code ec;
    std::filesystem::create_directories(m_dir, ec);
    if (ec || ::access(m_dir.c_str(), W_OK) != 0) {
        m_stats.problem = m_dir.string() + ": " + (ec ? ec.message() : std::string(std::strerror(errno)));
    }
}

std::uint64_t ProgramBinaryCache::hash(std::string_view sources, std::uint64_t seed) const {
    // FNV-1a, 64 bits, over the driver's identity and the sources.
    std::uint64_t h = seed;
    for (const std::string_view part : {std::string_view(m_driver), sources}) {
        for (const char c : part) {
            h ^= static_cast<unsigned char>(c);
            h *= 0x100000001b3ULL;
        }
    }
    return h;
}

std::filesystem::path ProgramBinaryCache::fileFor(std::string_view sources) const {
    char name[32];
    std::snprintf(name, sizeof name, "%016llx.glprog",
                  static_cast<unsigned long long>(hash(sources, 0xcbf29ce484222325ULL)));
    return m_dir / name;
}

GLuint ProgramBinaryCache::load(std::string_view sources) {
    if (!usable()) return 0;
    const std::filesystem::path file = fileFor(sources);
    std::ifstream in(file, std::ios::binary);
    if (!in) return 0;
    const std::vector<char> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    FileHeader h{};
    const bool framed = bytes.size() >= sizeof h && (std::memcpy(&h, bytes.data(), sizeof h), true) &&
                        std::memcmp(h.magic, kMagic, sizeof kMagic) == 0 &&
                        h.check == hash(sources, 0x84222325cbf29ce4ULL) && bytes.size() - sizeof h == h.size;
    GLuint program = 0;
    if (framed) {
        while (glGetError() != GL_NO_ERROR) {}
        program = glCreateProgram();
        glProgramBinary(program, h.format, bytes.data() + sizeof h, static_cast<GLsizei>(h.size));
        GLint ok = GL_FALSE;
        glGetProgramiv(program, GL_LINK_STATUS, &ok);
        if (glGetError() != GL_NO_ERROR || ok != GL_TRUE) {
            glDeleteProgram(program);
            program = 0;
        }
    }
    if (program == 0) {
        // Rejected (driver update, corrupt or foreign file): compiled from source instead, and
        // the file goes so that the fresh binary replaces it.
        ++m_stats.rejected;
        std::error_code ec;
        std::filesystem::remove(file, ec);
        return 0;
    }
    ++m_stats.loaded;
    return program;
}

void ProgramBinaryCache::store(std::string_view sources, GLuint program) {
    if (!usable()) return;
    GLint length = 0;
    glGetProgramiv(program, GL_PROGRAM_BINARY_LENGTH, &length);
    std::vector<char> bytes(sizeof(FileHeader) + static_cast<std::size_t>(std::max(length, 0)));
    GLsizei written = 0;
    GLenum format = 0;
    if (length > 0) glGetProgramBinary(program, length, &written, &format, bytes.data() + sizeof(FileHeader));
    if (written <= 0) {
        ++m_stats.write_errors;
        return;
    }
    FileHeader h{};
    std::memcpy(h.magic, kMagic, sizeof kMagic);
    h.check = hash(sources, 0x84222325cbf29ce4ULL);
    h.format = format;
    h.size = static_cast<std::uint32_t>(written);
    std::memcpy(bytes.data(), &h, sizeof h);
    bytes.resize(sizeof h + h.size);
    const std::filesystem::path file = fileFor(sources);
    std::filesystem::path tmp = file;
    tmp += ".tmp" + std::to_string(::getpid());
    bool ok = false;
    {
        std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
        ok = out.write(bytes.data(), static_cast<std::streamsize>(bytes.size())).good();
        out.close();
        ok = ok && !out.fail();
    }
    std::error_code ec;
    if (ok) std::filesystem::rename(tmp, file, ec);
    if (!ok || ec) {
        std::filesystem::remove(tmp, ec);
        ++m_stats.write_errors;
        return;
    }
    ++m_stats.stored;
}

ProgramBinaryCache* ProgramBinaryCache::current() { return t_current; }

ProgramBinaryCache::Use::Use(ProgramBinaryCache* cache) : m_previous(t_current) { t_current = cache; }

ProgramBinaryCache::Use::~Use() { t_current = m_previous; }

}  // namespace navmap::render::gl
