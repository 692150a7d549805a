// SPDX-License-Identifier: Apache-2.0
#pragma once
// The daemon's own memory use, for status, /metrics and the exit summary.

#include <cstdint>

namespace navmap::daemon {

struct ProcessMemory {
    std::uint64_t rss = 0;   ///< VmRSS, bytes
    std::uint64_t peak = 0;  ///< VmHWM (peak RSS), bytes
};

/// VmRSS and VmHWM of this process from /proc/self/status; zeros when unreadable.
ProcessMemory processMemory();

}  // namespace navmap::daemon
