// SPDX-License-Identifier: Apache-2.0
#pragma once
// FrameQueue: bounded multi-producer/single-consumer queue of CanFrames between an input thread
// (SocketCAN reader, Replayer) and a consumer (decoder). push() never blocks: when the queue is full
// the oldest frame is dropped and counted, so the consumer always sees the newest data. The mutex
// is held only to copy one frame.

#include <cstddef>
#include <cstdint>
#include <mutex>
#include <vector>

#include "navmap/ipc/can/can_frame.h"

namespace navmap::ipc {

class FrameQueue {
public:
    explicit FrameQueue(std::size_t capacity = 4096);

    /// Adds a frame; drops the oldest one when full. Thread-safe, non-blocking.
    void push(const CanFrame& frame);
    /// Takes the oldest frame if there is one. Thread-safe, non-blocking.
    bool tryPop(CanFrame& out);
    /// Moves up to `max` frames into `out` (appends); returns how many.
    std::size_t popAll(std::vector<CanFrame>& out, std::size_t max = SIZE_MAX);

    std::size_t size() const;
    std::size_t capacity() const noexcept { return m_ring.size(); }
    /// Frames dropped because the consumer was too slow.
    std::uint64_t dropped() const;

private:
    mutable std::mutex m_mutex;
    std::vector<CanFrame> m_ring;
    std::size_t m_head = 0;  // oldest element
    std::size_t m_count = 0;
    std::uint64_t m_dropped = 0;
};

}  // namespace navmap::ipc
