// SPDX-License-Identifier: Apache-2.0
#include "navmap/ipc/can/replayer.h"

#include <algorithm>
#include <cmath>

namespace navmap::ipc {

namespace {

// Frames already in memory (the simulator's drive, tests).
class VectorSource final : public ReplaySource {
public:
    explicit VectorSource(std::vector<CanFrame> frames) : m_frames(std::move(frames)) {}
    bool next(CanFrame& out) override {
        if (m_next >= m_frames.size()) {
            return false;
        }
        out = m_frames[m_next++];
        return true;
    }
    bool rewind() override {
        m_next = 0;
        return true;
    }
    [[nodiscard]] const std::string& failure() const override { return m_failure; }

private:
    std::vector<CanFrame> m_frames;
    std::size_t m_next = 0;
    std::string m_failure;  // never set
};

// Checked nanosecond arithmetic: log timestamps come from files and can be anything.
bool addNs(std::int64_t a, std::int64_t b, std::int64_t& out) { return !__builtin_add_overflow(a, b, &out); }
bool subNs(std::int64_t a, std::int64_t b, std::int64_t& out) { return !__builtin_sub_overflow(a, b, &out); }

bool playsAsFastAsPossible(double speed) { return !(speed > 0.0) || !std::isfinite(speed); }

}  // namespace

Replayer::Replayer(std::vector<CanFrame> frames, ReplayOptions options)
    : Replayer(std::make_unique<VectorSource>(std::move(frames)), options) {}

Replayer::Replayer(std::unique_ptr<ReplaySource> source, ReplayOptions options)
    : m_source(std::move(source)), m_options(options) {
    reset(CanClock::now());
}

Replayer::~Replayer() { stop(); }

void Replayer::reset(CanTime start_time) {
    m_start = start_time;
    if (m_fresh && !m_finished) {
        // Nothing played since the source was (re)wound: keep the frame read ahead, so the source
        // does not read (and count) its first chunk twice. Its time is rescheduled.
        if (!schedule(m_pending_log_ns, m_pending_due)) {
            ++m_time_errors;
            m_fresh = false;
            if (fetch()) m_fresh = true;
        }
        return;
    }
    m_loops = 0;
    m_pass_started = false;
    m_prev_offset_ns = 0;
    m_pass_frames = 0;
    m_loop_base_ns = 0;
    m_error.clear();
    m_finished = false;
    if (!m_source->rewind()) {
        finish(m_source->failure());
        return;
    }
    m_fresh = fetch();
}

bool Replayer::schedule(std::int64_t log_ns, CanTime& due) const {
    if (playsAsFastAsPossible(m_options.speed)) {
        due = m_start;
        return true;
    }
    // Below 2^63 the conversion back to int64 is defined.
    const double wall_ns = static_cast<double>(log_ns) / m_options.speed;
    std::int64_t due_ns = 0;
    if (!(wall_ns >= 0.0 && wall_ns < 0x1p63) ||
        !addNs(m_start.time_since_epoch().count(), static_cast<std::int64_t>(wall_ns), due_ns)) {
        return false;
    }
    due = CanTime(std::chrono::nanoseconds(due_ns));
    return true;
}

void Replayer::finish(std::string error) {
    m_error = std::move(error);
    m_finished = true;
}

std::string Replayer::error() const { return m_finished.load() ? m_error : std::string(); }

// Reads the next frame into m_pending with its due time; at the end of a pass rewinds (loop) or
// finishes. False when the replay is finished.
bool Replayer::fetch() {
    for (;;) {
        CanFrame f;
        if (m_source->next(f)) {
            // Log time since the pass's first frame; a log whose time goes backwards (clock step
            // while recording) is played without waiting.
            std::int64_t offset = 0;
            if (!m_pass_started) {
                m_pass_started = true;
                m_pass_first = f.timestamp;
            } else if (!subNs(f.timestamp.time_since_epoch().count(), m_pass_first.time_since_epoch().count(),
                              offset)) {
                ++m_time_errors;
                continue;
            }
            offset = std::max(offset, m_prev_offset_ns);
            std::int64_t log_ns = 0;
            CanTime due{};
            if (!addNs(m_loop_base_ns, offset, log_ns) || !schedule(log_ns, due)) {
                ++m_time_errors;
                continue;
            }
            m_prev_offset_ns = offset;
            ++m_pass_frames;
            m_pending = f;
            m_pending_log_ns = log_ns;
            m_pending_due = due;
            return true;
        }
        if (!m_source->failure().empty()) {
            finish(m_source->failure());
            return false;
        }
        if (m_pass_frames == 0 || !m_options.loop) {
            finish({});  // the end, or a log without a playable frame: nothing to loop
            return false;
        }
        // One loop lasts the log plus one mean frame interval, so the first frame of the next
        // loop does not coincide with the last of this one.
        const std::int64_t span = m_prev_offset_ns;
        const std::int64_t gap = m_pass_frames > 1 ? span / static_cast<std::int64_t>(m_pass_frames - 1) : 0;
        std::int64_t period = 0;
        if (!addNs(span, gap, period) ||
            !addNs(m_loop_base_ns, std::max<std::int64_t>(period, 1'000'000), m_loop_base_ns)) {
            finish("replay time out of range after " + std::to_string(m_loops.load()) + " loops");
            return false;
        }
        ++m_loops;
        m_pass_started = false;
        m_prev_offset_ns = 0;
        m_pass_frames = 0;
        if (!m_source->rewind()) {
            finish(m_source->failure());
            return false;
        }
    }
}

CanTime Replayer::nextDue() const noexcept {
    if (m_finished) {
        return CanTime::max();
    }
    return m_pending_due;
}

bool Replayer::finished() const noexcept { return m_finished.load(); }

std::size_t Replayer::advanceTo(CanTime now, const FrameSink& sink, std::size_t max_burst) {
    std::size_t count = 0;
    while (!m_finished && count < max_burst) {
        if (m_pending_due > now) {
            break;
        }
        CanFrame f = m_pending;
        if (m_options.restamp) {
            f.timestamp = playsAsFastAsPossible(m_options.speed) ? now : m_pending_due;
        }
        sink(f);
        ++count;
        ++m_emitted;
        m_fresh = false;
        fetch();
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
