// SPDX-License-Identifier: Apache-2.0
// FrameServer + StreamClient over real sockets in one process: shm ring, TCP raw/zlib, HTTP
// (MJPEG, /status, /metrics), slow and stalled clients, malformed input, fd and memory stability.

#include <gtest/gtest.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <thread>

#include "navmap/ipc/client/frame_header.h"
#include "navmap/ipc/client/stream_client.h"
#include "navmap/ipc/client/zlib_inflater.h"
#include "navmap/ipc/stream/frame_server.h"
#include "navmap/ipc/stream/frame_server_stats_json.h"
#include "stream_test_util.h"
#include "wait_for.h"

using namespace navmap::ipc;
using namespace navmap::stream_test;
using namespace std::chrono_literals;

namespace {

StreamRequest small(StreamPayload payload, int fps = 240, PixelFormat format = PixelFormat::Rgba8) {
    StreamRequest r;
    r.profile.name = "test";
    r.profile.width = 64;
    r.profile.height = 32;
    r.profile.view = "bird";
    r.profile.fps = fps;
    r.profile.format = format;
    r.payload = payload;
    return r;
}

class StreamServerTest : public ::testing::Test {
protected:
    void SetUp() override {
        m_fds_before = countOpenFds();
        FrameServerOptions o;
        o.unix_path = uniqueSocketPath("stream-test");
        o.tcp_port = 0;
        o.http_port = 0;
        o.stall_timeout = 300ms;
        o.handshake_timeout = 2s;
        o.mjpeg_profile = "center";
        o.metrics = [](MetricsRegistry& r) { r.counter("navmapd_frames_total", "The daemon's frames.").sample(42); };
        o.status_json = [] { return std::string(R"({"vehicle":{"speed":13.5}})"); };
        m_server = std::make_unique<FrameServer>(o);
        auto s = m_server->start();
        ASSERT_TRUE(s.ok()) << s.message();
    }
    void TearDown() override {
        m_server.reset();
        EXPECT_EQ(countOpenFds(), m_fds_before) << "descriptors leaked";
    }
    // Publishes one frame of the small profile with every pixel = seq.
    void publishSeq(std::uint64_t seq, const std::string& view = "bird", int w = 64, int h = 32) {
        const auto px = sequencePattern(w, h, seq);
        FrameView f;
        f.pixels = px.data();
        f.width = w;
        f.height = h;
        f.source_time_ns = 1000 + static_cast<std::int64_t>(seq);
        f.render_time_ns = 5000 + static_cast<std::int64_t>(seq);
        m_server->publish(view, f);
    }
    template <typename Pred>
    bool waitFor(Pred pred, std::chrono::milliseconds limit = 3s) {
        return navmap::test::waitFor(pred, limit);
    }
    std::unique_ptr<StreamClient> connect(const StreamRequest& r) {
        auto c = r.payload == StreamPayload::Shm
                     ? StreamClient::connectUnix(m_server->options().unix_path, r)
                     : StreamClient::connectTcp("127.0.0.1", m_server->tcpPort(), r, 5s, zlibInflater());
        EXPECT_TRUE(c.ok()) << (c.ok() ? "" : c.error().message);
        return c.ok() ? std::move(c.value()) : nullptr;
    }

    int m_fds_before = 0;
    std::unique_ptr<FrameServer> m_server;
};

void expectPattern(const ReceivedFrame& f, std::uint64_t seq) {
    ASSERT_EQ(f.pixels.size(), f.header.pixelBytes());
    const auto want = sequencePattern(static_cast<int>(f.header.width), static_cast<int>(f.header.height), seq);
    ASSERT_EQ(0, std::memcmp(f.pixels.data(), want.data(), want.size()))
        << "frame " << seq << " pixel 0 = " << int(f.pixels[0]) << "," << int(f.pixels[1]) << "," << int(f.pixels[2]);
}

// Torn-frame check for frames from a Publisher: all pixels of one frame carry one value.
void expectUniform(const ReceivedFrame& f) {
    ASSERT_TRUE(wholePublisherFrame(f.pixels, f.header.pixelBytes())) << "torn frame " << f.header.sequence;
}

}  // namespace

