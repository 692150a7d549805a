// SPDX-License-Identifier: Apache-2.0
// FrameServer's caps per peer address on TCP and HTTP: one host that opens every slot of a
// transport leaves room for another host's TCP or MJPEG client. Distinct hosts are loopback
// addresses (the whole of 127.0.0.0/8 is loopback on Linux); IPv6 peers count per /64 and an
// IPv4 peer on a dual-stack socket by its IPv4 address.

#include <arpa/inet.h>
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cstring>
#include <string>
#include <vector>

#include "navmap/ipc/client/frame_header.h"
#include "navmap/ipc/client/stream_profile.h"
#include "navmap/ipc/stream/frame_server.h"
#include "stream_test_util.h"

using namespace navmap::ipc;
using namespace navmap::stream_test;
using namespace std::chrono_literals;

namespace {

// A TCP connection to `to`:`port` from the address `from` (bound before connect); -1 on error.
int connectFrom(const std::string& from, const std::string& to, int port) {
    const bool v6 = from.find(':') != std::string::npos;
    const int fd = ::socket(v6 ? AF_INET6 : AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
    if (fd < 0) {
        return -1;
    }
    sockaddr_storage src{};
    sockaddr_storage dst{};
    socklen_t len = 0;
    if (v6) {
        auto& s6 = reinterpret_cast<sockaddr_in6&>(src);
        auto& d6 = reinterpret_cast<sockaddr_in6&>(dst);
        s6.sin6_family = d6.sin6_family = AF_INET6;
        d6.sin6_port = htons(static_cast<std::uint16_t>(port));
        ::inet_pton(AF_INET6, from.c_str(), &s6.sin6_addr);
        ::inet_pton(AF_INET6, to.c_str(), &d6.sin6_addr);
        len = sizeof(sockaddr_in6);
    } else {
        auto& s4 = reinterpret_cast<sockaddr_in&>(src);
        auto& d4 = reinterpret_cast<sockaddr_in&>(dst);
        s4.sin_family = d4.sin_family = AF_INET;
        d4.sin_port = htons(static_cast<std::uint16_t>(port));
        ::inet_pton(AF_INET, from.c_str(), &s4.sin_addr);
        ::inet_pton(AF_INET, to.c_str(), &d4.sin_addr);
        len = sizeof(sockaddr_in);
    }
    if (::bind(fd, reinterpret_cast<sockaddr*>(&src), len) != 0 ||
        ::connect(fd, reinterpret_cast<sockaddr*>(&dst), len) != 0) {
        ::close(fd);
        return -1;
    }
    return fd;
}

bool ipv6Loopback() {
    const int fd = ::socket(AF_INET6, SOCK_STREAM | SOCK_CLOEXEC, 0);
    if (fd < 0) {
        return false;
    }
    sockaddr_in6 a{};
    a.sin6_family = AF_INET6;
    a.sin6_addr = in6addr_loopback;
    const bool ok = ::bind(fd, reinterpret_cast<sockaddr*>(&a), sizeof a) == 0;
    ::close(fd);
    return ok;
}

StreamRequest rawBird() {
    StreamRequest r;
    r.profile.name = "test";
    r.profile.view = "bird";
    r.profile.width = 64;
    r.profile.height = 32;
    r.profile.fps = 0;
    r.payload = StreamPayload::Raw;
    return r;
}

// Handshake for raw frames on `fd`; returns the reply line and the first frame's decoded header
// sequence (0 when no whole header came within 3 s).
std::string rawFrameClient(int fd, std::uint64_t* sequence) {
    *sequence = 0;
    if (!sendAllRaw(fd, formatStreamRequest(rawBird()))) {
        return "send failed";
    }
    std::string got;
    const auto deadline = std::chrono::steady_clock::now() + 3s;
    while (std::chrono::steady_clock::now() < deadline) {
        const auto nl = got.find('\n');
        if (nl != std::string::npos && got.size() >= nl + 1 + kFrameHeaderBytes) {
            auto h = decodeFrameHeader(reinterpret_cast<const std::uint8_t*>(got.data()) + nl + 1, kFrameHeaderBytes);
            if (h) {
                *sequence = h.value().sequence;
            }
            return got.substr(0, nl);
        }
        const std::string more = readUntilClose(fd, 100ms);
        if (more.empty() && got.find('\n') != std::string::npos && got.find("\"ok\":false") < got.find('\n')) {
            break;
        }
        got += more;
    }
    const auto nl = got.find('\n');
    return nl == std::string::npos ? got : got.substr(0, nl);
}

class StreamPeerCapsTest : public ::testing::Test {
protected:
    void SetUp() override { m_fds_before = countOpenFds(); }
    void TearDown() override {
        for (const int fd : m_held) {
            ::close(fd);
        }
        m_server.reset();
        EXPECT_EQ(countOpenFds(), m_fds_before) << "descriptors leaked";
    }
    void start(FrameServerOptions o) {
        m_server = std::make_unique<FrameServer>(std::move(o));
        const auto st = m_server->start();
        ASSERT_TRUE(st.ok()) << st.message();
    }
    // `count` connections from `from` that say nothing (they hold their slots until the
    // handshake timeout); returns how many the server refused at once, with `refusal` the text.
    int hold(const std::string& from, const std::string& to, int port, int count, std::string* refusal) {
        int refused = 0;
        std::vector<int> fds;
        for (int i = 0; i < count; ++i) {
            const int fd = connectFrom(from, to, port);
            EXPECT_GE(fd, 0) << "connect from " << from;
            if (fd >= 0) {
                fds.push_back(fd);
            }
        }
        for (const int fd : fds) {
            // A refused connection gets its answer and the end of the stream at once.
            pollfd p{fd, POLLIN, 0};
            if (::poll(&p, 1, 100) > 0) {
                const std::string r = readUntilClose(fd, 1s);
                if (!r.empty()) {
                    ++refused;
                    *refusal = r;
                }
                ::close(fd);
                continue;
            }
            m_held.push_back(fd);
        }
        return refused;
    }

    int m_fds_before = 0;
    std::vector<int> m_held;
    std::unique_ptr<FrameServer> m_server;
};

}  // namespace

TEST_F(StreamPeerCapsTest, OneAddressCannotTakeEveryTcpSlot) {
    FrameServerOptions o;
    o.tcp_port = 0;
    o.handshake_timeout = 20s;  // the silent connections keep their slots for the whole test
    start(o);                   // library defaults: 32 TCP connections, 8 per address
    Publisher pub(*m_server, "bird", 64, 32, 60);
    std::string refusal;
    const int refused = hold("127.0.0.1", "127.0.0.1", m_server->tcpPort(), 32, &refusal);
    EXPECT_EQ(refused, 24);
    EXPECT_EQ(refusal, "{\"ok\":false,\"error\":\"too many tcp connections from 127.0.0.1 (limit 8)\"}\n");
    // Another host's client still gets its frames.
    const int fd = connectFrom("127.0.0.2", "127.0.0.1", m_server->tcpPort());
    ASSERT_GE(fd, 0);
    std::uint64_t seq = 0;
    const std::string reply = rawFrameClient(fd, &seq);
    ::close(fd);
    EXPECT_NE(reply.find("\"ok\":true"), std::string::npos) << reply;
    EXPECT_GT(seq, 0U) << reply;
    const auto s = m_server->stats();
    EXPECT_EQ(s.refused_address_full, 24U);
    EXPECT_EQ(s.refused_transport_full, 0U);
    EXPECT_NE(s.last_error.find("(127.0.0.1): refused: too many tcp connections from 127.0.0.1 (limit 8)"),
              std::string::npos)
        << s.last_error;
    EXPECT_NE(m_server->metricsText().find("navmap_stream_refusals_total{reason=\"address_full\"} 24\n"),
              std::string::npos);
    pub.stop();
}

TEST_F(StreamPeerCapsTest, OneAddressCannotTakeEveryHttpSlot) {
    FrameServerOptions o;
    o.http_port = 0;
    o.handshake_timeout = 20s;
    start(o);
    Publisher pub(*m_server, "bird", 64, 32, 30);
    const int port = m_server->httpPort();
    std::string refusal;
    EXPECT_EQ(hold("127.0.0.1", "127.0.0.1", port, 32, &refusal), 24);
    const std::string why = "too many http connections from 127.0.0.1 (limit 8)\n";
    EXPECT_EQ(refusal, "HTTP/1.0 503 Service Unavailable\r\nContent-Type: text/plain\r\nContent-Length: " +
                           std::to_string(why.size()) + "\r\nConnection: close\r\n\r\n" + why);
    // Another host gets the status page and an MJPEG stream.
    const int fd = connectFrom("127.0.0.2", "127.0.0.1", port);
    ASSERT_GE(fd, 0);
    ASSERT_TRUE(sendAllRaw(fd, "GET /status HTTP/1.1\r\nHost: 127.0.0.1:" + std::to_string(port) + "\r\n\r\n"));
    const std::string status = readUntilClose(fd, 3s);
    ::close(fd);
    EXPECT_EQ(status.rfind("HTTP/1.0 200 OK", 0), 0U) << status;
    EXPECT_NE(status.find("\"address_full\":24"), std::string::npos) << status;
    const int mj = connectFrom("127.0.0.3", "127.0.0.1", port);
    ASSERT_GE(mj, 0);
    ASSERT_TRUE(
        sendAllRaw(mj, "GET /stream.mjpg?profile=t&width=64&height=32&view=bird&fps=30 HTTP/1.1\r\nHost: 127.0.0.1:" +
                           std::to_string(port) + "\r\n\r\n"));
    std::string head;
    const auto deadline = std::chrono::steady_clock::now() + 3s;
    while (head.find("\xFF\xD8") == std::string::npos && std::chrono::steady_clock::now() < deadline) {
        pollfd p{mj, POLLIN, 0};
        if (::poll(&p, 1, 100) > 0) {
            char buf[4096];
            const ssize_t n = ::recv(mj, buf, sizeof buf, 0);
            if (n <= 0) {
                break;
            }
            head.append(buf, static_cast<std::size_t>(n));
        }
    }
    ::close(mj);
    EXPECT_EQ(head.rfind("HTTP/1.0 200 OK", 0), 0U) << head.substr(0, 200);
    EXPECT_NE(head.find("\xFF\xD8"), std::string::npos) << "no JPEG within 3 s";
    EXPECT_EQ(m_server->stats().refused_address_full, 24U);
    pub.stop();
}

TEST_F(StreamPeerCapsTest, Ipv6PeersCountPerPrefixAndIpv4PeersOnDualStackByAddress) {
    if (!ipv6Loopback()) {
        GTEST_SKIP() << "no IPv6 loopback (::1) on this machine";
    }
    FrameServerOptions o;
    o.tcp_port = 0;
    o.bind_address = "::";  // dual stack: IPv4 peers arrive as ::ffff:a.b.c.d
    o.max_clients_per_address = 2;
    o.handshake_timeout = 20s;
    start(o);
    const int port = m_server->tcpPort();
    std::string refusal;
    EXPECT_EQ(hold("::1", "::1", port, 3, &refusal), 1);
    EXPECT_EQ(refusal, "{\"ok\":false,\"error\":\"too many tcp connections from ::/64 (limit 2)\"}\n");
    EXPECT_EQ(hold("127.0.0.1", "127.0.0.1", port, 3, &refusal), 1);
    EXPECT_EQ(refusal, "{\"ok\":false,\"error\":\"too many tcp connections from 127.0.0.1 (limit 2)\"}\n");
    EXPECT_EQ(hold("127.0.0.2", "127.0.0.1", port, 2, &refusal), 0);
    EXPECT_EQ(m_server->stats().refused_address_full, 2U);
    EXPECT_EQ(m_server->stats().connections, 6U);
}
