// SPDX-License-Identifier: Apache-2.0
// Payload dmabuf (docs/frame-protocol.md "dma-buf frames"): a server that cannot export dma-bufs
// refuses the request naming why and the fallback; a client that allows the fallback gets shm
// frames on a second connection and says so, in C++ and in the C API.

#include <gtest/gtest.h>
#include <unistd.h>

#include <memory>
#include <string>
#include <thread>

#include "navmap/ipc/client/reconnecting_client.h"
#include "navmap/ipc/client/stream_client.h"
#include "navmap/ipc/stream/frame_server.h"
#include "navmap_client.h"
#include "stream_test_util.h"
#include "wait_for.h"

using namespace navmap::ipc;
using namespace navmap::stream_test;
using namespace std::chrono_literals;

namespace {

constexpr const char* kReason = "llvmpipe on the surfaceless platform: no EGL_MESA_image_dma_buf_export";

StreamRequest dmabufRequest(bool fallback) {
    StreamRequest r;
    r.profile.name = "test";
    r.profile.width = 64;
    r.profile.height = 32;
    r.profile.view = "bird";
    r.profile.fps = 240;
    r.payload = StreamPayload::Dmabuf;
    r.hold = true;
    r.dmabuf_fallback_shm = fallback;
    return r;
}

// Every pixel is (n, 0, 0, 255) for one n in 1..last: a whole frame of publish(n).
::testing::AssertionResult samePixels(const std::uint8_t* px, std::size_t count, std::uint64_t last) {
    const std::uint8_t n = px[0];
    if (n < 1 || n > last) return ::testing::AssertionFailure() << "first pixel " << int(n) << " not in 1.." << last;
    for (std::size_t i = 0; i < count; ++i) {
        if (px[4 * i] != n || px[4 * i + 1] != 0 || px[4 * i + 2] != 0 || px[4 * i + 3] != 255) {
            return ::testing::AssertionFailure() << "pixel " << i << " differs from frame " << int(n);
        }
    }
    return ::testing::AssertionSuccess();
}

class StreamDmabufTest : public ::testing::Test {
protected:
    void SetUp() override {
        FrameServerOptions o;
        o.unix_path = uniqueSocketPath("dmabuf-test");
        o.tcp_port = 0;
        o.handshake_timeout = 2s;
        o.dmabuf_unavailable_reason = [] { return std::string(kReason); };
        m_server = std::make_unique<FrameServer>(o);
        auto s = m_server->start();
        ASSERT_TRUE(s.ok()) << s.message();
        m_path = o.unix_path;
    }
    void publish(std::uint64_t seq) {
        m_last = seq;
        const auto px = sequencePattern(64, 32, seq);
        FrameView f;
        f.pixels = px.data();
        f.width = 64;
        f.height = 32;
        m_server->publish("bird", f);
    }
    std::unique_ptr<FrameServer> m_server;
    std::string m_path;
    std::uint64_t m_last = 0;  ///< the newest number published
};

TEST(StreamDmabufWire, RequestRoundTripsAndHoldIsAllowed) {
    auto r = parseStreamRequest(R"({"version":1,"profile":"hud","payload":"dmabuf","hold":true})");
    ASSERT_TRUE(r.ok()) << r.error().message;
    EXPECT_EQ(r.value().payload, StreamPayload::Dmabuf);
    EXPECT_TRUE(r.value().hold);
    const std::string line = formatStreamRequest(dmabufRequest(true));
    EXPECT_NE(line.find(R"("payload":"dmabuf")"), std::string::npos) << line;
    EXPECT_EQ(line.find("fallback"), std::string::npos) << "the fallback is the client's, never sent: " << line;
    EXPECT_EQ(std::string(streamPayloadName(StreamPayload::Dmabuf)), "dmabuf");
}

TEST(StreamDmabufWire, AnAcceptingReplyIsAnErrorThisLibraryNames) {
    const auto reply =
        parseStreamReply(R"({"ok":true,"version":1,"payload":"dmabuf","stride":256,"header_bytes":80,"dmabuf":1})",
                         dmabufRequest(false));
    ASSERT_FALSE(reply.ok());
    EXPECT_EQ(reply.error().message,
              "reply: payload dmabuf accepted, but this client library cannot import dma-buf frames yet");
}

TEST_F(StreamDmabufTest, TheServerRefusesNamingTheReasonAndTheFallback) {
    auto raw = rawShmHandshake(m_path, formatStreamRequest(dmabufRequest(false)));
    ASSERT_NE(raw, nullptr);
    EXPECT_EQ(raw->reply, std::string(R"({"ok":false,"error":"handshake: dmabuf frames are not available here ()") +
                              kReason + R"(); ask for shm"})");
    EXPECT_EQ(raw->ring_fd, -1) << "no ring for a refused request";
    EXPECT_EQ(m_server->stats().handshake_errors, 1U);
}

TEST_F(StreamDmabufTest, WithoutFallbackTheClientReportsTheRefusal) {
    auto c = StreamClient::connectUnix(m_path, dmabufRequest(false), 2s);
    ASSERT_FALSE(c.ok());
    EXPECT_EQ(c.error().message, "handshake refused by " + m_path +
                                     ": handshake: dmabuf frames are not available here (" + kReason +
                                     "); ask for shm");
}

TEST_F(StreamDmabufTest, TheClientFallsBackToShmAndGetsFrames) {
    auto c = StreamClient::connectUnix(m_path, dmabufRequest(true), 2s);
    ASSERT_TRUE(c.ok()) << c.error().message;
    StreamClient& client = *c.value();
    EXPECT_EQ(client.payload(), StreamPayload::Shm);
    EXPECT_EQ(client.fallbackReason(), "handshake refused by " + m_path +
                                           ": handshake: dmabuf frames are not available here (" + kReason +
                                           "); ask for shm");
    HeldFrame f;
    bool got = false;
    for (std::uint64_t seq = 1; seq < 200 && !got; ++seq) {
        publish(seq);
        auto r = client.nextHeld(f, 20ms);
        ASSERT_TRUE(r.ok()) << r.error().message;
        got = r.value();
    }
    ASSERT_TRUE(got);
    EXPECT_EQ(f.header.encoding, FrameEncoding::Shm);
    EXPECT_EQ(f.header.width, 64U);
    // A whole published frame: every pixel the published number's bytes (sequencePattern).
    EXPECT_TRUE(samePixels(f.pixels, 64 * 32, m_last));
    ASSERT_TRUE(client.release().ok());
}

TEST_F(StreamDmabufTest, ShmStaysQuietAndTcpRefusesDmabuf) {
    // A plain shm client has no fallback to report.
    StreamRequest shm = dmabufRequest(false);
    shm.payload = StreamPayload::Shm;
    auto c = StreamClient::connectUnix(m_path, shm, 2s);
    ASSERT_TRUE(c.ok()) << c.error().message;
    EXPECT_EQ(c.value()->fallbackReason(), "");
    // The library refuses dmabuf over TCP before connecting; the server would too.
    auto t = StreamClient::connectTcp("127.0.0.1", m_server->tcpPort(), dmabufRequest(true), 2s);
    ASSERT_FALSE(t.ok());
    EXPECT_EQ(t.error().message,
              "connect(127.0.0.1:" + std::to_string(m_server->tcpPort()) + "): payload dmabuf needs the Unix socket");
    const int fd = connectTcpRaw(m_server->tcpPort());
    ASSERT_GE(fd, 0);
    StreamRequest r = dmabufRequest(false);
    r.hold = false;
    ASSERT_TRUE(sendAllRaw(fd, formatStreamRequest(r)));
    const std::string answer = readUntilClose(fd, 2s);
    ::close(fd);
    EXPECT_NE(answer.find(R"(handshake: payload \"dmabuf\" needs the Unix socket)"), std::string::npos) << answer;
}

TEST_F(StreamDmabufTest, TheCApiFallsBackAndReportsThePayload) {
    navmap_client_options o;
    navmap_client_options_init(&o);
    o.socket_path = m_path.c_str();
    o.profile = "test";
    o.width = 64;
    o.height = 32;
    o.view = "bird";
    o.fps = 240;
    navmap_client* c = navmap_client_create(&o, nullptr);
    ASSERT_NE(c, nullptr);
    EXPECT_STREQ(navmap_client_payload(c), "");  // not connected yet
    ASSERT_EQ(navmap_client_request_dmabuf(c), 0);
    navmap_frame f;
    bool got = false;
    for (std::uint64_t seq = 1; seq < 200 && !got; ++seq) {
        publish(seq);
        got = navmap_client_next_frame(c, 20, &f) == NAVMAP_CLIENT_FRAME;
    }
    ASSERT_TRUE(got) << navmap_client_last_error(c);
    EXPECT_EQ(f.width, 64U);
    EXPECT_TRUE(samePixels(f.pixels, 64 * 32, m_last));
    EXPECT_STREQ(navmap_client_payload(c), "shm");
    EXPECT_EQ(std::string(navmap_client_payload_fallback(c)),
              "handshake refused by " + m_path + ": handshake: dmabuf frames are not available here (" + kReason +
                  "); ask for shm");
    EXPECT_EQ(navmap_client_request_dmabuf(c), NAVMAP_CLIENT_ERROR);  // connected: too late
    EXPECT_EQ(navmap_client_release_frame(c, &f), NAVMAP_CLIENT_FRAME);
    navmap_client_destroy(c);
    EXPECT_EQ(navmap_client_request_dmabuf(nullptr), NAVMAP_CLIENT_ERROR);
    EXPECT_STREQ(navmap_client_payload(nullptr), "");
    EXPECT_STREQ(navmap_client_payload_fallback(nullptr), "");
}

}  // namespace