TEST_F(StreamServerTest, EveryTransportDeliversTheSameFrameAndHeader) {
    auto shm = connect(small(StreamPayload::Shm));
    auto raw = connect(small(StreamPayload::Raw));
    auto zl = connect(small(StreamPayload::Zlib));
    ASSERT_TRUE(shm && raw && zl);
    ASSERT_TRUE(waitFor([&] { return m_server->stats().clients == 3; }));
    EXPECT_EQ(m_server->stats().rings, 1U);  // one ring per profile, shared by all transports
    const auto active = m_server->activeProfiles();
    ASSERT_EQ(active.size(), 1U);
    EXPECT_EQ(active[0].view, "bird");
    EXPECT_EQ(active[0].width, 64);
    EXPECT_EQ(active[0].clients, 3U);
    publishSeq(1);
    for (StreamClient* c : {shm.get(), raw.get(), zl.get()}) {
        ReceivedFrame f;
        auto r = c->next(f, 3s);
        ASSERT_TRUE(r.ok()) << r.error().message;
        ASSERT_TRUE(r.value()) << "timeout on " << streamPayloadName(c->payload());
        EXPECT_EQ(f.header.sequence, 1U);
        EXPECT_EQ(f.header.width, 64U);
        EXPECT_EQ(f.header.height, 32U);
        EXPECT_EQ(f.header.stride, 256U);
        EXPECT_EQ(f.header.format, PixelFormat::Rgba8);
        EXPECT_EQ(f.header.source_time_ns, 1001);
        EXPECT_EQ(f.header.render_time_ns, 5001);
        EXPECT_EQ(f.header.dropped, 0U);
        expectPattern(f, 1);
    }
    EXPECT_LT(zl->stats().bytes, 64U * 32U * 4U / 10U);  // flat frames compress well
}

TEST_F(StreamServerTest, Rgb565IsConvertedOnPublish) {
    auto shm = connect(small(StreamPayload::Shm, 240, PixelFormat::Rgb565));
    auto tcp = connect(small(StreamPayload::Zlib, 240, PixelFormat::Rgb565));
    ASSERT_TRUE(shm && tcp);
    ASSERT_TRUE(waitFor([&] { return m_server->stats().clients == 2; }));
    const std::uint64_t seq = 0x00F80480;  // R=0x80 G=0x04 B=0xF8
    publishSeq(seq);
    for (StreamClient* c : {shm.get(), tcp.get()}) {
        ReceivedFrame f;
        auto r = c->next(f, 3s);
        ASSERT_TRUE(r.ok() && r.value());
        EXPECT_EQ(f.header.format, PixelFormat::Rgb565);
        EXPECT_EQ(f.header.stride, 128U);
        // 0x80>>3=16, 0x04>>2=1, 0xF8>>3=31: 16<<11 | 1<<5 | 31 = 0x803F
        EXPECT_EQ(f.pixels[0], 0x3F);
        EXPECT_EQ(f.pixels[1], 0x80);
    }
}

TEST_F(StreamServerTest, SlowShmReaderNeverGetsATornFrame) {
    // Render as fast as possible into a 4-slot ring while the client dawdles after each frame:
    // every frame it accepts must be one whole frame (all pixels carry the same sequence).
    auto c = connect(small(StreamPayload::Shm));
    ASSERT_TRUE(c);
    ASSERT_TRUE(waitFor([&] { return m_server->stats().clients == 1; }));
    Publisher pub(*m_server, "bird", 64, 32, 0);
    ReceivedFrame f;
    int got = 0;
    std::uint64_t last = 0;
    const auto until = std::chrono::steady_clock::now() + 500ms;
    while (std::chrono::steady_clock::now() < until) {
        auto r = c->next(f, 1s);
        ASSERT_TRUE(r.ok()) << r.error().message;
        if (!r.value()) {
            continue;
        }
        ++got;
        EXPECT_GT(f.header.sequence, last);
        last = f.header.sequence;
        expectUniform(f);
        std::this_thread::sleep_for(10ms);  // 100 fps at best, though it asked for up to 240
    }
    pub.stop();
    EXPECT_GT(got, 20);
    EXPECT_GT(pub.published(), static_cast<std::uint64_t>(got));  // it really was lapped
    EXPECT_GT(f.header.dropped, 0U);                              // and the drops are counted
    std::printf("slow reader: %d frames of %llu published, dropped %llu (lost locally %llu)\n", got,
                static_cast<unsigned long long>(pub.published()), static_cast<unsigned long long>(f.header.dropped),
                static_cast<unsigned long long>(c->stats().lost_locally));
}

namespace {

// Frames a fast shm client receives in `window` while frames are published at `fps`.
int framesReceived(StreamClient& c, std::chrono::milliseconds window) {
    ReceivedFrame f;
    int n = 0;
    const auto until = std::chrono::steady_clock::now() + window;
    while (std::chrono::steady_clock::now() < until) {
        auto r = c.next(f, 50ms);
        if (!r.ok()) {
            ADD_FAILURE() << r.error().message;
            return -1;
        }
        n += r.value() ? 1 : 0;
    }
    return n;
}

}  // namespace

