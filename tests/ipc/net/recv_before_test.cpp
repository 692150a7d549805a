// SPDX-License-Identifier: Apache-2.0
// recvBefore, the clients' one wait-and-receive step: bytes that arrive, a deadline that passes,
// the peer's close, a recv() error, and a signal in the middle of the wait (retried, not an error).

#include "navmap/ipc/net/recv_before.h"

#include <gtest/gtest.h>
#include <pthread.h>
#include <signal.h>
#include <sys/socket.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <string>
#include <thread>

#include "navmap/ipc/net/unique_fd.h"

namespace {

using navmap::ipc::net::Received;
using navmap::ipc::net::recvBefore;
using navmap::ipc::net::UniqueFd;
using namespace std::chrono_literals;
using Clock = std::chrono::steady_clock;

struct SocketPair {
    UniqueFd a, b;
    SocketPair() {
        int fds[2] = {-1, -1};
        EXPECT_EQ(::socketpair(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0, fds), 0);
        a.reset(fds[0]);
        b.reset(fds[1]);
    }
};

std::atomic<int> g_signals{0};
void countSignal(int) { ++g_signals; }

TEST(RecvBeforeTest, ReturnsWhatArrivedUpToTheBufferSize) {
    SocketPair s;
    ASSERT_EQ(::send(s.b.get(), "hello world", 11, 0), 11);
    char buf[5];
    const auto got = recvBefore(s.a.get(), buf, sizeof buf, Clock::now() + 1s, "peer");
    ASSERT_EQ(got.kind, Received::Kind::Data) << got.error;
    ASSERT_EQ(got.bytes, 5U);
    EXPECT_EQ(std::string(buf, 5), "hello");
}

TEST(RecvBeforeTest, APassedDeadlineIsATimeoutNotAnError) {
    SocketPair s;
    char buf[8];
    const auto got = recvBefore(s.a.get(), buf, sizeof buf, Clock::now() - 1s, "peer");
    EXPECT_EQ(got.kind, Received::Kind::TimedOut);
    EXPECT_EQ(got.bytes, 0U);
    EXPECT_EQ(got.error, "");
}

TEST(RecvBeforeTest, ThePeersCloseAndRecvErrorsNameThePeer) {
    SocketPair s;
    s.b.reset();
    char buf[8];
    const auto closed = recvBefore(s.a.get(), buf, sizeof buf, Clock::now() + 1s, "/run/navmap/control.sock");
    EXPECT_EQ(closed.kind, Received::Kind::Failed);
    EXPECT_EQ(closed.error, "recv(/run/navmap/control.sock): connection closed by the server");

    int p[2] = {-1, -1};
    ASSERT_EQ(::pipe(p), 0);  // readable, but no socket: recv() fails with ENOTSOCK
    const UniqueFd in(p[0]), out(p[1]);
    ASSERT_EQ(::write(out.get(), "x", 1), 1);
    const auto failed = recvBefore(in.get(), buf, sizeof buf, Clock::now() + 1s, "tcp:host:1");
    EXPECT_EQ(failed.kind, Received::Kind::Failed);
    EXPECT_EQ(failed.error, "recv(tcp:host:1): Socket operation on non-socket");
}

TEST(RecvBeforeTest, ASignalDuringTheWaitIsRetriedAndTheDataStillArrives) {
    struct sigaction sa {};
    struct sigaction old {};
    sa.sa_handler = countSignal;  // no SA_RESTART; poll() is never restarted anyway
    ASSERT_EQ(::sigaction(SIGUSR1, &sa, &old), 0);
    SocketPair s;
    g_signals = 0;
    const pthread_t waiter = ::pthread_self();
    std::thread sender([&] {
        std::this_thread::sleep_for(100ms);
        ::pthread_kill(waiter, SIGUSR1);
        std::this_thread::sleep_for(100ms);
        [[maybe_unused]] const auto n = ::send(s.b.get(), "late", 4, 0);
    });
    char buf[8];
    const auto got = recvBefore(s.a.get(), buf, sizeof buf, Clock::now() + 20s, "peer");
    sender.join();
    ::sigaction(SIGUSR1, &old, nullptr);
    EXPECT_EQ(g_signals.load(), 1);
    ASSERT_EQ(got.kind, Received::Kind::Data) << got.error;
    EXPECT_EQ(std::string(buf, got.bytes), "late");
}

}  // namespace
