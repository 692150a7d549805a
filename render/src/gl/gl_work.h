// SPDX-License-Identifier: Apache-2.0
#pragma once
// The GL work the renderer asks for, counted on the calling thread: draw calls, the vertices
// they draw (instances times count) and the bytes handed to buffers and textures. The counts
// depend only on the scene, not on the driver or the machine, so tests assert how they grow
// (MapFrameStats::*_work per pass, docs/benchmarks/README.md "Work counters"). The render code
// calls these wrappers instead of glDrawArrays, glDrawElements, glBufferData, ... directly.

#include <GLES3/gl3.h>

#include <cstdint>

#include "navmap/render/map_frame.h"

namespace navmap::render::gl {

/// This thread's running totals (the render thread's: GL calls are made on one thread).
PassWork& glWork();

/// Bytes of w x h texels of an upload's format and type (0 for formats it does not know).
std::uint64_t texelBytes(GLsizei w, GLsizei h, GLenum format, GLenum type);

inline void countedDrawArrays(GLenum mode, GLint first, GLsizei count) {
    PassWork& w = glWork();
    ++w.draw_calls;
    w.vertices += static_cast<std::uint64_t>(count);
    glDrawArrays(mode, first, count);
}

inline void countedDrawArraysInstanced(GLenum mode, GLint first, GLsizei count, GLsizei instances) {
    PassWork& w = glWork();
    ++w.draw_calls;
    w.vertices += static_cast<std::uint64_t>(count) * static_cast<std::uint64_t>(instances);
    glDrawArraysInstanced(mode, first, count, instances);
}

inline void countedDrawElements(GLenum mode, GLsizei count, GLenum type, const void* indices) {
    PassWork& w = glWork();
    ++w.draw_calls;
    w.vertices += static_cast<std::uint64_t>(count);
    glDrawElements(mode, count, type, indices);
}

inline void countedBufferData(GLenum target, GLsizeiptr size, const void* data, GLenum usage) {
    if (data != nullptr) glWork().bytes_uploaded += static_cast<std::uint64_t>(size);
    glBufferData(target, size, data, usage);
}

inline void countedBufferSubData(GLenum target, GLintptr offset, GLsizeiptr size, const void* data) {
    glWork().bytes_uploaded += static_cast<std::uint64_t>(size);
    glBufferSubData(target, offset, size, data);
}

inline void countedTexImage2D(GLenum target, GLint level, GLint internal_format, GLsizei w, GLsizei h, GLint border,
                              GLenum format, GLenum type, const void* pixels) {
    if (pixels != nullptr) glWork().bytes_uploaded += texelBytes(w, h, format, type);
    glTexImage2D(target, level, internal_format, w, h, border, format, type, pixels);
}

inline void countedTexSubImage2D(GLenum target, GLint level, GLint x, GLint y, GLsizei w, GLsizei h, GLenum format,
                                 GLenum type, const void* pixels) {
    if (pixels != nullptr) glWork().bytes_uploaded += texelBytes(w, h, format, type);
    glTexSubImage2D(target, level, x, y, w, h, format, type, pixels);
}

}  // namespace navmap::render::gl
