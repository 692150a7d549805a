// SPDX-License-Identifier: Apache-2.0
#pragma once
// ReadbackQueue: the asynchronous readback contract of every backend (Renderer::readAsync,
// collectReadbacks, drainReadbacks in navmap/render/renderer.h), kept once: at most `slots`
// readbacks in flight per target, handed out oldest first, and a readback into a full ring
// completes the oldest one first and returns it. T is what a backend keeps per readback in
// flight (the GL backend: the index of its pixel-pack slot; the no-op backend: the frame's
// sequence); the backend says how one starts, completes and whether it has finished. GL-free,
// private to render/.

#include <algorithm>
#include <cstddef>
#include <deque>
#include <optional>
#include <utility>
#include <vector>

#include "navmap/render/renderer.h"

namespace navmap::render {

template <class T>
class ReadbackQueue {
public:
    explicit ReadbackQueue(std::size_t slots) : m_slots(std::max<std::size_t>(slots, 1)) {}

    [[nodiscard]] std::size_t slots() const { return m_slots; }
    [[nodiscard]] std::size_t size() const { return m_pending.size(); }

    /// readAsync(): when `slots` are in flight, `complete(T&)` finishes the oldest (it is handed
    /// back); then `start()` begins the new readback and returns its T.
    template <class Complete, class Start>
    std::optional<Frame> submit(Complete&& complete, Start&& start) {
        std::optional<Frame> oldest;
        if (m_pending.size() >= m_slots) {
            oldest = complete(m_pending.front());
            m_pending.pop_front();
        }
        m_pending.push_back(start());
        return oldest;
    }

    /// collectReadbacks(): the readbacks that `ready(const T&)` says have finished, oldest first,
    /// up to the first that has not.
    template <class Ready, class Complete>
    std::vector<Frame> collect(Ready&& ready, Complete&& complete) {
        std::vector<Frame> frames;
        while (!m_pending.empty() && ready(std::as_const(m_pending.front()))) {
            frames.push_back(complete(m_pending.front()));
            m_pending.pop_front();
        }
        return frames;
    }

    /// drainReadbacks(): completes every readback in flight, oldest first.
    template <class Complete>
    std::vector<Frame> drain(Complete&& complete) {
        return collect([](const T&) { return true; }, std::forward<Complete>(complete));
    }

    /// Forgets every readback in flight without completing it.
    void clear() { m_pending.clear(); }

private:
    std::size_t m_slots;
    std::deque<T> m_pending;  // oldest first
};

}  // namespace navmap::render
