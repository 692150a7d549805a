// SPDX-License-Identifier: Apache-2.0
// Status headers (kind 2, docs/frame-protocol.md "Frame header"): what a client gets while the
// daemon holds its frames back. FrameServer::publishStatus on the wire (exact bytes, only to the
// clients of that view and size without a frame yet, the first-frame timeout restarted by each),
// and StreamClient keeping the status and waiting on for the frame.

#include <gtest/gtest.h>
#include <poll.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <unistd.h>

#include <atomic>
#include <cstring>
#include <string>
#include <thread>
#include <vector>

#include "navmap/ipc/client/frame_header.h"
#include "navmap/ipc/client/stream_client.h"
#include "navmap/ipc/client/zlib_inflater.h"
#include "navmap/ipc/stream/frame_server.h"
#include "stream_test_util.h"
#include "wait_for.h"

using namespace navmap::ipc;
using namespace navmap::stream_test;
using namespace std::chrono_literals;

namespace {

StreamRequest request(StreamPayload payload, const std::string& view = "bird") {
    StreamRequest r;
    r.profile.name = "test";
    r.profile.width = 64;
    r.profile.height = 32;
    r.profile.view = view;
    r.profile.fps = 0;
    r.payload = payload;
    return r;
}

// Up to `n` bytes from `fd`; fewer when the peer closes or `timeout` passes.
std::string readBytes(int fd, std::size_t n, std::chrono::milliseconds timeout) {
    std::string out;
    const auto deadline = std::chrono::steady_clock::now() + timeout;
    while (out.size() < n) {
        const auto left =
            std::chrono::duration_cast<std::chrono::milliseconds>(deadline - std::chrono::steady_clock::now()).count();
        pollfd p{fd, POLLIN, 0};
        if (left <= 0 || poll(&p, 1, static_cast<int>(left)) <= 0) {
            break;
        }
        char buf[4096];
        const ssize_t got = recv(fd, buf, std::min(sizeof(buf), n - out.size()), 0);
        if (got <= 0) {
            break;
        }
        out.append(buf, static_cast<std::size_t>(got));
    }
    return out;
}

// The handshake reply line, read byte by byte so nothing after it is consumed.
std::string readReplyLine(int fd) {
    std::string line;
    while (line.empty() || line.back() != '\n') {
        const std::string b = readBytes(fd, 1, 3s);
        if (b.empty()) {
            break;
        }
        line += b;
    }
    return line;
}

// The next header on a raw socket, decoded; fails the test when none comes or it does not decode.
FrameHeader nextHeader(int fd) {
    const std::string bytes = readBytes(fd, kFrameHeaderBytes, 3s);
    EXPECT_EQ(bytes.size(), kFrameHeaderBytes) << "no header";
    if (bytes.size() != kFrameHeaderBytes) {
        return {};
    }
    auto h = decodeFrameHeader(reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size());
    EXPECT_TRUE(h.ok()) << h.error().message;
    return h.ok() ? h.value() : FrameHeader{};
}

std::string loading(int i) {
    return R"({"state":"loading","view":"bird","tiles_wanted":)" + std::to_string(12 - i) + R"(,"held_back":)" +
           std::to_string(3 * i) + R"(,"waited_ms":)" + std::to_string(100 * i) + "}";
}

class StreamStatusTest : public ::testing::Test {
protected:
    void SetUp() override {
        m_fds_before = countOpenFds();
        FrameServerOptions o;
        o.unix_path = uniqueSocketPath("stream-status");
        o.tcp_port = 0;
        o.stall_timeout = 2s;
        o.handshake_timeout = 300ms;  // short: statuses must keep the clients past several of these
        m_server = std::make_unique<FrameServer>(o);
        auto s = m_server->start();
        ASSERT_TRUE(s.ok()) << s.message();
    }
    void TearDown() override {
        m_server.reset();
        EXPECT_EQ(countOpenFds(), m_fds_before) << "descriptors leaked";
    }
    void publishSeq(std::uint64_t seq) {
        const auto px = sequencePattern(64, 32, seq);
        FrameView f;
        f.pixels = px.data();
        f.width = 64;
        f.height = 32;
        m_server->publish("bird", f);
    }
    template <typename Pred>
    bool waitFor(Pred pred, std::chrono::milliseconds limit = 3s) {
        return navmap::test::waitFor(pred, limit);
    }

