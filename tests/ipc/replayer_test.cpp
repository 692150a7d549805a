// SPDX-License-Identifier: Apache-2.0
#include <gtest/gtest.h>

#include <limits>
#include <thread>

#include "frame_queue.h"
#include "navmap/ipc/can/candump_reader.h"
#include "navmap/ipc/can/replayer.h"
#include "test_paths.h"

using namespace std::chrono_literals;
using navmap::ipc::CanFrame;
using navmap::ipc::CanTime;
using navmap::ipc::FrameQueue;
using navmap::ipc::Replayer;
using navmap::ipc::ReplayOptions;

namespace {

std::vector<CanFrame> framesAt(std::initializer_list<int> millis) {
    std::vector<CanFrame> out;
    std::uint32_t id = 1;
    for (const int ms : millis) {
        CanFrame f;
        f.id = id++;
        f.len = 1;
        f.timestamp = CanTime(std::chrono::seconds(1000) + std::chrono::milliseconds(ms));
        out.push_back(f);
    }
    return out;
}

const CanTime kT0 = CanTime(std::chrono::seconds(5000));

}  // namespace

TEST(Replayer, OriginalTimingAndRestamp) {
    Replayer r(framesAt({0, 10, 30}), ReplayOptions{});
    r.reset(kT0);
    std::vector<CanFrame> out;
    const auto sink = [&](const CanFrame& f) { out.push_back(f); };
    EXPECT_EQ(r.advanceTo(kT0 - 1ms, sink), 0U);
    EXPECT_EQ(r.advanceTo(kT0, sink), 1U);
    EXPECT_EQ(r.advanceTo(kT0 + 9ms, sink), 0U);
    EXPECT_EQ(r.nextDue(), kT0 + 10ms);
    EXPECT_EQ(r.advanceTo(kT0 + 40ms, sink), 2U);
    EXPECT_TRUE(r.finished());
    EXPECT_EQ(r.nextDue(), CanTime::max());
    ASSERT_EQ(out.size(), 3U);
    EXPECT_EQ(out[0].timestamp, kT0);
    EXPECT_EQ(out[1].timestamp, kT0 + 10ms);  // scheduled time, not the late poll time
    EXPECT_EQ(out[2].timestamp, kT0 + 30ms);
    EXPECT_EQ(out[2].id, 3U);
}

TEST(Replayer, SpeedFactorAndKeepTimestamps) {
    ReplayOptions o;
    o.speed = 2.0;
    o.restamp = false;
    Replayer r(framesAt({0, 10, 30}), o);
    r.reset(kT0);
    std::vector<CanFrame> out;
    const auto sink = [&](const CanFrame& f) { out.push_back(f); };
    EXPECT_EQ(r.advanceTo(kT0 + 5ms, sink), 2U);
    EXPECT_EQ(r.advanceTo(kT0 + 14ms, sink), 0U);
    EXPECT_EQ(r.advanceTo(kT0 + 15ms, sink), 1U);
    EXPECT_EQ(out[1].timestamp, CanTime(std::chrono::seconds(1000) + 10ms));
}

TEST(Replayer, LoopsWithMeanIntervalGap) {
    ReplayOptions o;
    o.loop = true;
    Replayer r(framesAt({0, 10, 20}), o);  // period = 20 + 10 ms
    r.reset(kT0);
    std::vector<CanFrame> out;
    const auto sink = [&](const CanFrame& f) { out.push_back(f); };
    EXPECT_EQ(r.advanceTo(kT0 + 29ms, sink), 3U);
    EXPECT_EQ(r.advanceTo(kT0 + 30ms, sink), 1U);
    EXPECT_EQ(r.loops(), 1U);
    EXPECT_EQ(out.back().id, 1U);
    EXPECT_EQ(out.back().timestamp, kT0 + 30ms);
    EXPECT_EQ(r.advanceTo(kT0 + 95ms, sink), 6U);  // 40, 50 | 60, 70, 80 | 90
    EXPECT_EQ(r.loops(), 3U);
    EXPECT_FALSE(r.finished());
}

TEST(Replayer, AsFastAsPossibleIsBoundedPerCall) {
    ReplayOptions o;
    o.speed = 0.0;
    std::vector<CanFrame> frames(5000);
    Replayer r(frames, o);
    r.reset(kT0);
    std::size_t n = 0;
    const auto sink = [&](const CanFrame&) { ++n; };
    EXPECT_EQ(r.advanceTo(kT0, sink, 1000), 1000U);
    while (!r.finished()) {
        r.advanceTo(kT0, sink, 1000);
    }
    EXPECT_EQ(n, 5000U);
}

TEST(Replayer, BackwardsTimestampsAndEmptyLogs) {
    Replayer r(framesAt({0, 50, 20, 60}), ReplayOptions{});
    r.reset(kT0);
    std::vector<CanFrame> out;
    const auto sink = [&](const CanFrame& f) { out.push_back(f); };
    EXPECT_EQ(r.advanceTo(kT0 + 50ms, sink), 3U);  // the step back to 20 ms is played at 50 ms
    Replayer empty(std::vector<CanFrame>{}, ReplayOptions{});
    EXPECT_TRUE(empty.finished());
    EXPECT_EQ(empty.advanceTo(kT0 + 1h, sink), 0U);
}