TEST_F(StreamServerTest, ClientsThatNeverReadDoNotSlowTheOthers) {
    auto fast = connect(small(StreamPayload::Shm));
    ASSERT_TRUE(fast);
    Publisher pub(*m_server, "bird", 64, 32, 100);
    const int alone = framesReceived(*fast, 600ms);
    ASSERT_GT(alone, 20);

    // A shm client that never acks, a TCP client and an MJPEG viewer that never read, and a
    // connection that never completes its handshake.
    const int stuck_shm = connectUnixRaw(m_server->options().unix_path);
    ASSERT_TRUE(sendAllRaw(stuck_shm, formatStreamRequest(small(StreamPayload::Shm))));
    const int stuck_tcp = connectTcpRaw(m_server->tcpPort());
    int tiny = 4096;
    setsockopt(stuck_tcp, SOL_SOCKET, SO_RCVBUF, &tiny, sizeof(tiny));
    ASSERT_TRUE(sendAllRaw(stuck_tcp, formatStreamRequest(small(StreamPayload::Raw))));
    const int stuck_http = connectTcpRaw(m_server->httpPort());
    setsockopt(stuck_http, SOL_SOCKET, SO_RCVBUF, &tiny, sizeof(tiny));
    ASSERT_TRUE(sendAllRaw(stuck_http,
                           "GET /stream.mjpg?profile=test&width=64&height=32&view=bird HTTP/1.1\r\nHost: 127.0.0.1:" +
                               std::to_string(m_server->httpPort()) + "\r\n\r\n"));
    const int silent = connectUnixRaw(m_server->options().unix_path);

    const int with_stuck = framesReceived(*fast, 600ms);
    std::printf("fast client: %d frames alone, %d with four stuck clients\n", alone, with_stuck);
    EXPECT_GE(with_stuck, alone * 9 / 10);
    // The stalled ones are gone after the stall timeout (300 ms), the silent one after the
    // handshake timeout (2 s); the fast one, still reading, stays.
    const auto until = std::chrono::steady_clock::now() + 6s;
    while (std::chrono::steady_clock::now() < until &&
           (m_server->stats().stall_disconnects < 3 || m_server->stats().handshake_timeouts < 1 ||
            m_server->stats().clients != 1)) {
        ASSERT_GE(framesReceived(*fast, 50ms), 0);
    }
    EXPECT_EQ(m_server->stats().stall_disconnects, 3U);
    EXPECT_EQ(m_server->stats().handshake_timeouts, 1U);
    EXPECT_EQ(m_server->stats().clients, 1U);
    EXPECT_GT(framesReceived(*fast, 200ms), 5);
    pub.stop();
    for (int fd : {stuck_shm, stuck_tcp, stuck_http, silent}) {
        close(fd);
    }
}

TEST_F(StreamServerTest, DisconnectAndReconnect) {
    Publisher pub(*m_server, "bird", 64, 32, 200);
    for (int round = 0; round < 3; ++round) {
        auto c = connect(small(round == 1 ? StreamPayload::Zlib : StreamPayload::Shm));
        ASSERT_TRUE(c);
        ReceivedFrame f;
        int got = 0;
        for (int i = 0; i < 50 && got < 5; ++i) {
            auto r = c->next(f, 200ms);
            ASSERT_TRUE(r.ok()) << r.error().message;
            if (r.value()) {
                expectUniform(f);
                ++got;
            }
        }
        EXPECT_EQ(got, 5) << "round " << round;
        c.reset();
        ASSERT_TRUE(waitFor([&] { return m_server->stats().clients == 0 && m_server->stats().rings == 0; }));
        EXPECT_TRUE(m_server->activeProfiles().empty());
    }
    pub.stop();
}

