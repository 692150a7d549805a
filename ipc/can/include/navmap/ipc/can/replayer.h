// SPDX-License-Identifier: Apache-2.0
#pragma once
// Replayer: plays recorded CAN frames (e.g. a candump log) in-process with the original timing
// scaled by a speed factor, optionally looping, so that everything upstream of the decoder works
// where the kernel has no CAN. Frames come one at a time from a ReplaySource (a streamed candump
// file, or a vector), one frame read ahead. Time arithmetic is checked: a frame whose schedule
// does not fit the clock is skipped and counted (timeErrors()), never overflowed. Two ways to
// drive it:
//  - advanceTo(now, sink): deterministic stepping from the caller's loop (tests, simulations);
//  - start(sink) / stop(): an own thread that sleeps until each frame is due and calls the sink
//    (push into a FrameQueue there so the consumer never blocks).

#include <atomic>
#include <condition_variable>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "navmap/ipc/can/can_frame.h"
#include "navmap/ipc/can/replay_source.h"

namespace navmap::ipc {

struct ReplayOptions {
    /// Playback speed: 2.0 plays twice as fast; 0 (or negative, or not finite) plays as fast as
    /// possible.
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
    /// Frames from `source`, which the replayer owns (it reads the first one at once: a source
    /// that fails there is finished with error() set).
    Replayer(std::unique_ptr<ReplaySource> source, ReplayOptions options);
    ~Replayer();
    Replayer(const Replayer&) = delete;
    Replayer& operator=(const Replayer&) = delete;

    /// Sets the wall-clock time at which the first frame is due (and rewinds the source).
    void reset(CanTime start_time);
    /// Emits every frame due at or before `now` to `sink`; returns how many were emitted.
    /// With speed <= 0 emits at most `maxBurst` frames per call.
    std::size_t advanceTo(CanTime now, const FrameSink& sink, std::size_t max_burst = 1024);
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
    /// Frames skipped because their time did not fit the clock (log time differences, the speed
    /// factor, the loop count).
    std::uint64_t timeErrors() const noexcept { return m_time_errors.load(); }
    /// Why the replay stopped early (the source failed, e.g. binary data, or it cannot loop);
    /// empty while it plays or after a normal end.
    std::string error() const;
    /// The source (for its counters), owned by the replayer.
    const ReplaySource& source() const noexcept { return *m_source; }

private:
    bool fetch();
    void finish(std::string error);
    /// Wall time of a log time (since the first pass's first frame); false when it does not fit.
    bool schedule(std::int64_t log_ns, CanTime& due) const;

    std::unique_ptr<ReplaySource> m_source;
    ReplayOptions m_options;
    CanTime m_start{};
    // The frame read ahead: the next to emit, due at m_pending_due.
    CanFrame m_pending{};
    std::int64_t m_pending_log_ns = 0;
    CanTime m_pending_due{};
    bool m_fresh = false;  // the source was wound back and nothing was played since
    // Log time of this pass: its first frame's timestamp and the last offset (monotone).
    bool m_pass_started = false;
    CanTime m_pass_first{};
    std::int64_t m_prev_offset_ns = 0;
    std::uint64_t m_pass_frames = 0;
    std::int64_t m_loop_base_ns = 0;  // log time of the passes before this one
    std::atomic<std::uint64_t> m_loops{0};
    std::atomic<std::uint64_t> m_emitted{0};
    std::atomic<std::uint64_t> m_time_errors{0};
    std::atomic<bool> m_finished{false};
    std::string m_error;  // written before m_finished is set

    std::thread m_thread;
    std::mutex m_mutex;
    std::condition_variable m_cv;
    bool m_stop = false;
};

}  // namespace navmap::ipc
