// SPDX-License-Identifier: Apache-2.0
// Signals through a signalfd and systemd notifications through a real NOTIFY_SOCKET.
#include <gtest/gtest.h>

#include <signal.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <string>

#include "lifecycle.h"

namespace {

using namespace navmap::daemon;

TEST(Lifecycle, SignalsArriveThroughTheLoopNotAHandler) {
    Signals signals;
    EXPECT_EQ(signals.wait(std::chrono::milliseconds(0)), SignalEvent::None);
    ::kill(::getpid(), SIGHUP);
    EXPECT_EQ(signals.wait(std::chrono::milliseconds(500)), SignalEvent::Reload);
    ::kill(::getpid(), SIGHUP);
    ::kill(::getpid(), SIGTERM);
    EXPECT_EQ(signals.wait(std::chrono::milliseconds(500)), SignalEvent::Stop) << "a stop wins over a reload";
    EXPECT_EQ(signals.wait(std::chrono::milliseconds(0)), SignalEvent::None);
}

struct NotifySocket {
    int fd = -1;
    std::string path;
    NotifySocket() {
        path = (std::filesystem::temp_directory_path() / ("navmap-notify-" + std::to_string(::getpid()))).string();
        ::unlink(path.c_str());
        fd = ::socket(AF_UNIX, SOCK_DGRAM | SOCK_CLOEXEC, 0);
        sockaddr_un a{};
        a.sun_family = AF_UNIX;
        std::snprintf(a.sun_path, sizeof a.sun_path, "%s", path.c_str());
        EXPECT_EQ(::bind(fd, reinterpret_cast<sockaddr*>(&a), sizeof a), 0);
    }
    ~NotifySocket() {
        ::close(fd);
        ::unlink(path.c_str());
    }
    std::string receive() {
        char buf[512];
        timeval tv{1, 0};
        ::setsockopt(fd, SOL_SOCKET, SO_RCVTIMEO, &tv, sizeof tv);
        const ssize_t n = ::recv(fd, buf, sizeof buf, 0);
        return n > 0 ? std::string(buf, static_cast<std::size_t>(n)) : std::string();
    }
};

TEST(Lifecycle, SystemdGetsReadyStatusAndWatchdog) {
    NotifySocket sock;
    ::setenv("NOTIFY_SOCKET", sock.path.c_str(), 1);
    ::setenv("WATCHDOG_USEC", "200000", 1);
    ::setenv("WATCHDOG_PID", std::to_string(::getpid()).c_str(), 1);
    SystemdNotifier n;
    ASSERT_TRUE(n.active());
    EXPECT_EQ(n.watchdogInterval(), std::chrono::microseconds(200000));
    n.ready("rendering 3 profiles");
    EXPECT_EQ(sock.receive(), "READY=1\nSTATUS=rendering 3 profiles");
    n.watchdog();
    EXPECT_EQ(sock.receive(), "WATCHDOG=1");
    n.watchdog();  // within half an interval: not repeated
    n.status("ok");
    EXPECT_EQ(sock.receive(), "STATUS=ok");
    n.stopping();
    EXPECT_EQ(sock.receive(), "STOPPING=1");
    ::unsetenv("NOTIFY_SOCKET");
    ::unsetenv("WATCHDOG_USEC");
    ::unsetenv("WATCHDOG_PID");
}

TEST(Lifecycle, WithoutSystemdNothingIsSent) {
    ::unsetenv("NOTIFY_SOCKET");
    SystemdNotifier n;
    EXPECT_FALSE(n.active());
    n.ready("x");  // must not crash or block
}

}  // namespace