    int m_fds_before = 0;
    std::unique_ptr<FrameServer> m_server;
};

}  // namespace

TEST_F(StreamStatusTest, StatusesReachWaitingClientsAsSentAndKeepThemPastTheFirstFrameTimeout) {
    // A raw TCP client and a shm client of bird 64x32, and a client of another view.
    const int tcp = connectTcpRaw(m_server->tcpPort());
    ASSERT_GE(tcp, 0);
    ASSERT_TRUE(sendAllRaw(tcp, formatStreamRequest(request(StreamPayload::Raw))));
    ASSERT_NE(readReplyLine(tcp).find("\"ok\":true"), std::string::npos);
    auto shm = rawShmHandshake(m_server->options().unix_path, formatStreamRequest(request(StreamPayload::Shm)));
    ASSERT_NE(shm->reply.find("\"ok\":true"), std::string::npos) << shm->reply;
    const int other = connectTcpRaw(m_server->tcpPort());
    ASSERT_TRUE(sendAllRaw(other, formatStreamRequest(request(StreamPayload::Raw, "hud"))));
    ASSERT_NE(readReplyLine(other).find("\"ok\":true"), std::string::npos);
    ASSERT_TRUE(waitFor([&] { return m_server->stats().clients == 3; }));

    // Ten statuses, 100 ms apart: 1 s, more than three first-frame timeouts.
    const auto t0 = std::chrono::steady_clock::now();
    constexpr int kStatuses = 10;
    for (int i = 0; i < kStatuses; ++i) {
        if (i > 0) {
            std::this_thread::sleep_for(100ms);
        }
        const std::string json = loading(i);
        ASSERT_TRUE(m_server->publishStatus("bird", 64, 32, json).ok());
        for (const int fd : {tcp, shm->fd}) {
            const FrameHeader h = nextHeader(fd);
            ASSERT_EQ(h.kind, FrameKind::Status) << "status " << i;
            ASSERT_EQ(h.payload_bytes, json.size());
            EXPECT_EQ(readBytes(fd, h.payload_bytes, 3s), json) << "status " << i;
        }
    }
    EXPECT_GE(std::chrono::steady_clock::now() - t0, 900ms);
    // Both are still there; the client of the other view got no status and was dropped on time.
    EXPECT_TRUE(waitFor([&] { return m_server->stats().statuses_sent == 2U * kStatuses; }))
        << m_server->stats().statuses_sent;  // counted just after the bytes went out
    auto s = m_server->stats();
    EXPECT_EQ(s.first_frame_timeouts, 1U);
    EXPECT_EQ(s.clients, 2U);
    const std::string other_got = readUntilClose(other, 3s);
    close(other);
    ASSERT_GE(other_got.size(), kFrameHeaderBytes);
    auto oh = decodeFrameHeader(reinterpret_cast<const std::uint8_t*>(other_got.data()), other_got.size());
    ASSERT_TRUE(oh.ok()) << oh.error().message;
    EXPECT_EQ(oh.value().kind, FrameKind::Error);
    EXPECT_EQ(other_got.substr(kFrameHeaderBytes),
              "disconnected, no frame within 300 ms of the handshake (nothing published for hud 64x32)");

    // Then the frame, on both transports.
    publishSeq(1);
    const FrameHeader raw = nextHeader(tcp);
    EXPECT_EQ(raw.kind, FrameKind::Frame);
    EXPECT_EQ(raw.encoding, FrameEncoding::Raw);
    EXPECT_EQ(raw.sequence, 1U);
    const std::string pixels = readBytes(tcp, raw.payload_bytes, 3s);
    const auto want = sequencePattern(64, 32, 1);
    ASSERT_EQ(pixels.size(), want.size());
    EXPECT_EQ(0, std::memcmp(pixels.data(), want.data(), want.size()));
    const FrameHeader note = nextHeader(shm->fd);
    EXPECT_EQ(note.kind, FrameKind::Frame);
    EXPECT_EQ(note.encoding, FrameEncoding::Shm);
    EXPECT_EQ(note.sequence, 1U);
    ASSERT_TRUE(sendAllRaw(shm->fd, "A"));

    // A status after the first frame goes to nobody: the next thing on the wire is frame 2.
    ASSERT_TRUE(m_server->publishStatus("bird", 64, 32, loading(99)).ok());
    std::this_thread::sleep_for(50ms);
    publishSeq(2);
    for (const int fd : {tcp, shm->fd}) {
        const FrameHeader h = nextHeader(fd);
        EXPECT_EQ(h.kind, FrameKind::Frame);
        EXPECT_EQ(h.sequence, 2U);
    }
    EXPECT_EQ(m_server->stats().statuses_sent, 2U * kStatuses);
    close(tcp);
}