TEST_F(StreamServerTest, MalformedHandshakesGetErrorsAndChangeNothing) {
    auto good = connect(small(StreamPayload::Shm));
    ASSERT_TRUE(good);
    ASSERT_TRUE(waitFor([&] { return m_server->stats().clients == 1; }));
    const std::vector<std::string> bad = {
        "not json\n",
        "{\"version\":1,\"profile\":\"hud\",\"width\":-5}\n",
        "{\"version\":7,\"profile\":\"hud\"}\n",
        "{\"version\":1,\"profile\":\"cluster\",\"payload\":\"carrier-pigeon\"}\n",
        std::string("\x00\x01\x02\xff\xfe garbage", 13),
        std::string(5000, 'x'),
        "{\"version\":1,\"profile\":\"hud\"}{\"more\":1}\n",
    };
    for (const bool tcp : {false, true}) {
        for (const auto& b : bad) {
            const int fd = tcp ? connectTcpRaw(m_server->tcpPort()) : connectUnixRaw(m_server->options().unix_path);
            ASSERT_GE(fd, 0);
            sendAllRaw(fd, b);
            const std::string reply = readUntilClose(fd, 3s);
            close(fd);
            const auto nl = reply.find('\n');
            ASSERT_NE(nl, std::string::npos) << "no reply to " << b.substr(0, 40);
            auto j = nlohmann::json::parse(reply.substr(0, nl), nullptr, false);
            ASSERT_TRUE(j.is_object()) << reply;
            EXPECT_EQ(j["ok"], false);
            EXPECT_TRUE(j["error"].is_string() && !j["error"].get<std::string>().empty()) << reply;
        }
    }
    // shm over TCP is refused with a reason.
    {
        const int fd = connectTcpRaw(m_server->tcpPort());
        sendAllRaw(fd, formatStreamRequest(small(StreamPayload::Shm)));
        const std::string reply = readUntilClose(fd, 3s);
        close(fd);
        EXPECT_NE(reply.find("needs the Unix socket"), std::string::npos) << reply;
    }
    const auto s = m_server->stats();
    EXPECT_EQ(s.handshake_errors, 2 * bad.size() + 1);
    EXPECT_EQ(s.clients, 1U);
    EXPECT_EQ(s.rings, 1U);
    // The good client still streams.
    publishSeq(9);
    ReceivedFrame f;
    auto r = good->next(f, 3s);
    ASSERT_TRUE(r.ok() && r.value());
    expectPattern(f, 9);
}

TEST_F(StreamServerTest, GarbageAfterTheHandshakeEndsWithAnErrorFrame) {
    for (const auto payload : {StreamPayload::Shm, StreamPayload::Raw}) {
        const int fd = payload == StreamPayload::Shm ? connectUnixRaw(m_server->options().unix_path)
                                                     : connectTcpRaw(m_server->tcpPort());
        ASSERT_TRUE(sendAllRaw(fd, formatStreamRequest(small(payload))));
        ASSERT_TRUE(waitFor([&] { return m_server->stats().clients == 1; }));
        ASSERT_TRUE(sendAllRaw(fd, "\x7fXYZ"));
        const std::string all = readUntilClose(fd, 3s);
        close(fd);
        const auto nl = all.find('\n');
        ASSERT_NE(nl, std::string::npos);
        EXPECT_NE(all.find("\"ok\":true"), std::string::npos);
        const std::string rest = all.substr(nl + 1);
        ASSERT_GE(rest.size(), kFrameHeaderBytes);
        auto h = decodeFrameHeader(reinterpret_cast<const std::uint8_t*>(rest.data()), rest.size());
        ASSERT_TRUE(h.ok()) << h.error().message;
        EXPECT_EQ(h.value().kind, FrameKind::Error);
        EXPECT_EQ(rest.substr(kFrameHeaderBytes), "unexpected byte 0x7f after the handshake");
        ASSERT_TRUE(waitFor([&] { return m_server->stats().clients == 0; }));
    }
    EXPECT_EQ(m_server->stats().protocol_errors, 2U);
    // The client library reports the server's message.
    auto c = connect(small(StreamPayload::Shm));
    ASSERT_TRUE(c);
    ASSERT_TRUE(sendAllRaw(c->fd(), "A"));  // an ack without a frame
    ReceivedFrame f;
    auto r = c->next(f, 3s);
    ASSERT_FALSE(r.ok());
    EXPECT_NE(r.error().message.find("ack without a frame"), std::string::npos) << r.error().message;
}

