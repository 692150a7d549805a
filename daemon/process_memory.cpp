// SPDX-License-Identifier: Apache-2.0
#include "process_memory.h"

#include <cstdio>

namespace navmap::daemon {

ProcessMemory processMemory() {
    ProcessMemory m;
    std::FILE* f = std::fopen("/proc/self/status", "r");
    if (!f) return m;
    char line[256];
    while (std::fgets(line, sizeof line, f)) {
        unsigned long long kb = 0;
        if (std::sscanf(line, "VmRSS: %llu kB", &kb) == 1) m.rss = kb * 1024;
        if (std::sscanf(line, "VmHWM: %llu kB", &kb) == 1) m.peak = kb * 1024;
    }
    std::fclose(f);
    return m;
}

}  // namespace navmap::daemon