TEST_F(StreamStatusTest, WithoutStatusesTheSameClientIsDroppedAfterTheTimeout) {
    // The control for the test above: no statuses, no frame, and the client is gone.
    const int tcp = connectTcpRaw(m_server->tcpPort());
    ASSERT_TRUE(sendAllRaw(tcp, formatStreamRequest(request(StreamPayload::Raw))));
    ASSERT_NE(readReplyLine(tcp).find("\"ok\":true"), std::string::npos);
    const FrameHeader h = nextHeader(tcp);
    EXPECT_EQ(h.kind, FrameKind::Error);
    EXPECT_EQ(readBytes(tcp, h.payload_bytes, 3s),
              "disconnected, no frame within 300 ms of the handshake (nothing published for bird 64x32)");
    close(tcp);
    EXPECT_EQ(m_server->stats().first_frame_timeouts, 1U);
}

TEST_F(StreamStatusTest, PublishStatusRefusesWhatIsNoUtf8JsonObjectAndSendsNothing) {
    const int tcp = connectTcpRaw(m_server->tcpPort());
    ASSERT_TRUE(sendAllRaw(tcp, formatStreamRequest(request(StreamPayload::Raw))));
    ASSERT_NE(readReplyLine(tcp).find("\"ok\":true"), std::string::npos);
    ASSERT_TRUE(waitFor([&] { return m_server->stats().clients == 1; }));
    const auto why = [&](std::string json, int width = 64) {
        const auto s = m_server->publishStatus("bird", width, 32, std::move(json));
        return s.ok() ? std::string("accepted") : s.message();
    };
    EXPECT_EQ(why("{\"state\":\"\xff\"}"), "publishStatus(bird): status: not UTF-8 (byte 0xff at offset 10)");
    EXPECT_EQ(why("[1,2]"), "publishStatus(bird): status: not a JSON object");
    EXPECT_EQ(why("{\"state\":"), "publishStatus(bird): status: not a JSON object");
    EXPECT_EQ(why("{\"pad\":\"" + std::string(kMaxStatusPayloadBytes, 'x') + "\"}"),
              "publishStatus(bird): status: 65546 bytes (limit 65536)");
    EXPECT_EQ(why("{}", 0), "publishStatus(bird): bad size 0x32");
    std::this_thread::sleep_for(100ms);
    EXPECT_EQ(m_server->stats().statuses_sent, 0U);
    EXPECT_EQ(readBytes(tcp, 1, 50ms), "");  // nothing on the wire
    close(tcp);
}

TEST_F(StreamStatusTest, StreamClientKeepsTheStatusAndStillGetsTheFrame) {
    auto shm = StreamClient::connectUnix(m_server->options().unix_path, request(StreamPayload::Shm));
    ASSERT_TRUE(shm.ok()) << shm.error().message;
    auto zlib = StreamClient::connectTcp("127.0.0.1", m_server->tcpPort(), request(StreamPayload::Zlib),
                                         std::chrono::seconds(5), zlibInflater());
    ASSERT_TRUE(zlib.ok()) << zlib.error().message;
    ASSERT_TRUE(waitFor([&] { return m_server->stats().clients == 2; }));
    std::vector<std::string> seen;
    shm.value()->setStatusHandler([&](const std::string& text) { seen.push_back(text); });

    // A status alone: next() reports no frame (timeout), the status is kept and was handed over.
    // (Short waits: the first-frame timeout is 300 ms from this status.)
    ASSERT_TRUE(m_server->publishStatus("bird", 64, 32, loading(1)).ok());
    ASSERT_TRUE(waitFor([&] { return m_server->stats().statuses_sent == 2; }));
    for (auto* c : {shm.value().get(), zlib.value().get()}) {
        ReceivedFrame f;
        auto r = c->next(f, 50ms);
        ASSERT_TRUE(r.ok()) << r.error().message;
        EXPECT_FALSE(r.value());
        EXPECT_EQ(c->lastStatus(), loading(1));
        EXPECT_EQ(c->stats().statuses, 1U);
        EXPECT_EQ(c->stats().frames, 0U);
    }
    ASSERT_EQ(seen.size(), 1U);
    EXPECT_EQ(seen[0], loading(1));

    // A status, then a frame: one next() reads past the status and returns the frame.
    ASSERT_TRUE(m_server->publishStatus("bird", 64, 32, loading(2)).ok());
    ASSERT_TRUE(waitFor([&] { return m_server->stats().statuses_sent == 4; }));
    publishSeq(1);
    for (auto* c : {shm.value().get(), zlib.value().get()}) {
        ReceivedFrame f;
        auto r = c->next(f, 3s);
        ASSERT_TRUE(r.ok()) << r.error().message;
        ASSERT_TRUE(r.value()) << "no frame after the status";
        EXPECT_EQ(f.header.sequence, 1U);
        const auto want = sequencePattern(64, 32, 1);
        ASSERT_EQ(f.pixels.size(), want.size());
        EXPECT_EQ(0, std::memcmp(f.pixels.data(), want.data(), want.size()));
        EXPECT_EQ(c->lastStatus(), loading(2));
        EXPECT_EQ(c->stats().statuses, 2U);
    }
    EXPECT_EQ(seen.size(), 2U);
}

