// SPDX-License-Identifier: Apache-2.0
#include <gtest/gtest.h>

#include <linux/can.h>
#include <linux/can/error.h>
#include <linux/can/raw.h>

#include "navmap/ipc/can/socketcan_codec.h"
#include "navmap/ipc/can/socketcan_source.h"
#include "navmap/ipc/net/backoff.h"
#include "open_fds.h"

using namespace std::chrono_literals;
using navmap::ipc::Backoff;
using navmap::ipc::CanFrame;
using navmap::ipc::CanTime;

namespace {}  // namespace

TEST(SocketCanCodec, ClassicExtendedRtrAndFdFromKernel) {
    const CanTime t(std::chrono::seconds(7));
    can_frame k{};
    k.can_id = 0x415;
    k.len = 8;
    for (int i = 0; i < 8; ++i) {
        k.data[i] = static_cast<std::uint8_t>(i + 1);
    }
    auto f = navmap::ipc::frameFromKernel(&k, CAN_MTU, t);
    ASSERT_TRUE(f.has_value());
    EXPECT_EQ(f->id, 0x415U);
    EXPECT_EQ(f->len, 8);
    EXPECT_EQ(f->data[7], 8);
    EXPECT_EQ(f->timestamp, t);
    EXPECT_FALSE(f->extended());

    k.can_id = 0x1ABCDEF0 | CAN_EFF_FLAG | CAN_RTR_FLAG;
    k.len = 3;
    f = navmap::ipc::frameFromKernel(&k, CAN_MTU, t);
    ASSERT_TRUE(f.has_value());
    EXPECT_TRUE(f->extended());
    EXPECT_TRUE(f->rtr());
    EXPECT_EQ(f->id, 0x1ABCDEF0U);
    EXPECT_EQ(f->data[0], 0);  // no payload for RTR

    canfd_frame fd{};
    fd.can_id = 0x123;
    fd.len = 64;
    fd.flags = CANFD_BRS;
    fd.data[63] = 0x5A;
    f = navmap::ipc::frameFromKernel(&fd, CANFD_MTU, t);
    ASSERT_TRUE(f.has_value());
    EXPECT_TRUE(f->fd());
    EXPECT_EQ(f->len, 64);
    EXPECT_EQ(f->data[63], 0x5A);
    EXPECT_NE(f->flags & navmap::ipc::kCanBrs, 0);

    // Wrong sizes and lengths are rejected.
    EXPECT_FALSE(navmap::ipc::frameFromKernel(&fd, 20, t).has_value());
    EXPECT_FALSE(navmap::ipc::frameFromKernel(nullptr, CAN_MTU, t).has_value());
    fd.len = 13;
    EXPECT_FALSE(navmap::ipc::frameFromKernel(&fd, CANFD_MTU, t).has_value());
    k.len = 9;
    EXPECT_FALSE(navmap::ipc::frameFromKernel(&k, CAN_MTU, t).has_value());
}

TEST(SocketCanCodec, ToKernelRoundTrip) {
    CanFrame f;
    f.id = 0x1FFFFFFF;
    f.flags = navmap::ipc::kCanExtended;
    f.len = 5;
    f.data[4] = 0x99;
    canfd_frame k{};
    ASSERT_EQ(navmap::ipc::frameToKernel(f, k), static_cast<std::size_t>(CAN_MTU));
    EXPECT_EQ(k.can_id, 0x1FFFFFFFU | CAN_EFF_FLAG);
    auto back = navmap::ipc::frameFromKernel(&k, CAN_MTU, CanTime{});
    ASSERT_TRUE(back.has_value());
    EXPECT_EQ(back->id, f.id);
    EXPECT_EQ(back->data[4], 0x99);
    f.flags = navmap::ipc::kCanFd | navmap::ipc::kCanEsi;
    f.id = 0x7FF;
    f.len = 48;
    ASSERT_EQ(navmap::ipc::frameToKernel(f, k), static_cast<std::size_t>(CANFD_MTU));
    EXPECT_EQ(k.flags, CANFD_ESI);
    EXPECT_EQ(k.len, 48);
}

TEST(SocketCanCodec, FiltersMatchExactIds) {
    const std::uint32_t keys[] = {0x415, 0x091, 0x80000400};
    const auto filters = navmap::ipc::buildRawFilters(keys);
    ASSERT_EQ(filters.size(), 3U);
    EXPECT_EQ(filters[0].can_id, 0x415U);
    EXPECT_EQ(filters[0].can_mask, CAN_SFF_MASK | CAN_EFF_FLAG | CAN_RTR_FLAG);
    EXPECT_EQ(filters[2].can_id, 0x400U | CAN_EFF_FLAG);
    EXPECT_EQ(filters[2].can_mask, CAN_EFF_MASK | CAN_EFF_FLAG | CAN_RTR_FLAG);
    // How the kernel applies a filter: (id & mask) == (filter.id & mask).
    const auto matches = [&](canid_t id) {
        for (const auto& f : filters) {
            if ((id & f.can_mask) == (f.can_id & f.can_mask)) {
                return true;
            }
        }
        return false;
    };
    EXPECT_TRUE(matches(0x415));
    EXPECT_FALSE(matches(0x416));
    EXPECT_FALSE(matches(0x415 | CAN_EFF_FLAG));  // 29-bit 0x415 is another frame
    EXPECT_FALSE(matches(0x415 | CAN_RTR_FLAG));
    EXPECT_TRUE(matches(0x400 | CAN_EFF_FLAG));
    EXPECT_FALSE(matches(0x400));
    EXPECT_TRUE(navmap::ipc::buildRawFilters({}).empty());
    const std::vector<std::uint32_t> too_many(CAN_RAW_FILTER_MAX + 1, 1);
    EXPECT_TRUE(navmap::ipc::buildRawFilters(too_many).empty());
}

