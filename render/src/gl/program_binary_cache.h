// SPDX-License-Identifier: Apache-2.0
#pragma once
// Linked GL programs kept on disk as the driver's own binaries (GL_OES_get_program_binary, core
// in ES 3.0): a program the cache holds is loaded with glProgramBinary instead of compiling and
// linking its GLSL, which is the largest part of a renderer's creation on most drivers. The key
// is the program's full source text (both stages, with their preamble and defines) and the
// driver's identity (vendor, renderer, version strings), so a new shader or a driver update
// misses. A binary the driver rejects (another driver build, a corrupt file) is deleted and the
// program compiled from source as if there were no cache; a failed write leaves no file behind.
// Private to render/; used by ShaderProgram through ProgramBinaryCache::current().

#include <GLES3/gl3.h>

#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>

#include "navmap/render/renderer.h"

namespace navmap::render::gl {

class ProgramBinaryCache {
public:
    /// Creates `dir` when missing. Reads the driver's identity and binary formats from the
    /// current context; without a format (Mesa offers one only while its own shader cache is on)
    /// or without a usable directory the cache is off and stats().problem says why.
    explicit ProgramBinaryCache(std::filesystem::path dir);

    [[nodiscard]] bool usable() const { return m_stats.problem.empty(); }
    [[nodiscard]] const ProgramCacheStats& stats() const { return m_stats; }

    /// A linked program from the binary stored for `sources`, or 0: none stored, unreadable, or
    /// rejected by the driver (then its file is deleted and counted in stats().rejected).
    GLuint load(std::string_view sources);
    /// Keeps `program`'s binary for `sources` (written to a temporary file, then renamed; a
    /// failure is counted in stats().write_errors and otherwise ignored).
    void store(std::string_view sources, GLuint program);
    /// Counts a program compiled from source (a miss).
    void countCompiled() { ++m_stats.compiled; }
    /// The file a program's binary is kept in.
    [[nodiscard]] std::filesystem::path fileFor(std::string_view sources) const;

    /// The cache the programs compiled on this thread use; null: none. GlRenderer sets it while
    /// it creates or renders (the passes compile their programs then).
    static ProgramBinaryCache* current();
    /// Makes `cache` current on this thread for the scope's lifetime (null: none).
    class Use {
    public:
        explicit Use(ProgramBinaryCache* cache);
        ~Use();
        Use(const Use&) = delete;
        Use& operator=(const Use&) = delete;

    private:
        ProgramBinaryCache* m_previous;
    };

private:
    [[nodiscard]] std::uint64_t hash(std::string_view sources, std::uint64_t seed) const;

    std::filesystem::path m_dir;
    std::string m_driver;  // vendor, renderer, version and GLSL version strings
    ProgramCacheStats m_stats;
};

}  // namespace navmap::render::gl