namespace {

// A one-connection server on a Unix socket that grants a raw stream, then sends `after`.
class FakeServer {
public:
    explicit FakeServer(std::string after) : m_path(uniqueSocketPath("fake-status")) {
        ::unlink(m_path.c_str());
        m_listen = socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0);
        sockaddr_un a{};
        a.sun_family = AF_UNIX;
        std::strncpy(a.sun_path, m_path.c_str(), sizeof(a.sun_path) - 1);
        if (bind(m_listen, reinterpret_cast<sockaddr*>(&a), sizeof(a)) != 0 || listen(m_listen, 1) != 0) {
            ADD_FAILURE() << "bind/listen " << m_path << ": " << std::strerror(errno);
        }
        m_thread = std::thread([this, after = std::move(after)] {
            const int c = accept4(m_listen, nullptr, nullptr, SOCK_CLOEXEC);
            if (c < 0) {
                return;
            }
            readReplyLine(c);  // the client's request line
            sendAllRaw(c, R"({"ok":true,"version":1,"profile":{"name":"test","width":64,"height":32,"fps":0,)"
                          R"("view":"bird","format":"rgba8"},"payload":"raw","stride":256,"header_bytes":80})"
                          "\n" +
                              after);
            readUntilClose(c, 3s);
            close(c);
        });
    }
    ~FakeServer() {
        m_thread.join();
        close(m_listen);
        ::unlink(m_path.c_str());
    }
    const std::string& path() const { return m_path; }

private:
    std::string m_path;
    int m_listen = -1;
    std::thread m_thread;
};

std::string statusBytes(const std::string& text, std::uint32_t declared) {
    FrameHeader h;
    h.kind = FrameKind::Status;
    h.payload_bytes = declared;
    const auto hb = encodeFrameHeader(h);
    return std::string(hb.begin(), hb.end()) + text;
}

}  // namespace

TEST(StreamClientStatus, ABrokenStatusIsAProtocolErrorNamingTheProblem) {
    const int fds = countOpenFds();
    const std::string bad_utf8 = "{\"state\":\"\xc3(\"}";
    const std::pair<std::string, std::string> cases[] = {
        {statusBytes(bad_utf8, static_cast<std::uint32_t>(bad_utf8.size())),
         ": status: not UTF-8 (byte 0xc3 at offset 10)"},
        {statusBytes("{}", kMaxStatusPayloadBytes + 1), ": frame header: status of 65537 bytes (limit 65536)"},
    };
    for (const auto& [wire, why] : cases) {
        FakeServer server(wire);
        auto c = StreamClient::connectUnix(server.path(), request(StreamPayload::Raw));
        ASSERT_TRUE(c.ok()) << c.error().message;
        ReceivedFrame f;
        auto r = c.value()->next(f, 3s);
        ASSERT_FALSE(r.ok()) << why;
        EXPECT_EQ(r.error().message, server.path() + why);
        EXPECT_EQ(c.value()->lastStatus(), "");
        EXPECT_EQ(c.value()->stats().statuses, 0U);
    }
    EXPECT_EQ(countOpenFds(), fds);
}
