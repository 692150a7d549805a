// SPDX-License-Identifier: Apache-2.0
#pragma once
// StreamStats: the frame server's counters, newest error and active profiles, written by the
// server thread (and publish timing by the render thread), read as snapshots from any thread.
// The mutex guards only these values, never I/O. Private to ipc/stream.

#include <atomic>
#include <cstdint>
#include <mutex>
#include <string>
#include <vector>

#include "navmap/ipc/stream/frame_server.h"

namespace navmap::ipc::stream_detail {

/// A FrameServerStats counter (&FrameServerStats::refused_peer).
using StatsCounter = std::uint64_t FrameServerStats::*;

class StreamStats {
public:
    void count(StatsCounter counter, std::uint64_t n = 1);
    /// Counts and records the problem as lastError ("tcp#7: handshake: ...").
    void countError(StatsCounter counter, std::string last_error);
    void setLastError(std::string last_error);
    /// Runs `f` on the counters under the lock (server thread; `f` must not block).
    template <class F>
    void update(F&& f) {
        std::lock_guard lock(m_mutex);
        f(m_stats);
    }
    void setActive(std::vector<ActiveProfile> active);
    std::vector<ActiveProfile> active() const;
    /// Render thread: one publish() reached a ring (counted before the server thread is woken).
    void countPublished() noexcept;
    /// Render thread: what that publish() cost.
    void recordPublishTime(std::int64_t ns) noexcept;
    FrameServerStats snapshot() const;

private:
    mutable std::mutex m_mutex;
    FrameServerStats m_stats;
    std::vector<ActiveProfile> m_active;
    std::atomic<std::uint64_t> m_published{0};
    std::atomic<std::int64_t> m_publish_ns_last{0};
    std::atomic<std::int64_t> m_publish_ns_max{0};
};

}  // namespace navmap::ipc::stream_detail