TEST(SocketCanCodec, ErrorFrameClassification) {
    CanFrame f;
    f.flags = navmap::ipc::kCanError;
    f.len = 8;
    f.id = CAN_ERR_BUSOFF;
    auto info = navmap::ipc::classifyErrorFrame(f);
    EXPECT_TRUE(info.bus_off);
    EXPECT_EQ(info.describe(), "bus-off");
    f.id = CAN_ERR_CRTL | CAN_ERR_ACK;
    f.data[1] = CAN_ERR_CRTL_RX_OVERFLOW | CAN_ERR_CRTL_TX_PASSIVE;
    info = navmap::ipc::classifyErrorFrame(f);
    EXPECT_TRUE(info.controller_problem);
    EXPECT_TRUE(info.rx_overflow);
    EXPECT_TRUE(info.error_passive);
    EXPECT_EQ(info.describe(), "controller problem (overflow, error passive); no ACK");
    f.flags = 0;
    EXPECT_FALSE(navmap::ipc::classifyErrorFrame(f).bus_off);
}

TEST(Backoff, DoublesUpToTheCapAndResets) {
    Backoff b(100ms, 1000ms);
    const auto t0 = Backoff::Clock::time_point{} + 1h;
    EXPECT_TRUE(b.due(t0));
    b.failed(t0);
    EXPECT_FALSE(b.due(t0 + 99ms));
    EXPECT_TRUE(b.due(t0 + 100ms));
    const std::chrono::milliseconds expected[] = {200ms, 400ms, 800ms, 1000ms, 1000ms};
    for (const auto e : expected) {
        EXPECT_EQ(b.currentDelay(), e);
        b.failed(t0);
    }
    EXPECT_EQ(b.nextAttempt(), t0 + 1000ms);
    EXPECT_EQ(b.failures(), 6U);
    b.succeeded();
    EXPECT_EQ(b.currentDelay(), 100ms);
    EXPECT_TRUE(b.due(t0));
}

// Where the kernel has no AF_CAN (this host) or the interface does not exist, the source reports
// the failing call, backs off and never blocks; poll() returns at once.
TEST(SocketCanSource, MissingInterfaceOrFamilyBacksOffWithoutBlocking) {
    const int fds_before = navmap::test::countOpenFds();
    {
        navmap::ipc::SocketCanOptions o;
        o.interface_name = "navmapnone0";
        o.backoff_initial = 50ms;
        navmap::ipc::SocketCanSource src(o);
        std::size_t frames = 0;
        const auto start = std::chrono::steady_clock::now();
        EXPECT_EQ(src.poll([&](const CanFrame&) { ++frames; }), 0U);
        EXPECT_EQ(src.status().state, navmap::ipc::SocketCanStatus::State::Retrying);
        const std::string& err = src.status().last_error;
        const bool no_family = err.rfind("socket(PF_CAN)(navmapnone0): ", 0) == 0;
        const bool no_device = err.rfind("if_nametoindex(navmapnone0): No such device", 0) == 0;
        EXPECT_TRUE(no_family || no_device) << err;
        EXPECT_EQ(src.status().open_failures, 1U);
        EXPECT_EQ(src.fd(), -1);
        // Within the backoff window no new attempt is made.
        EXPECT_EQ(src.poll([&](const CanFrame&) { ++frames; }), 0U);
        EXPECT_EQ(src.status().open_failures, 1U);
        src.waitReadable(1000ms);  // sleeps only until the retry is due (50 ms)
        EXPECT_EQ(src.poll([&](const CanFrame&) { ++frames; }), 0U);
        EXPECT_EQ(src.status().open_failures, 2U);
        EXPECT_EQ(src.backoff().currentDelay(), 200ms);
        EXPECT_LT(std::chrono::steady_clock::now() - start, 500ms);
        EXPECT_FALSE(src.send(CanFrame{}).ok());
        EXPECT_EQ(frames, 0U);
    }
    navmap::ipc::SocketCanOptions bad;
    bad.interface_name = "an-interface-name-too-long";
    navmap::ipc::SocketCanSource src(bad);
    EXPECT_EQ(src.poll([](const CanFrame&) {}), 0U);
    EXPECT_NE(src.status().last_error.find("must have 1..15 characters"), std::string::npos);
    EXPECT_EQ(navmap::test::countOpenFds(), fds_before);  // no socket leaked by the failed opens
}
