// SPDX-License-Identifier: Apache-2.0
#include "process_clock.h"

#include <time.h>
#include <unistd.h>

#include <cstdio>
#include <cstring>
#include <string>

namespace navmap::daemon {

std::chrono::steady_clock::time_point processStartTime(std::chrono::steady_clock::time_point fallback) {
    std::FILE* f = std::fopen("/proc/self/stat", "r");
    if (!f) return fallback;
    char buf[1024];
    const std::size_t n = std::fread(buf, 1, sizeof buf - 1, f);
    std::fclose(f);
    buf[n] = '\0';
    // Field 22 (starttime), 19 fields after the command name (field 2), which may hold spaces:
    // counted from its ')'.
    const char* p = std::strrchr(buf, ')');
    if (!p) return fallback;
    unsigned long long start_ticks = 0;
    if (std::sscanf(p + 2, "%*s %*s %*s %*s %*s %*s %*s %*s %*s %*s %*s %*s %*s %*s %*s %*s %*s %*s %*s %llu",
                    &start_ticks) != 1)
        return fallback;
    const long hz = ::sysconf(_SC_CLK_TCK);
    timespec boot{};
    if (hz <= 0 || ::clock_gettime(CLOCK_BOOTTIME, &boot) != 0) return fallback;
    const auto now = std::chrono::steady_clock::now();
    const double age_s = static_cast<double>(boot.tv_sec) + static_cast<double>(boot.tv_nsec) / 1e9 -
                         static_cast<double>(start_ticks) / static_cast<double>(hz);
    if (age_s < 0 || age_s > 3600.0 * 24 * 365) return fallback;
    return now - std::chrono::duration_cast<std::chrono::steady_clock::duration>(std::chrono::duration<double>(age_s));
}

}  // namespace navmap::daemon