TEST_F(StreamServerTest, HttpPagesStatusAndMetrics) {
    const std::string page = httpGet(m_server->httpPort(), "/");
    EXPECT_EQ(page.rfind("HTTP/1.0 200 OK\r\n", 0), 0U) << page.substr(0, 80);
    EXPECT_NE(page.find("text/html"), std::string::npos);
    EXPECT_NE(page.find("<img id=\"view\""), std::string::npos);
    EXPECT_NE(page.find("/stream.mjpg?profile=center"), std::string::npos);

    const std::string status =
        httpExchange(m_server->httpPort(),
                     "GET /status HTTP/1.0\r\nHost: localhost:" + std::to_string(m_server->httpPort()) + "\r\n\r\n");
    ASSERT_NE(status.find("\r\n\r\n"), std::string::npos);
    auto j = nlohmann::json::parse(status.substr(status.find("\r\n\r\n") + 4), nullptr, false);
    ASSERT_TRUE(j.is_object()) << status;
    EXPECT_EQ(j["daemon"]["vehicle"]["speed"], 13.5);
    EXPECT_EQ(j["stream"]["clients"], 0);
    j["stream"].erase("profiles");  // the rest is frameServerStatsJson's object, as in get_status
    EXPECT_EQ(j["stream"].size(), frameServerStatsJson({}).size()) << j["stream"].dump();
    EXPECT_TRUE(j["stream"]["frames_sent"].is_number() && j["stream"]["statuses_sent"].is_number());

    const std::string metrics = httpGet(m_server->httpPort(), "/metrics");
    EXPECT_NE(metrics.find("text/plain; version=0.0.4"), std::string::npos);
    // The server's families first, then the daemon's, each with HELP and TYPE, each once.
    EXPECT_NE(metrics.find("\r\n\r\n# HELP navmap_stream_clients "), std::string::npos) << metrics;
    EXPECT_NE(metrics.find("# TYPE navmapd_frames_total counter\nnavmapd_frames_total 42\n"), std::string::npos)
        << metrics;
    EXPECT_EQ(metrics.find("# TYPE navmap_stream_clients"), metrics.rfind("# TYPE navmap_stream_clients")) << metrics;
    EXPECT_NE(metrics.find("# TYPE navmap_stream_frames_published_total counter"), std::string::npos);
    EXPECT_NE(metrics.find("navmap_stream_clients{transport=\"shm\"} 0"), std::string::npos);
}

TEST_F(StreamServerTest, HttpGarbageGetsErrors) {
    const int port = m_server->httpPort();
    const std::string host = "Host: 127.0.0.1:" + std::to_string(port) + "\r\n";
    const std::pair<std::string, std::string> cases[] = {
        {"GET /nothing HTTP/1.1\r\n" + host + "\r\n", "HTTP/1.0 404"},
        {"POST /status HTTP/1.1\r\n" + host + "Content-Length: 0\r\n\r\n", "HTTP/1.0 405"},
        {"GET / HTTP/2.0\r\n\r\n", "HTTP/1.0 400"},
        {"BLAH\r\n\r\n", "HTTP/1.0 400"},
        {std::string("\x16\x03\x01\x02\x00\x01\x00\x01\xfc\x03\x03", 11), "HTTP/1.0 400"},  // a TLS hello
        {"GET /" + std::string(9000, 'a') + " HTTP/1.1\r\n\r\n", "HTTP/1.0 431"},
        {"GET /stream.mjpg?profile=warp HTTP/1.1\r\n" + host + "\r\n", "HTTP/1.0 400"},
        {"GET /stream.mjpg?profile=hud&fps=100000 HTTP/1.1\r\n" + host + "\r\n", "HTTP/1.0 400"},
    };
    for (const auto& [req, want] : cases) {
        const std::string reply = httpExchange(port, req);
        EXPECT_EQ(reply.rfind(want, 0), 0U) << req.substr(0, 40) << " -> " << reply.substr(0, 80);
    }
    const auto s = m_server->stats();
    EXPECT_EQ(s.http_errors, std::size(cases));
    EXPECT_EQ(s.clients, 0U);
    EXPECT_EQ(s.rings, 0U);
}

TEST_F(StreamServerTest, MjpegOverHttpDecodesToThePublishedImage) {
    MjpegReader reader(m_server->httpPort(), "/stream.mjpg?profile=side&width=96&height=48&view=bird&fps=60");
    ASSERT_TRUE(reader.ok()) << reader.responseHead();
    EXPECT_NE(reader.responseHead().find("multipart/x-mixed-replace; boundary=navmapframe"), std::string::npos);
    ASSERT_TRUE(waitFor([&] { return m_server->stats().mjpeg_clients == 1; }));
    // Left half red, right half blue.
    std::vector<std::uint8_t> px(96 * 48 * 4);
    for (int y = 0; y < 48; ++y) {
        for (int x = 0; x < 96; ++x) {
            std::uint8_t* p = &px[(static_cast<std::size_t>(y) * 96 + x) * 4];
            p[0] = x < 48 ? 220 : 20;
            p[1] = 30;
            p[2] = x < 48 ? 20 : 200;
            p[3] = 255;
        }
    }
    for (int i = 0; i < 2; ++i) {
        m_server->publish("bird", FrameView{px.data(), 96, 48, 0, PixelFormat::Rgba8, 0, 0, {}, {}});
        std::uint64_t seq = 0;
        const auto jpeg = reader.next(3s, &seq);
        ASSERT_FALSE(jpeg.empty()) << "no JPEG part " << i;
        EXPECT_EQ(seq, static_cast<std::uint64_t>(i + 1));
        int w = 0, h = 0;
        std::vector<std::uint8_t> rgba;
        ASSERT_TRUE(decodeJpeg(jpeg, &w, &h, &rgba));
        ASSERT_EQ(w, 96);
        ASSERT_EQ(h, 48);
        const auto at = [&](int x, int y, int c) {
            return static_cast<int>(rgba[(static_cast<std::size_t>(y) * 96 + x) * 4 + c]);
        };
        EXPECT_NEAR(at(10, 24, 0), 220, 12);
        EXPECT_NEAR(at(10, 24, 2), 20, 12);
        EXPECT_NEAR(at(85, 24, 0), 20, 12);
        EXPECT_NEAR(at(85, 24, 2), 200, 12);
        std::this_thread::sleep_for(20ms);  // stay under the 60 fps cap
    }
}

