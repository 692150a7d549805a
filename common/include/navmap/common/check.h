// SPDX-License-Identifier: Apache-2.0
#pragma once
// NAVMAP_CHECK(cond, msg): an invariant that stays checked in release builds (unlike assert,
// which NDEBUG removes). For conditions whose failure would corrupt output: a buffer read or
// written out of bounds, a frame whose size disagrees with its header, an index past its
// vertices. On failure it prints "<2>navmap: check failed: <file>:<line>: <cond>: <msg>" to
// stderr (journald's "critical" level) and aborts, so systemd restarts the daemon and a core
// dump keeps the state. It never throws: a broken invariant is a bug, not an input error, and
// no caller could handle it. Expected failures (bad input, a peer gone, a missing tile) are
// return values, never checks (docs/architecture.md "Errors").

#include <cstdio>
#include <cstdlib>

namespace navmap::detail {

[[noreturn]] inline void checkFailed(const char* file, int line, const char* condition, const char* message) noexcept {
    std::fprintf(stderr, "<2>navmap: check failed: %s:%d: %s: %s\n", file, line, condition, message);
    std::fflush(stderr);
    std::abort();
}

}  // namespace navmap::detail

/// Aborts with file, line, the condition's text and `msg` (a C string) when `cond` is false,
/// in every build type. `cond` is evaluated exactly once.
#define NAVMAP_CHECK(cond, msg)                                              \
    do {                                                                     \
        if (!(cond)) [[unlikely]] {                                          \
            ::navmap::detail::checkFailed(__FILE__, __LINE__, #cond, (msg)); \
        }                                                                    \
    } while (false)
