#pragma once
// Replayer: plays recorded CAN frames (e.g. a candump log) in-process with the original timing
// scaled by a speed factor, optionally looping, so that everything upstream of the decoder works
// where the kernel has no CAN. Two ways to drive it:
//  - advanceTo(now, sink): deterministic stepping from the caller's loop (tests, simulations);
//  - start(sink) / stop(): an own thread that sleeps until each frame is due and calls the sink
//    (push into a FrameQueue there so the consumer never blocks).

#include <atomic>
#include <condition_variable>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>

#include "navmap/ipc/can_frame.h"

namespace navmap::ipc {

struct ReplayOptions {
    /// Playback speed: 2.0 plays twice as fast; 0 (or negative) plays as fast as possible.
    double speed = 1.0;
    /// Start again from the first frame after the last one (forever, until stop()).
    bool loop = false;
    /// Stamp emitted frames with their scheduled emission time (realtime clock), as the kernel
    /// would; false keeps the log's timestamps.
    bool restamp = true;
};

using FrameSink = std::function<void(const CanFrame&)>;

class Replayer {
public:
    /// `frames` in log order (timestamps non-decreasing; a backwards step is treated as 0 s).
    Replayer(std::vector<CanFrame> frames, ReplayOptions options);
    ~Replayer();
    Replayer(const Replayer&) = delete;
    Replayer& operator=(const Replayer&) = delete;

    /// Sets the wall-clock time at which the first frame is due (and rewinds).
    void reset(CanTime startTime);
    /// Emits every frame due at or before `now` to `sink`; returns how many were emitted.
    /// With speed <= 0 emits at most `maxBurst` frames per call.
    std::size_t advanceTo(CanTime now, const FrameSink& sink, std::size_t maxBurst = 1024);
    /// Time at which the next frame is due, or nullopt-like CanTime::max() when finished.
    CanTime nextDue() const noexcept;
    bool finished() const noexcept;

    /// Runs the replay on an own thread from now on. Call stop() (or destroy) to end it.
    void start(FrameSink sink);
    void stop();
    /// Waits until a non-looping replay on the thread has finished (or stop()).
    void waitFinished();

    std::uint64_t emitted() const noexcept { return m_emitted.load(); }
    std::uint64_t loops() const noexcept { return m_loops.load(); }
    std::size_t frameCount() const noexcept { return m_frames.size(); }

private:
    CanTime scheduled(std::size_t index, std::uint64_t loop) const noexcept;

    std::vector<CanFrame> m_frames;
    std::vector<std::chrono::nanoseconds> m_offsets;  // log time since the first frame, monotone
    std::chrono::nanoseconds m_period{0};             // loop length in log time
    ReplayOptions m_options;
    CanTime m_start{};
    std::size_t m_next = 0;
    std::atomic<std::uint64_t> m_loops{0};
    std::atomic<std::uint64_t> m_emitted{0};
    std::atomic<bool> m_finished{false};

    std::thread m_thread;
    std::mutex m_mutex;
    std::condition_variable m_cv;
    bool m_stop = false;
};

}  // namespace navmap::ipc