TEST(Replayer, TimeArithmeticIsCheckedAtTheInt64Extremes) {
    const auto at = [](std::int64_t ns, std::uint32_t id) {
        CanFrame f;
        f.id = id;
        f.timestamp = CanTime(std::chrono::nanoseconds(ns));
        return f;
    };
    constexpr std::int64_t kMin = std::numeric_limits<std::int64_t>::min();
    constexpr std::int64_t kMax = std::numeric_limits<std::int64_t>::max();
    std::vector<CanFrame> out;
    const auto sink = [&](const CanFrame& f) { out.push_back(f); };
    {
        // Differences to the first frame that do not fit: skipped and counted, never wrapped.
        Replayer r({at(kMin, 1), at(0, 2), at(kMax, 3), at(kMin + 5, 4)}, ReplayOptions{});
        r.reset(kT0);
        EXPECT_EQ(r.advanceTo(CanTime::max(), sink), 2U);
        EXPECT_TRUE(r.finished());
        EXPECT_EQ(r.error(), "");
        EXPECT_EQ(r.timeErrors(), 2U);
        ASSERT_EQ(out.size(), 2U);
        EXPECT_EQ(out[1].id, 4U);
        EXPECT_EQ(out[1].timestamp, kT0 + 5ns);
    }
    {
        // A speed factor that scales a fine offset past the clock: the frame is skipped.
        ReplayOptions o;
        o.speed = 1e-300;
        Replayer r({at(0, 1), at(1'000'000, 2)}, o);
        r.reset(kT0);
        out.clear();
        EXPECT_EQ(r.advanceTo(CanTime::max(), sink), 1U);
        EXPECT_EQ(r.timeErrors(), 1U);
        // Not a number or infinite: as fast as possible, like 0.
        o.speed = std::numeric_limits<double>::quiet_NaN();
        Replayer nan({at(0, 1), at(kMax, 2)}, o);
        nan.reset(kT0);
        EXPECT_EQ(nan.advanceTo(kT0, sink), 2U);
        EXPECT_EQ(nan.timeErrors(), 0U);
    }
    {
        // A log spanning most of the clock cannot loop: the loop offset would overflow.
        ReplayOptions o;
        o.loop = true;
        o.speed = 4.0;
        Replayer r({at(0, 1), at(kMax - 1, 2)}, o);
        r.reset(kT0);
        out.clear();
        EXPECT_EQ(r.advanceTo(CanTime::max(), sink), 2U);
        EXPECT_EQ(out[1].timestamp,
                  kT0 + std::chrono::nanoseconds(static_cast<std::int64_t>(static_cast<double>(kMax - 1) / 4.0)));
        EXPECT_TRUE(r.finished());
        EXPECT_EQ(r.error(), "replay time out of range after 0 loops");
    }
}

TEST(Replayer, ThreadFeedsQueueWithoutBlockingConsumer) {
    ReplayOptions o;
    o.speed = 10.0;
    Replayer r(framesAt({0, 10, 20, 30, 40, 50, 60, 70, 80, 90}), o);
    FrameQueue q(64);
    const auto start = std::chrono::steady_clock::now();
    r.start([&q](const CanFrame& f) { q.push(f); });
    r.waitFinished();
    const auto elapsed = std::chrono::steady_clock::now() - start;
    r.stop();
    std::vector<CanFrame> got;
    EXPECT_EQ(q.popAll(got), 10U);
    EXPECT_EQ(got.front().id, 1U);
    EXPECT_EQ(got.back().id, 10U);
    EXPECT_GE(elapsed, 8ms);  // 90 ms of log at 10x
    for (std::size_t i = 1; i < got.size(); ++i) {
        EXPECT_GE(got[i].timestamp, got[i - 1].timestamp);
    }
    EXPECT_EQ(r.emitted(), 10U);
}

TEST(Replayer, StopEndsALoopingThread) {
    ReplayOptions o;
    o.loop = true;
    o.speed = 100.0;
    Replayer r(framesAt({0, 1, 2}), o);
    FrameQueue q(8);
    r.start([&q](const CanFrame& f) { q.push(f); });
    std::this_thread::sleep_for(20ms);
    r.stop();
    EXPECT_GT(r.loops(), 0U);
    EXPECT_GT(q.dropped(), 0U);  // nobody consumed: oldest frames were dropped, never blocked
    EXPECT_EQ(q.size(), 8U);
}

TEST(FrameQueue, DropsOldestWhenFull) {
    FrameQueue q(3);
    for (std::uint32_t i = 1; i <= 5; ++i) {
        CanFrame f;
        f.id = i;
        q.push(f);
    }
    EXPECT_EQ(q.dropped(), 2U);
    CanFrame f;
    ASSERT_TRUE(q.tryPop(f));
    EXPECT_EQ(f.id, 3U);
    std::vector<CanFrame> rest;
    EXPECT_EQ(q.popAll(rest, 1), 1U);
    EXPECT_EQ(rest[0].id, 4U);
    ASSERT_TRUE(q.tryPop(f));
    EXPECT_EQ(f.id, 5U);
    EXPECT_FALSE(q.tryPop(f));
}

TEST(Replayer, RealLogKeepsItsDuration) {
    auto log = navmap::ipc::loadCandumpFile(navmap::test::ipcDataDir() / "can" /
                                            "ford_fusion_2017_lane_keep_assist_on_red_lines.candump");
    ASSERT_TRUE(log.ok()) << log.error().message;
    Replayer r(log.value().frames(), ReplayOptions{});
    r.reset(kT0);
    std::size_t n = 0;
    CanTime last{};
    const auto sink = [&](const CanFrame& f) {
        ++n;
        last = f.timestamp;
    };
    while (r.advanceTo(kT0 + 1300ms, sink, 100000) > 0) {}
    EXPECT_GT(n, 2000U);
    EXPECT_LT(n, 2841U);  // the log lasts 1.4 s
    while (r.advanceTo(kT0 + 2s, sink, 100000) > 0) {}
    EXPECT_EQ(n, 2841U);
    EXPECT_GT(last - kT0, 1300ms);
}