TEST_F(StreamServerTest, NoFdOrMemoryGrowthOver100ConnectDisconnectCycles) {
    Publisher pub(*m_server, "bird", 64, 32, 200);
    const auto cycle = [&](int i) {
        switch (i % 4) {
            case 0:
            case 1: {
                auto c = connect(small(i % 4 == 0 ? StreamPayload::Shm : StreamPayload::Zlib));
                ASSERT_TRUE(c);
                ReceivedFrame f;
                auto r = c->next(f, 2s);
                ASSERT_TRUE(r.ok() && r.value()) << "cycle " << i;
                break;
            }
            case 2: {
                MjpegReader m(m_server->httpPort(), "/stream.mjpg?profile=t&width=64&height=32&view=bird");
                ASSERT_TRUE(m.ok());
                ASSERT_FALSE(m.next(2s).empty()) << "cycle " << i;
                break;
            }
            default: {
                const int fd = connectUnixRaw(m_server->options().unix_path);
                sendAllRaw(fd, "{\"broken\n");
                readUntilClose(fd, 2s);
                close(fd);
                break;
            }
        }
    };
    for (int i = 0; i < 12; ++i) {  // warm-up: allocator pools, first rings
        cycle(i);
    }
    ASSERT_TRUE(waitFor([&] { return m_server->stats().connections == 0; }));
    const int fds = countOpenFds();
    const long rss = rssKb();
    for (int i = 0; i < 100; ++i) {
        cycle(i);
    }
    ASSERT_TRUE(waitFor([&] { return m_server->stats().connections == 0 && m_server->stats().rings == 0; }));
    const int fds_after = countOpenFds();
    const long rss_after = rssKb();
    pub.stop();
    EXPECT_EQ(fds_after, fds);
    std::printf("100 cycles: fds %d -> %d, RSS %ld -> %ld kB\n", fds, fds_after, rss, rss_after);
    EXPECT_LT(rss_after - rss, 4096) << "RSS grew by " << (rss_after - rss) << " kB";
}

TEST_F(StreamServerTest, ActiveProfilesTellTheDaemonWhatToRender) {
    StreamRequest a = small(StreamPayload::Shm, 10);
    StreamRequest b = small(StreamPayload::Raw, 25, PixelFormat::Rgb565);
    auto c1 = connect(a);
    auto c2 = connect(b);
    auto hud = parseStreamRequest(R"({"version":1,"profile":"hud","payload":"shm"})");
    ASSERT_TRUE(hud.ok());
    auto c3 = connect(hud.value());
    ASSERT_TRUE(c1 && c2 && c3);
    ASSERT_TRUE(waitFor([&] { return m_server->stats().clients == 3; }));
    auto active = m_server->activeProfiles();
    ASSERT_EQ(active.size(), 2U);  // the two formats of bird 64x32 render once
    std::sort(active.begin(), active.end(), [](const auto& x, const auto& y) { return x.view < y.view; });
    EXPECT_EQ(active[0].view, "bird");
    EXPECT_EQ(active[0].max_fps, 25);
    EXPECT_EQ(active[0].clients, 2U);
    EXPECT_EQ(active[1].view, "hud");
    EXPECT_EQ(active[1].width, 800);
    EXPECT_EQ(active[1].height, 240);
    EXPECT_EQ(m_server->stats().rings, 3U);
}

