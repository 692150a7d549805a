#include "navmap/ipc/replayer.h"

#include <algorithm>

namespace navmap::ipc {

Replayer::Replayer(std::vector<CanFrame> frames, ReplayOptions options)
    : m_frames(std::move(frames)), m_options(options) {
    m_offsets.reserve(m_frames.size());
    std::chrono::nanoseconds prev{0};
    for (const auto& f : m_frames) {
        // A log whose time goes backwards (clock step while recording) is played without waiting.
        const auto off = std::max(prev, f.timestamp - m_frames.front().timestamp);
        m_offsets.push_back(off);
        prev = off;
    }
    if (!m_frames.empty()) {
        // One loop lasts the log plus one mean frame interval, so the first frame of the next loop
        // does not coincide with the last of this one.
        const auto span = m_offsets.back();
        const auto gap = m_frames.size() > 1 ? span / static_cast<std::int64_t>(m_frames.size() - 1)
                                             : std::chrono::nanoseconds{0};
        m_period = std::max(span + gap, std::chrono::nanoseconds(std::chrono::milliseconds(1)));
    }
    reset(CanClock::now());
}

Replayer::~Replayer() { stop(); }

void Replayer::reset(CanTime startTime) {
    m_start = startTime;
    m_next = 0;
    m_loops = 0;
    m_finished = m_frames.empty();
}

CanTime Replayer::scheduled(std::size_t index, std::uint64_t loop) const noexcept {
    if (m_options.speed <= 0.0) {
        return m_start;
    }
    const double logNs = static_cast<double>(m_offsets[index].count()) +
                         static_cast<double>(loop) * static_cast<double>(m_period.count());
    return m_start + std::chrono::nanoseconds(static_cast<std::int64_t>(logNs / m_options.speed));
}

CanTime Replayer::nextDue() const noexcept {
    if (m_finished) {
        return CanTime::max();
    }
    return scheduled(m_next, m_loops.load());
}

bool Replayer::finished() const noexcept { return m_finished.load(); }

std::size_t Replayer::advanceTo(CanTime now, const FrameSink& sink, std::size_t maxBurst) {
    std::size_t count = 0;
    while (!m_finished && count < maxBurst) {
        const CanTime due = scheduled(m_next, m_loops.load());
        if (due > now) {
            break;
        }
        CanFrame f = m_frames[m_next];
        if (m_options.restamp) {
            f.timestamp = m_options.speed <= 0.0 ? now : due;
        }
        sink(f);
        ++count;
        ++m_emitted;
        if (++m_next == m_frames.size()) {
            m_next = 0;
            if (m_options.loop) {
                ++m_loops;
            } else {
                m_finished = true;
            }
        }
    }
    return count;
}

void Replayer::start(FrameSink sink) {
    stop();
    {
        const std::lock_guard lock(m_mutex);
        m_stop = false;
    }
    reset(CanClock::now());
    m_thread = std::thread([this, sink = std::move(sink)] {
        std::unique_lock lock(m_mutex);
        while (!m_stop && !m_finished) {
            const CanTime due = nextDue();
            if (due > CanClock::now()) {
                m_cv.wait_until(lock, due, [this] { return m_stop; });
                continue;
            }
            lock.unlock();
            advanceTo(CanClock::now(), sink);
            lock.lock();
        }
        m_cv.notify_all();
    });
}

void Replayer::stop() {
    {
        const std::lock_guard lock(m_mutex);
        m_stop = true;
    }
    m_cv.notify_all();
    if (m_thread.joinable()) {
        m_thread.join();
    }
}

void Replayer::waitFinished() {
    if (m_thread.joinable()) {
        std::unique_lock lock(m_mutex);
        m_cv.wait(lock, [this] { return m_stop || m_finished; });
    }
}

}  // namespace navmap::ipc
