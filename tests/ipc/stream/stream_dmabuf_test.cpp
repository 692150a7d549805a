// SPDX-License-Identifier: Apache-2.0
// Payload dmabuf (docs/frame-protocol.md "dma-buf frames"): a server that cannot export dma-bufs
// refuses the request naming why and the fallback; a client that allows the fallback gets shm
// frames on a second connection and says so, in C++ and in the C API. A server that exports
// passes each buffer's fd once per client and allocation, holds a buffer from its notification to
// the client's ack, and the client reads the frame through the buffer (here memfds stand in for
// the GPU's buffers: the protocol does not care; tests/render/run_dmabuf_guest's end-to-end test
// uses real ones).

#include <gtest/gtest.h>
#include <sys/eventfd.h>
#include <sys/mman.h>
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
using navmap::test::waitFor;

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

// The C API's client of the test profile (64x32 bird) on `path`.
navmap_client* cClient(const std::string& path) {
    navmap_client_options o;
    navmap_client_options_init(&o);
    o.socket_path = path.c_str();
    o.profile = "test";
    o.width = 64;
    o.height = 32;
    o.view = "bird";
    o.fps = 240;
    return navmap_client_create(&o, nullptr);
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

TEST(StreamDmabufWire, TheReplyNamesTheBlockVersion) {
    const std::string head = R"({"ok":true,"version":1,"payload":"dmabuf","hold":true,"stride":256,"header_bytes":80)";
    EXPECT_TRUE(parseStreamReply(head + R"(,"dmabuf":1})", dmabufRequest(false)).ok());
    auto r = parseStreamReply(head + "}", dmabufRequest(false));
    ASSERT_FALSE(r.ok());
    EXPECT_EQ(r.error().message, "reply: \"dmabuf\" must be 1 (the dma-buf block version this client reads)");
    r = parseStreamReply(head + R"(,"dmabuf":2})", dmabufRequest(false));
    ASSERT_FALSE(r.ok());
    StreamRequest shm = dmabufRequest(false);
    shm.payload = StreamPayload::Shm;
    r = parseStreamReply(
        R"({"ok":true,"version":1,"payload":"shm","hold":true,"stride":256,"header_bytes":80,"dmabuf":1})", shm);
    ASSERT_FALSE(r.ok());
    EXPECT_EQ(r.error().message, "reply: \"dmabuf\" without asking for payload dmabuf");
}

TEST(StreamDmabufWire, TheBlockRoundTripsAndBadOnesAreNamed) {
    DmabufBlock b;
    b.flags = kDmabufBufferFd | kDmabufFenceFd;
    b.fourcc = 0x34324241;
    b.modifier = 0x0100000000000002ULL;
    b.stride = 320;
    b.offset = 64;
    b.width = 64;
    b.height = 32;
    auto bytes = encodeDmabufBlock(b);
    EXPECT_EQ(std::string(bytes.begin(), bytes.begin() + 4), "NMDB");
    auto d = decodeDmabufBlock(bytes.data(), bytes.size());
    ASSERT_TRUE(d.ok()) << d.error().message;
    EXPECT_EQ(d.value().modifier, b.modifier);
    EXPECT_EQ(d.value().stride, 320U);
    EXPECT_EQ(d.value().flags, b.flags);
    const auto broken = [&](std::size_t at, std::uint8_t v) {
        auto copy = bytes;
        copy[at] = v;
        auto r = decodeDmabufBlock(copy.data(), copy.size());
        return r.ok() ? std::string("ok") : r.error().message;
    };
    EXPECT_EQ(broken(0, 'X'), "dma-buf block: bad magic (expected \"NMDB\")");
    EXPECT_EQ(broken(4, 2), "dma-buf block: version 2 (this client reads version 1)");
    EXPECT_EQ(broken(6, 4), "dma-buf block: unknown flags 0x4");
    EXPECT_EQ(broken(12, 2), "dma-buf block: 2 planes (version 1 has one)");
    EXPECT_EQ(broken(25, 0), "dma-buf block: stride 64 for width 64");
    EXPECT_EQ(broken(47, 1), "dma-buf block: reserved bytes 40..47 not 0");
    EXPECT_FALSE(decodeDmabufBlock(bytes.data(), 47).ok());
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
    navmap_client* c = cClient(m_path);
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

// A stand-in for an exported buffer: a memfd of stride x height with every pixel (n, 0, 0, 255)
// and the padding after each row 0xEE.
struct FakeBuffer {
    FakeBuffer(int width, int height, std::uint32_t stride_bytes, std::uint8_t n) : stride(stride_bytes) {
        fd = ::memfd_create("navmap-test-dmabuf", MFD_CLOEXEC);
        std::vector<std::uint8_t> bytes(std::size_t{stride} * height, 0xEE);
        for (int y = 0; y < height; ++y) {
            for (int x = 0; x < width; ++x) {
                std::uint8_t* p = &bytes[y * stride + x * 4];
                p[0] = n, p[1] = 0, p[2] = 0, p[3] = 255;
            }
        }
        EXPECT_EQ(::write(fd, bytes.data(), bytes.size()), static_cast<ssize_t>(bytes.size()));
    }
    ~FakeBuffer() { ::close(fd); }
    int fd = -1;
    std::uint32_t stride;
};

class StreamDmabufFramesTest : public ::testing::Test {
protected:
    void SetUp() override {
        FrameServerOptions o;
        o.unix_path = uniqueSocketPath("dmabuf-frames");
        o.handshake_timeout = 2s;
        o.dmabuf_unavailable_reason = [] { return std::string(); };  // exports
        m_server = std::make_unique<FrameServer>(o);
        auto s = m_server->start();
        ASSERT_TRUE(s.ok()) << s.message();
        m_path = o.unix_path;
    }
    // Buffer `index` (allocation `generation`) holds the newest frame.
    std::size_t publish(const FakeBuffer& b, int index, std::uint64_t generation, int fence = -1) {
        DmabufBuffer d;
        d.index = index;
        d.generation = generation;
        d.fd = b.fd;
        d.layout.fourcc = 0x34324241;
        d.layout.stride = b.stride;
        d.layout.width = 64;
        d.layout.height = 32;
        d.fence_fd = fence;
        FrameView info;
        info.width = 64;
        info.height = 32;
        return m_server->publishDmabuf("bird", info, d);
    }
    std::unique_ptr<StreamClient> connect(bool hold = true) {
        StreamRequest r = dmabufRequest(false);
        r.hold = hold;
        auto c = StreamClient::connectUnix(m_path, r, 2s);
        EXPECT_TRUE(c.ok()) << c.error().message;
        if (!c.ok()) return nullptr;
        EXPECT_TRUE(waitFor([&] {
            const auto a = m_server->activeProfiles();
            return !a.empty() && a[0].dmabuf_clients >= 1;
        }));
        return std::move(c.value());
    }
    std::unique_ptr<FrameServer> m_server;
    std::string m_path;
};

TEST_F(StreamDmabufFramesTest, TheBufferFdComesOnceAndThePixelsAreThere) {
    auto client = connect();
    ASSERT_NE(client, nullptr);
    EXPECT_EQ(client->payload(), StreamPayload::Dmabuf);
    const FakeBuffer a(64, 32, 320, 7), b(64, 32, 320, 9);
    DmabufFrameRef f;
    std::uint64_t seen = 0;
    for (const auto& [buffer, index, want_new] :
         {std::tuple{&a, 0, true}, std::tuple{&b, 1, true}, std::tuple{&a, 0, false}}) {
        ASSERT_EQ(publish(*buffer, index, 1), 1U);
        auto r = client->nextDmabuf(f, 2s);
        ASSERT_TRUE(r.ok()) << r.error().message;
        ASSERT_TRUE(r.value());
        EXPECT_GT(f.header.sequence, seen);
        seen = f.header.sequence;
        EXPECT_EQ(f.header.encoding, FrameEncoding::Dmabuf);
        EXPECT_EQ(f.header.slot, static_cast<std::uint32_t>(index));
        EXPECT_EQ(f.new_buffer, want_new) << "buffer " << index;
        EXPECT_EQ(f.block.stride, 320U);
        EXPECT_EQ(f.block.fourcc, 0x34324241U);
        // The client's fd is the same buffer: its bytes are the frame's.
        void* map = ::mmap(nullptr, 320 * 32, PROT_READ, MAP_SHARED, f.fd, 0);
        ASSERT_NE(map, MAP_FAILED);
        EXPECT_EQ(static_cast<const std::uint8_t*>(map)[0], index == 0 ? 7 : 9);
        ::munmap(map, 320 * 32);
        ASSERT_TRUE(client->release().ok());
    }
    EXPECT_EQ(client->stats().dmabuf_fds, 2U) << "one fd per buffer, not per frame";
    EXPECT_EQ(client->stats().cpu_copies, 0U);
    EXPECT_TRUE(waitFor([&] { return m_server->stats().dmabuf_frames_sent == 3; }));
    EXPECT_EQ(m_server->stats().dmabuf_fds_sent, 2U);
    EXPECT_EQ(m_server->stats().dmabuf_clients, 1U);
    // A new allocation of buffer 0: its fd comes again.
    const FakeBuffer c(64, 32, 320, 11);
    ASSERT_EQ(publish(c, 0, 2), 1U);
    auto r = client->nextDmabuf(f, 2s);
    ASSERT_TRUE(r.ok() && r.value());
    EXPECT_TRUE(f.new_buffer);
    EXPECT_EQ(client->stats().dmabuf_fds, 3U);
}

TEST_F(StreamDmabufFramesTest, AHeldBufferStaysBusyUntilTheAck) {
    auto client = connect();
    ASSERT_NE(client, nullptr);
    const FakeBuffer a(64, 32, 256, 1), b(64, 32, 256, 2);
    EXPECT_EQ(m_server->dmabufBusy("bird"), 0U);
    ASSERT_EQ(publish(a, 0, 1), 1U);
    EXPECT_EQ(m_server->dmabufBusy("bird"), 1U) << "the newest frame's buffer";
    DmabufFrameRef f;
    auto r = client->nextDmabuf(f, 2s);
    ASSERT_TRUE(r.ok() && r.value());
    ASSERT_EQ(publish(b, 1, 1), 1U);
    EXPECT_EQ(m_server->dmabufBusy("bird"), 3U) << "buffer 0 held by the client, buffer 1 the newest";
    ASSERT_TRUE(client->release().ok());
    EXPECT_TRUE(waitFor([&] { return m_server->dmabufBusy("bird") == 2U; })) << m_server->dmabufBusy("bird");
    // The client gone: nothing of it is held.
    r = client->nextDmabuf(f, 2s);
    ASSERT_TRUE(r.ok() && r.value());
    EXPECT_EQ(f.header.slot, 1U);
    ASSERT_EQ(publish(a, 0, 1), 1U);
    client.reset();
    EXPECT_TRUE(waitFor([&] { return m_server->stats().dmabuf_clients == 0; }));
    EXPECT_TRUE(m_server->activeProfiles().empty());
}

TEST_F(StreamDmabufFramesTest, NextCopiesOutOfTheBufferAndWaitsForTheFence) {
    auto client = connect(false);
    ASSERT_NE(client, nullptr);
    const FakeBuffer a(64, 32, 320, 5);
    const int fence = ::eventfd(1, EFD_CLOEXEC);  // signalled: readable
    ASSERT_GE(fence, 0);
    ASSERT_EQ(publish(a, 2, 1, fence), 1U);
    ReceivedFrame f;
    auto r = client->next(f, 2s);
    ASSERT_TRUE(r.ok()) << r.error().message;
    ASSERT_TRUE(r.value());
    EXPECT_EQ(f.header.stride, 256U) << "a copy has the profile's rows, not the buffer's";
    EXPECT_TRUE(samePixels(f.pixels.data(), 64 * 32, 5));
    EXPECT_EQ(client->stats().cpu_copies, 1U);
    // A fence that never signals: the client says so instead of reading a half-drawn frame.
    const int unsignalled = ::eventfd(0, EFD_CLOEXEC);
    ASSERT_EQ(publish(a, 2, 1, unsignalled), 1U);
    r = client->next(f, 100ms);
    ASSERT_FALSE(r.ok());
    EXPECT_NE(r.error().message.find("its fence did not signal in time"), std::string::npos) << r.error().message;
}

TEST_F(StreamDmabufFramesTest, TheCApiMapsTheBufferAndNamesIt) {
    navmap_client* c = cClient(m_path);
    ASSERT_NE(c, nullptr);
    ASSERT_EQ(navmap_client_request_dmabuf(c), 0);
    const FakeBuffer a(64, 32, 320, 3);
    navmap_frame f;
    bool got = false;
    for (int i = 0; i < 200 && !got; ++i) {
        publish(a, 0, 1);
        got = navmap_client_next_frame(c, 20, &f) == NAVMAP_CLIENT_FRAME;
    }
    ASSERT_TRUE(got) << navmap_client_last_error(c);
    EXPECT_STREQ(navmap_client_payload(c), "dmabuf");
    EXPECT_EQ(f.stride, 320U) << "the pixels lie in the mapped buffer, with its stride";
    for (std::uint32_t y = 0; y < 32; ++y) EXPECT_TRUE(samePixels(f.pixels + y * f.stride, 64, 3)) << y;
    navmap_dmabuf d;
    ASSERT_EQ(navmap_client_frame_dmabuf(c, &f, &d), NAVMAP_CLIENT_FRAME);
    EXPECT_GE(d.fd, 0);
    EXPECT_EQ(d.fourcc, 0x34324241U);
    EXPECT_EQ(d.stride, 320U);
    EXPECT_EQ(d.buffer, 0U);
    EXPECT_EQ(navmap_client_release_frame(c, &f), NAVMAP_CLIENT_FRAME);
    EXPECT_EQ(navmap_client_frame_dmabuf(c, &f, &d), NAVMAP_CLIENT_ERROR) << "released";
    navmap_client_destroy(c);
}

TEST_F(StreamDmabufFramesTest, OtherFormatsAreRefused) {
    StreamRequest r = dmabufRequest(false);
    r.profile.format = PixelFormat::Rgb565;
    auto c = StreamClient::connectUnix(m_path, r, 2s);
    ASSERT_FALSE(c.ok());
    EXPECT_NE(c.error().message.find("dmabuf frames are rgba8 (DRM_FORMAT_ABGR8888); ask for format rgba8"),
              std::string::npos)
        << c.error().message;
}

}  // namespace
