// SPDX-License-Identifier: Apache-2.0
#include "navmap/ipc/can/frame_queue.h"

#include <algorithm>

namespace navmap::ipc {

FrameQueue::FrameQueue(std::size_t capacity) : m_ring(std::max<std::size_t>(capacity, 1)) {}

void FrameQueue::push(const CanFrame& frame) {
    const std::lock_guard lock(m_mutex);
    if (m_count == m_ring.size()) {
        m_head = (m_head + 1) % m_ring.size();
        --m_count;
        ++m_dropped;
    }
    m_ring[(m_head + m_count) % m_ring.size()] = frame;
    ++m_count;
}

bool FrameQueue::tryPop(CanFrame& out) {
    const std::lock_guard lock(m_mutex);
    if (m_count == 0) {
        return false;
    }
    out = m_ring[m_head];
    m_head = (m_head + 1) % m_ring.size();
    --m_count;
    return true;
}

std::size_t FrameQueue::popAll(std::vector<CanFrame>& out, std::size_t max) {
    const std::lock_guard lock(m_mutex);
    const std::size_t n = std::min(max, m_count);
    for (std::size_t i = 0; i < n; ++i) {
        out.push_back(m_ring[m_head]);
        m_head = (m_head + 1) % m_ring.size();
    }
    m_count -= n;
    return n;
}

std::size_t FrameQueue::size() const {
    const std::lock_guard lock(m_mutex);
    return m_count;
}

std::uint64_t FrameQueue::dropped() const {
    const std::lock_guard lock(m_mutex);
    return m_dropped;
}

}  // namespace navmap::ipc
