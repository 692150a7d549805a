// SPDX-License-Identifier: Apache-2.0
#include "stream_stats.h"

#include <utility>

namespace navmap::ipc::stream_detail {

void StreamStats::count(StatsCounter counter, std::uint64_t n) {
    std::lock_guard lock(m_mutex);
    m_stats.*counter += n;
}

void StreamStats::countError(StatsCounter counter, std::string last_error) {
    std::lock_guard lock(m_mutex);
    ++(m_stats.*counter);
    m_stats.last_error = std::move(last_error);
}

void StreamStats::setLastError(std::string last_error) {
    std::lock_guard lock(m_mutex);
    m_stats.last_error = std::move(last_error);
}

void StreamStats::setActive(std::vector<ActiveProfile> active) {
    std::lock_guard lock(m_mutex);
    m_active = std::move(active);
}

std::vector<ActiveProfile> StreamStats::active() const {
    std::lock_guard lock(m_mutex);
    return m_active;
}

void StreamStats::countPublished() noexcept { m_published.fetch_add(1, std::memory_order_relaxed); }

void StreamStats::recordPublishTime(std::int64_t ns) noexcept {
    m_publish_ns_last.store(ns, std::memory_order_relaxed);
    if (ns > m_publish_ns_max.load(std::memory_order_relaxed)) {
        m_publish_ns_max.store(ns, std::memory_order_relaxed);
    }
}

FrameServerStats StreamStats::snapshot() const {
    std::lock_guard lock(m_mutex);
    FrameServerStats s = m_stats;
    s.published = m_published.load(std::memory_order_relaxed);
    s.publish_ms_last = static_cast<double>(m_publish_ns_last.load(std::memory_order_relaxed)) / 1e6;
    s.publish_ms_max = static_cast<double>(m_publish_ns_max.load(std::memory_order_relaxed)) / 1e6;
    return s;
}

}  // namespace navmap::ipc::stream_detail
