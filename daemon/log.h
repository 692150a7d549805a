// SPDX-License-Identifier: Apache-2.0
#pragma once
// navmapd's log: one line per event on stderr with a syslog priority prefix that journald
// understands (sd-daemon(3)): "<4>navmapd: ...". Lines above the configured level are dropped.
// Stateless apart from the level: every part of the daemon takes a copy.

#include <cstdarg>
#include <cstdio>

namespace navmap::daemon {

class Log {
public:
    static constexpr int kErr = 3, kWarning = 4, kNotice = 5, kInfo = 6, kDebug = 7;

    /// `level`: the highest priority number written (3 err .. 7 debug, [log] level).
    explicit Log(int level = kInfo) : m_level(level) {}

    /// True when lines of `priority` are written.
    [[nodiscard]] bool enabled(int priority) const { return priority <= m_level; }

    void operator()(int priority, const char* fmt, ...) const __attribute__((format(printf, 3, 4))) {
        if (priority > m_level) return;
        std::fprintf(stderr, "<%d>navmapd: ", priority);
        va_list ap;
        va_start(ap, fmt);
        std::vfprintf(stderr, fmt, ap);
        va_end(ap);
        std::fputc('\n', stderr);
    }

private:
    int m_level;
};

}  // namespace navmap::daemon
