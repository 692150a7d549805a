// SPDX-License-Identifier: Apache-2.0
// ControlServer stepped with pollOnce() from the test's thread, on what its poll loop owes the
// clients: an event published from another thread ends a long pollOnce() at once, a peer that
// half-closes after its requests gets every reply before the close, and a closed connection's
// slot and descriptor number go to the next client, which is then served.

#include <gtest/gtest.h>

#include <sys/socket.h>
#include <sys/un.h>
#include <unistd.h>

#include <chrono>
#include <cstring>
#include <memory>
#include <string>
#include <thread>

#include "control_test_util.h"
#include "navmap/ipc/control/control_client.h"
#include "navmap/ipc/control/control_server.h"
#include "navmap/ipc/control/control_state.h"

using namespace navmap::ipc;
using namespace std::chrono_literals;
using navmap::test::countOpenFds;

namespace {

// A ControlServer that nobody steps but the test (no own thread).
struct SteppedServer : navmap::test::ControlServerFixture {
    explicit SteppedServer(ControlServerConfig cfg = {}) : ControlServerFixture(cfg, false) {}
};

// A raw, blocking connection (ControlClient never half-closes).
int connectRaw(const std::string& path) {
    const int fd = ::socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0);
    sockaddr_un addr{};
    addr.sun_family = AF_UNIX;
    std::memcpy(addr.sun_path, path.data(), path.size());
    if (fd < 0 || ::connect(fd, reinterpret_cast<const sockaddr*>(&addr), sizeof addr) != 0) {
        ADD_FAILURE() << "connect(" << path << "): " << std::strerror(errno);
    }
    return fd;
}

}  // namespace

TEST(ControlServerLoop, AnEventPublishedFromAnotherThreadEndsALongPollOnce) {
    const int fds = countOpenFds();
    {
        SteppedServer s;
        ASSERT_TRUE(s.server);
        auto c = ControlClient::connect(s.server->path());
        ASSERT_TRUE(c.ok()) << c.error().message;
        ASSERT_TRUE(c.value().send(R"({"cmd":"subscribe","events":["position_lost"]})").ok());
        s.stepUntil([&] { return s.server->stats().commands == 1; });
        auto reply = c.value().readLine(1s);
        ASSERT_TRUE(reply.ok()) << reply.error().message;
        EXPECT_EQ(reply.value(), R"({"ok":true,"cmd":"subscribe","events":["position_lost"]})");

        std::thread publisher([&] {
            std::this_thread::sleep_for(100ms);
            s.server->publish({ControlEventKind::PositionLost, {}, 0, 0, 4.0});
        });
        // One call with a long timeout: the publish wakes it and the event goes out in that call.
        const auto t0 = std::chrono::steady_clock::now();
        ASSERT_TRUE(s.server->pollOnce(20s).ok());
        const auto waited = std::chrono::steady_clock::now() - t0;
        publisher.join();
        EXPECT_LT(waited, 10s) << "pollOnce() slept through the publish";
        EXPECT_EQ(s.server->stats().events, 1U);
        auto event = c.value().nextEvent(1s);
        ASSERT_TRUE(event.ok()) << event.error().message;
        EXPECT_EQ(event.value(), R"({"event":"position_lost","since_s":4.0})");
    }
    EXPECT_EQ(countOpenFds(), fds);
}

TEST(ControlServerLoop, AHalfClosedPeerGetsEveryReplyThenTheClose) {
    const int fds = countOpenFds();
    {
        SteppedServer s;
        ASSERT_TRUE(s.server);
        const int fd = connectRaw(s.server->path());
        ASSERT_GE(fd, 0);
        const std::string requests =
            "{\"cmd\":\"clear_route\"}\n{\"cmd\":\"set_style\",\"style\":\"dusk\"}\n"
            "{\"cmd\":\"set_style\",\"style\":\"night\"}\n";
        ASSERT_EQ(::send(fd, requests.data(), requests.size(), MSG_NOSIGNAL), static_cast<ssize_t>(requests.size()));
        ASSERT_EQ(::shutdown(fd, SHUT_WR), 0);  // done sending: the server sees the end of its stream
        s.stepUntil([&] { return s.server->stats().lines == 3 && s.server->stats().clients == 0; });
        EXPECT_EQ(s.server->stats().clients, 0U) << "the half-closed connection is closed once answered";
        std::string got;
        char buf[4096];
        for (;;) {
            const ssize_t n = ::recv(fd, buf, sizeof buf, 0);
            if (n <= 0) {
                break;  // the server's close
            }
            got.append(buf, static_cast<std::size_t>(n));
        }
        ::close(fd);
        EXPECT_EQ(got,
                  "{\"ok\":true,\"cmd\":\"clear_route\"}\n"
                  "{\"ok\":false,\"cmd\":\"set_style\",\"error\":\"\\\"style\\\": \\\"dusk\\\" is not one of day | "
                  "night | auto\"}\n"
                  "{\"ok\":true,\"cmd\":\"set_style\"}\n");
        EXPECT_EQ(s.state.view()->style, MapStyle::Night);
    }
    EXPECT_EQ(countOpenFds(), fds);
}

TEST(ControlServerLoop, AClosedConnectionsSlotAndDescriptorGoToTheNextClient) {
    const int fds = countOpenFds();
    {
        ControlServerConfig cfg;
        cfg.max_clients = 1;
        SteppedServer s(cfg);
        ASSERT_TRUE(s.server);
        for (int round = 0; round < 3; ++round) {
            // The previous client closed without a word; its EOF, its removal and this accept can
            // fall into one round, where the new socket often gets the old one's number.
            auto c = ControlClient::connect(s.server->path());
            ASSERT_TRUE(c.ok()) << c.error().message;
            s.stepUntil([&] { return s.server->stats().connections == static_cast<std::uint64_t>(round) + 1; });
            const std::string id = "r" + std::to_string(round);
            ASSERT_TRUE(c.value().send(R"({"cmd":"set_route","id":")" + id + R"(","points":[[1,2],[3,4]]})").ok());
            s.stepUntil([&] { return s.server->stats().commands == static_cast<std::uint64_t>(round) + 1; });
            auto reply = c.value().readLine(1s);
            ASSERT_TRUE(reply.ok()) << reply.error().message;
            EXPECT_EQ(reply.value(), R"({"ok":true,"cmd":"set_route","id":")" + id + R"(","maneuvers":0,"points":2})");
        }
        EXPECT_EQ(s.server->stats().refused_full, 0U);
        EXPECT_EQ(s.state.route()->id, "r2");
    }
    EXPECT_EQ(countOpenFds(), fds);
}