// Display processes wait for the socket file and connect the moment it is there: the file
// appears only once the socket listens (bound under a staging name, then renamed into place), so
// such a connect never meets a refusal. A thread polls for the path and connects as soon as it
// exists, across 300 starts of a server.
TEST(FrameServerSetup, TheSocketFileAppearsOnlyOnceItListens) {
    const std::string path = "/tmp/navmap-listen-" + std::to_string(::getpid()) + ".sock";
    std::atomic<int> refused{0}, connected{0};
    for (int i = 0; i < 300; ++i) {
        ::unlink(path.c_str());
        std::atomic<bool> stop{false};
        std::thread poller([&] {
            while (!stop) {
                if (::access(path.c_str(), F_OK) != 0) continue;
                const int fd = ::socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0);
                sockaddr_un addr{};
                addr.sun_family = AF_UNIX;
                std::memcpy(addr.sun_path, path.c_str(), path.size() + 1);
                if (::connect(fd, reinterpret_cast<const sockaddr*>(&addr), sizeof addr) == 0)
                    ++connected;
                else if (errno == ECONNREFUSED)
                    ++refused;
                ::close(fd);
                return;
            }
        });
        FrameServerOptions o;
        o.unix_path = path;
        FrameServer s(o);
        const auto st = s.start();
        EXPECT_TRUE(st.ok()) << st.message();
        EXPECT_TRUE(navmap::test::waitFor([&] { return connected + refused > i; }, 2s));
        stop = true;
        poller.join();
        EXPECT_FALSE(std::filesystem::exists(path + ".bind")) << "the staging name is gone";
    }
    ::unlink(path.c_str());
    EXPECT_EQ(refused, 0);
    EXPECT_EQ(connected, 300);
}

TEST(FrameServerSetup, BindErrorsNameTheCallAndTheObject) {
    const int fds = countOpenFds();
    {
        FrameServerOptions o;
        o.unix_path = "/nonexistent-navmap-dir/stream.sock";
        FrameServer s(o);
        auto st = s.start();
        ASSERT_FALSE(st.ok());
        EXPECT_EQ(st.message(), "bind(/nonexistent-navmap-dir/stream.sock): No such file or directory");
    }
    {
        FrameServerOptions o;
        o.tcp_port = 0;
        FrameServer first(o);
        ASSERT_TRUE(first.start().ok());
        FrameServerOptions o2;
        o2.tcp_port = first.tcpPort();
        FrameServer second(o2);
        auto st = second.start();
        ASSERT_FALSE(st.ok());
        EXPECT_EQ(st.message(), "bind(127.0.0.1:" + std::to_string(first.tcpPort()) + "): Address already in use");
    }
    {
        FrameServerOptions o;
        o.bind_address = "localhost-ish";
        o.http_port = 0;
        FrameServer s(o);
        auto st = s.start();
        ASSERT_FALSE(st.ok());
        EXPECT_NE(st.message().find("not a numeric"), std::string::npos);
    }
    EXPECT_EQ(countOpenFds(), fds);
}

TEST(StreamClientSetup, ConnectErrorsNameThePeer) {
    auto c = StreamClient::connectUnix("/nonexistent-navmap-dir/s.sock", StreamRequest{});
    ASSERT_FALSE(c.ok());
    EXPECT_EQ(c.error().message, "connect(/nonexistent-navmap-dir/s.sock): No such file or directory");
    StreamRequest r;
    r.payload = StreamPayload::Raw;
    auto t = StreamClient::connectTcp("127.0.0.1", 1, r, 500ms);
    ASSERT_FALSE(t.ok());
    EXPECT_EQ(t.error().message, "connect(127.0.0.1:1): Connection refused");
}

TEST_F(StreamServerTest, FrameRateCapDelaysButNeverLosesTheNewestFrame) {
    auto c = connect(small(StreamPayload::Shm, 10));  // at most one frame per 100 ms
    ASSERT_TRUE(c);
    ASSERT_TRUE(waitFor([&] { return m_server->stats().clients == 1; }));
    publishSeq(1);
    ReceivedFrame f;
    auto r = c->next(f, 2s);
    ASSERT_TRUE(r.ok() && r.value());
    EXPECT_EQ(f.header.sequence, 1U);
    const auto t0 = std::chrono::steady_clock::now();
    publishSeq(2);  // too early for a 10 fps client; the render loop then goes quiet
    r = c->next(f, 2s);
    ASSERT_TRUE(r.ok() && r.value()) << "the capped frame never came";
    const auto waited = std::chrono::steady_clock::now() - t0;
    EXPECT_EQ(f.header.sequence, 2U);
    expectPattern(f, 2);
    EXPECT_GE(waited, 40ms);  // held back by the cap (3/4 of the period, minus scheduling)
    EXPECT_LT(waited, 500ms);
    EXPECT_EQ(f.header.dropped, 0U);  // a capped frame is not a drop
}

