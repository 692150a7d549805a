// SPDX-License-Identifier: Apache-2.0
#pragma once
// When this process was started, on the steady clock: start-up times (the first frame of each
// profile, navmap_first_frame_seconds) count from the exec, not from main(), so that they include
// the dynamic loader and everything before the daemon's own first line.

#include <chrono>

namespace navmap::daemon {

/// The process's start (the kernel's start time in /proc/self/stat, in clock ticks since boot:
/// 10 ms steps) as a steady_clock time; `fallback` when /proc is unreadable.
std::chrono::steady_clock::time_point processStartTime(std::chrono::steady_clock::time_point fallback);

}  // namespace navmap::daemon