// zlib and JPEG encoding run on the encoder thread, once per frame and format: shared-memory
// clients keep their frame rate while a compressed TCP client and an MJPEG viewer take frames of
// a size and content that cost the encoder tens of milliseconds each.
TEST_F(StreamServerTest, ShmClientsKeepTheirRateWhileZlibAndMjpegClientsAreServed) {
    constexpr int kW = 1280, kH = 720, kFps = 30;
    std::vector<std::vector<std::uint8_t>> frames;
    std::uint32_t noise = 12345;
    for (int v = 0; v < 2; ++v) {
        std::vector<std::uint8_t> px(static_cast<std::size_t>(kW) * kH * 4);
        for (std::size_t i = 0; i < px.size(); ++i) {
            noise = noise * 1664525U + 1013904223U;
            px[i] = (i % 4 == 3) ? 255 : static_cast<std::uint8_t>((i / 4 % kW) / 5 + v * 40 + (noise >> 28));
        }
        frames.push_back(std::move(px));
    }
    std::atomic<bool> publishing{true};
    std::thread publisher([&] {
        auto next = std::chrono::steady_clock::now();
        for (std::uint64_t i = 0; publishing; ++i) {
            FrameView f;
            f.pixels = frames[i % 2].data();
            f.width = kW;
            f.height = kH;
            f.source_time_ns = 1;
            m_server->publish("bird", f);
            next += std::chrono::milliseconds(1000 / kFps);
            std::this_thread::sleep_until(next);
        }
    });
    StreamRequest shm_req = small(StreamPayload::Shm, 0);
    shm_req.profile.width = kW;
    shm_req.profile.height = kH;
    auto shm = connect(shm_req);
    ASSERT_TRUE(shm);
    ASSERT_GT(framesReceived(*shm, 300ms), 0);
    const int alone = framesReceived(*shm, 1500ms);

    StreamRequest z_req = shm_req;
    z_req.payload = StreamPayload::Zlib;
    auto zlib = connect(z_req);
    ASSERT_TRUE(zlib);
    std::atomic<bool> reading{true};
    std::atomic<int> zlib_frames{0}, jpeg_frames{0};
    std::thread zlib_reader([&] {
        ReceivedFrame f;
        while (reading) {
            auto r = zlib->next(f, 50ms);
            if (!r.ok()) return;
            zlib_frames += r.value() ? 1 : 0;
        }
    });
    std::thread jpeg_reader([&] {
        MjpegReader mjpeg(m_server->httpPort(), "/stream.mjpg?profile=test&width=1280&height=720&view=bird&fps=0");
        while (reading) {
            if (!mjpeg.next(200ms).empty()) ++jpeg_frames;
        }
    });
    // Both compressed clients get going (the shm client keeps reading meanwhile).
    for (int i = 0; i < 100 && (zlib_frames == 0 || jpeg_frames == 0); ++i) {
        framesReceived(*shm, 50ms);
    }
    const int zlib_before = zlib_frames, jpeg_before = jpeg_frames;
    const int with_encoders = framesReceived(*shm, 1500ms);
    // The compressed clients get a second more (on two loaded cores a 1280x720 encode can take a
    // few hundred milliseconds); the shm client keeps reading.
    framesReceived(*shm, 1000ms);
    const int zlib_during = zlib_frames - zlib_before, jpeg_during = jpeg_frames - jpeg_before;
    reading = false;
    zlib_reader.join();
    jpeg_reader.join();
    publishing = false;
    publisher.join();
    const std::string metrics = m_server->metricsText();
    std::printf("shm client: %d frames alone, %d with a zlib and an MJPEG client (%d zlib, %d JPEG frames meanwhile)\n",
                alone, with_encoders, zlib_during, jpeg_during);
    EXPECT_GE(alone, kFps * 3 / 2 * 8 / 10) << "the shm client keeps up with the publisher";
    EXPECT_GE(with_encoders, alone * 9 / 10);
    EXPECT_GT(zlib_during, 3) << m_server->stats().last_error;
    EXPECT_GT(jpeg_during, 3) << m_server->stats().last_error;
    EXPECT_EQ(metrics.find("navmap_stream_encodes_total 0\n"), std::string::npos) << metrics;
    EXPECT_NE(metrics.find("navmap_stream_encode_seconds{format=\"zlib\",stat=\"max\"}"), std::string::npos) << metrics;
}
