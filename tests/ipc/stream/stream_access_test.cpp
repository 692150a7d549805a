// SPDX-License-Identifier: Apache-2.0
// FrameServer against hostile local clients: the socket file's mode and group, SO_PEERCRED allow
// lists (with clients that really run as other uids), per-transport and per-uid caps, refusal of
// views and sizes that are not rendered, the handshake and first-frame timeouts, the ring memory
// ceiling, rings no client can write, and the HTTP Host check and token.

#include <fcntl.h>
#include <gtest/gtest.h>
#include <linux/falloc.h>
#include <sys/mman.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cstring>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>

#include "navmap/ipc/client/frame_header.h"
#include "navmap/ipc/client/frame_ring.h"
#include "navmap/ipc/client/stream_client.h"
#include "navmap/ipc/stream/frame_server.h"
#include "stream_test_util.h"
#include "wait_for.h"

using namespace navmap::ipc;
using namespace navmap::stream_test;
using namespace std::chrono_literals;
using navmap::test::cannotSwitchUser;
using navmap::test::ForeignProcess;
using navmap::test::ForeignUser;

namespace {

constexpr uid_t kNobody = 65534;
constexpr gid_t kNogroup = 65534;

StreamRequest request(const std::string& view, int width, int height, StreamPayload payload = StreamPayload::Shm,
                      PixelFormat format = PixelFormat::Rgba8) {
    StreamRequest r;
    r.profile.name = "test";
    r.profile.view = view;
    r.profile.width = width;
    r.profile.height = height;
    r.profile.fps = 0;
    r.profile.format = format;
    r.payload = payload;
    return r;
}

StreamRequest cluster(StreamPayload payload = StreamPayload::Shm) {
    StreamRequest r;
    r.profile = *defaultStreamProfile("cluster");
    r.payload = payload;
    return r;
}

// The lines of a ForeignProcess report that contain `text`.
int countLines(const std::string& report, const std::string& text) {
    std::istringstream in(report);
    int n = 0;
    for (std::string line; std::getline(in, line);) {
        n += line.find(text) != std::string::npos ? 1 : 0;
    }
    return n;
}

// A server for one test, and the fd count around it.
class StreamAccessTest : public ::testing::Test {
protected:
    void SetUp() override { m_fds_before = countOpenFds(); }
    void TearDown() override {
        m_server.reset();
        EXPECT_EQ(countOpenFds(), m_fds_before) << "descriptors leaked";
    }
    FrameServerOptions options() const {
        FrameServerOptions o;
        o.unix_path = uniqueSocketPath("stream-access");
        o.stall_timeout = 2s;
        return o;
    }
    void start(FrameServerOptions o) {
        m_server = std::make_unique<FrameServer>(std::move(o));
        const auto st = m_server->start();
        ASSERT_TRUE(st.ok()) << st.message();
    }
    const std::string& path() const { return m_server->options().unix_path; }
    template <typename Pred>
    bool waitFor(Pred pred, std::chrono::milliseconds limit = 5s) {
        return navmap::test::waitFor(pred, limit);
    }
    // One frame for `client` within `limit`; the pixels must be the Publisher's pattern.
    static void expectFrame(StreamClient& client, std::chrono::milliseconds limit = 3s) {
        ReceivedFrame f;
        const auto until = std::chrono::steady_clock::now() + limit;
        while (std::chrono::steady_clock::now() < until) {
            auto r = client.next(f, 100ms);
            ASSERT_TRUE(r.ok()) << r.error().message;
            if (r.value()) {
                ASSERT_EQ(f.pixels.size(), f.header.pixelBytes());
                const auto want = sequencePattern(static_cast<int>(f.header.width), static_cast<int>(f.header.height),
                                                  f.header.sequence);
                EXPECT_EQ(0, std::memcmp(f.pixels.data(), want.data(), want.size()));
                return;
            }
        }
        FAIL() << "no frame within " << limit.count() << " ms";
    }

    int m_fds_before = 0;
    std::unique_ptr<FrameServer> m_server;
};

}  // namespace

TEST_F(StreamAccessTest, SocketFileIs0660WithItsGroupWhateverTheUmask) {
    const mode_t old = ::umask(0);
    FrameServerOptions o = options();
    const gid_t group = ::geteuid() == 0 ? kNogroup : ::getegid();  // root may give it any group
    o.unix_group = group;
    start(o);
    ::umask(old);
    struct stat st {};
    ASSERT_EQ(::stat(path().c_str(), &st), 0);
    EXPECT_TRUE(S_ISSOCK(st.st_mode));
    EXPECT_EQ(st.st_mode & 07777, 0660U) << std::oct << (st.st_mode & 07777);
    EXPECT_EQ(st.st_gid, group);

    // A restrictive umask does not narrow it either.
    m_server.reset();
    const mode_t old2 = ::umask(077);
    start(options());
    ::umask(old2);
    ASSERT_EQ(::stat(path().c_str(), &st), 0);
    EXPECT_EQ(st.st_mode & 07777, 0660U) << std::oct << (st.st_mode & 07777);
}

TEST_F(StreamAccessTest, PeersNotOnTheAllowListAreRefused) {
    if (const auto why = cannotSwitchUser(); !why.empty()) {
        GTEST_SKIP() << why;
    }
    const mode_t old = ::umask(0);
    start(options());  // allowed: the server's own uid (root here) and root
    ::umask(old);
    const std::string line = formatStreamRequest(cluster());
    const std::string sock = path();
    {
        // The file mode keeps nobody out before any byte is exchanged.
        ForeignProcess nobody({kNobody, kNogroup, {}}, [&] { return holdConnections(sock, line, 1); });
        EXPECT_EQ(nobody.result(), "connect: Permission denied\n");
    }
    // Were the mode wider, SO_PEERCRED still refuses: an error line, then the connection closes.
    ASSERT_EQ(::chmod(sock.c_str(), 0666), 0);
    ForeignProcess nobody({kNobody, kNogroup, {}}, [&] {
        auto c = StreamClient::connectUnix(sock, cluster());
        return c.ok() ? std::string("accepted") : c.error().message;
    });
    const std::string got = nobody.result();
    EXPECT_NE(got.find("handshake refused by " + sock + ": peer uid 65534 (pid "), std::string::npos) << got;
    EXPECT_NE(got.find(") is not allowed on " + sock), std::string::npos) << got;
    nobody.release();
    EXPECT_TRUE(waitFor([&] { return m_server->stats().refused_peer == 1; }));
    const auto s = m_server->stats();
    EXPECT_EQ(s.connections, 0U);
    EXPECT_EQ(s.rings, 0U);
    EXPECT_NE(s.last_error.find("refused: peer uid 65534"), std::string::npos) << s.last_error;
    EXPECT_NE(m_server->metricsText().find("navmap_stream_refusals_total{reason=\"peer\"} 1\n"), std::string::npos);
}

TEST_F(StreamAccessTest, ListedUidsAndGroupMembersGetFrames) {
    if (const auto why = cannotSwitchUser(); !why.empty()) {
        GTEST_SKIP() << why;
    }
    constexpr gid_t kDisplays = 64000;  // the socket's group
    FrameServerOptions o = options();
    o.unix_group = kDisplays;
    o.allowed_peers.uids = {kNobody};
    start(o);
    Publisher pub(*m_server, "snail", 1280, 480, 20);
    const std::string sock = path();
    const auto watch = [sock] {
        auto c = StreamClient::connectUnix(sock, cluster());
        if (!c) {
            return c.error().message;
        }
        ReceivedFrame f;
        for (int i = 0; i < 30; ++i) {
            auto r = c.value()->next(f, 100ms);
            if (!r) {
                return r.error().message;
            }
            if (r.value()) {
                // One whole frame of the publisher's. Not checked against the header's sequence:
                // the ring is dropped when its last client leaves and made anew for the next, with
                // sequences from 1 again, and the publisher only restarts its count when a frame
                // finds no ring (a client may leave and the next come between two frames).
                return std::string(wholePublisherFrame(f.pixels, f.header.pixelBytes()) ? "frame ok" : "frame wrong");
            }
        }
        return std::string("no frame");
    };
    // A listed uid (file access through the socket's group as a supplementary group).
    ForeignProcess listed({kNobody, kNogroup, {kDisplays}}, watch);
    // An unlisted uid that is a member of the socket's group (a supplementary group: SO_PEERGROUPS).
    ForeignProcess member({64001, 64001, {kDisplays}}, watch);
    // Neither listed nor a member; the file mode is opened wide so that only the peer check decides.
    EXPECT_EQ(listed.result(), "frame ok");
    EXPECT_EQ(member.result(), "frame ok");
    ASSERT_EQ(::chmod(sock.c_str(), 0666), 0);
    ForeignProcess stranger({64002, 64002, {}}, watch);
    EXPECT_NE(stranger.result().find("peer uid 64002"), std::string::npos) << stranger.result();
    EXPECT_EQ(m_server->stats().refused_peer, 1U);
    pub.stop();
}

TEST_F(StreamAccessTest, OneUidCannotLockOthersOut) {
    if (const auto why = cannotSwitchUser(); !why.empty()) {
        GTEST_SKIP() << why;
    }
    FrameServerOptions o = options();
    o.unix_group = kNogroup;
    o.allowed_peers.uids = {kNobody};
    o.max_clients_per_uid = 4;
    o.max_clients_per_transport = 16;
    o.stall_timeout = 10s;  // nobody's four never ack; they stay for the whole test
    o.rendered_profiles = {{"cluster", "snail", 1280, 480}};
    start(o);
    Publisher pub(*m_server, "cluster", 1280, 480, 20);  // frames go to a rendered profile by its name
    const std::string sock = path();
    // nobody opens 64 cluster streams and holds them: 4 are served, 60 refused at once.
    const std::string line = formatStreamRequest(cluster());
    ForeignProcess nobody({kNobody, kNogroup, {}}, [&] { return holdConnections(sock, line, 64); });
    const std::string report = nobody.result();
    EXPECT_EQ(countLines(report, "\"ok\":true"), 4) << report;
    EXPECT_EQ(countLines(report, "{\"ok\":false,\"error\":\"too many connections from uid 65534 (limit 4)\"}"), 60)
        << report;
    // root's cluster client still connects and gets frames while nobody holds its four.
    auto c = StreamClient::connectUnix(sock, cluster());
    ASSERT_TRUE(c.ok()) << c.error().message;
    expectFrame(*c.value());
    const auto s = m_server->stats();
    EXPECT_EQ(s.refused_uid_full, 60U);
    EXPECT_EQ(s.refused_transport_full, 0U);
    EXPECT_EQ(s.shm_clients, 5U);
    EXPECT_NE(m_server->metricsText().find("navmap_stream_refusals_total{reason=\"uid_full\"} 60\n"),
              std::string::npos);
    nobody.release();
    pub.stop();
}

TEST_F(StreamAccessTest, EachTransportHasItsOwnCap) {
    FrameServerOptions o = options();
    o.tcp_port = 0;
    o.http_port = 0;
    o.max_clients_per_transport = 3;
    o.max_clients_per_uid = 3;
    start(o);
    Publisher pub(*m_server, "bird", 64, 32, 60);
    // Three TCP connections that say nothing fill the TCP transport.
    std::vector<int> tcp;
    tcp.reserve(3);
    for (int i = 0; i < 3; ++i) {
        tcp.push_back(connectTcpRaw(m_server->tcpPort()));
    }
    ASSERT_TRUE(waitFor([&] { return m_server->stats().connections == 3; }));
    const int extra = connectTcpRaw(m_server->tcpPort());
    EXPECT_EQ(readUntilClose(extra, 3s), "{\"ok\":false,\"error\":\"too many tcp clients (limit 3)\"}\n");
    close(extra);
    // Unix and HTTP keep their own slots.
    auto shm = StreamClient::connectUnix(path(), request("bird", 64, 32));
    ASSERT_TRUE(shm.ok()) << shm.error().message;
    expectFrame(*shm.value());
    EXPECT_EQ(httpGet(m_server->httpPort(), "/status").rfind("HTTP/1.0 200 OK", 0), 0U);
    // The fourth Unix connection of this uid is refused at once (uid cap 3 = transport cap 3).
    auto shm2 = StreamClient::connectUnix(path(), request("bird", 64, 32));
    auto shm3 = StreamClient::connectUnix(path(), request("bird", 64, 32));
    ASSERT_TRUE(shm2.ok() && shm3.ok());
    auto shm4 = StreamClient::connectUnix(path(), request("bird", 64, 32));
    ASSERT_FALSE(shm4.ok());
    EXPECT_EQ(shm4.error().message, "handshake refused by " + path() + ": too many unix clients (limit 3)");
    const auto s = m_server->stats();
    EXPECT_EQ(s.refused_transport_full, 2U);
    EXPECT_NE(s.last_error.find("too many unix clients (limit 3)"), std::string::npos) << s.last_error;
    for (int fd : tcp) {
        close(fd);
    }
    pub.stop();
}

TEST_F(StreamAccessTest, UnrenderedViewsAndSizesAreRefusedNamingWhatIsRendered) {
    FrameServerOptions o = options();
    o.tcp_port = 0;
    o.http_port = 0;
    o.rendered_profiles = {{"cluster", "snail", 1280, 480}, {"hud", "hud", 800, 240}};
    start(o);
    const std::string rendered = "rendered: cluster (snail 1280x480), hud (hud 800x240)";
    // Unix (shm) and TCP: an error line, no ring.
    auto big = StreamClient::connectUnix(path(), request("bird", 4096, 4096));
    ASSERT_FALSE(big.ok());
    EXPECT_EQ(big.error().message,
              "handshake refused by " + path() + ": handshake: bird 4096x4096 is not rendered here; " + rendered);
    auto wrong_view =
        StreamClient::connectTcp("127.0.0.1", m_server->tcpPort(), request("bird", 1280, 480, StreamPayload::Raw));
    ASSERT_FALSE(wrong_view.ok());
    EXPECT_NE(wrong_view.error().message.find("handshake: bird 1280x480 is not rendered here; " + rendered),
              std::string::npos)
        << wrong_view.error().message;
    // MJPEG: 400 with the same words.
    const std::string mjpeg = httpGet(m_server->httpPort(), "/stream.mjpg?width=4096&height=4096&view=bird");
    EXPECT_EQ(mjpeg.rfind("HTTP/1.0 400 Bad Request\r\n", 0), 0U) << mjpeg;
    EXPECT_NE(mjpeg.find("\r\n\r\nbird 4096x4096 is not rendered here; " + rendered + "\n"), std::string::npos)
        << mjpeg;
    EXPECT_EQ(m_server->stats().rings, 0U);
    EXPECT_EQ(m_server->stats().refused_not_rendered, 3U);
    EXPECT_NE(m_server->metricsText().find("navmap_stream_refusals_total{reason=\"not_rendered\"} 3\n"),
              std::string::npos);
    // What is rendered is served, in either pixel format, and by name on the MJPEG page.
    Publisher pub(*m_server, "hud", 800, 240, 60);
    StreamRequest hud;
    hud.profile = *defaultStreamProfile("hud");
    hud.profile.format = PixelFormat::Rgb565;
    auto ok = StreamClient::connectUnix(path(), hud);
    ASSERT_TRUE(ok.ok()) << ok.error().message;
    MjpegReader by_name(m_server->httpPort(), "/stream.mjpg?profile=hud");
    ASSERT_TRUE(by_name.ok()) << by_name.responseHead();
    EXPECT_FALSE(by_name.next(3s).empty());
    pub.stop();
}

TEST_F(StreamAccessTest, SilentConnectionsAndClientsWithoutAFrameAreClosed) {
    FrameServerOptions o = options();
    o.tcp_port = 0;
    o.http_port = 0;
    o.handshake_timeout = 300ms;
    start(o);
    const auto t0 = std::chrono::steady_clock::now();
    const int silent_unix = connectUnixRaw(path());
    const int silent_tcp = connectTcpRaw(m_server->tcpPort());
    const int half_http = connectTcpRaw(m_server->httpPort());
    ASSERT_TRUE(sendAllRaw(half_http, "GET /status HTTP/1.1\r\n"));
    // A client of a view nobody publishes: handshake fine, then no frame.
    auto starved = StreamClient::connectUnix(path(), request("bird", 64, 32));
    ASSERT_TRUE(starved.ok()) << starved.error().message;
    // A client of a published view stays.
    Publisher pub(*m_server, "hud", 64, 32, 50);
    auto fed = StreamClient::connectUnix(path(), request("hud", 64, 32));
    ASSERT_TRUE(fed.ok()) << fed.error().message;

    EXPECT_EQ(readUntilClose(silent_unix, 3s), "{\"ok\":false,\"error\":\"no complete handshake within 300 ms\"}\n");
    EXPECT_EQ(readUntilClose(silent_tcp, 3s), "{\"ok\":false,\"error\":\"no complete handshake within 300 ms\"}\n");
    const std::string http = readUntilClose(half_http, 3s);
    EXPECT_EQ(http.rfind("HTTP/1.0 408 Request Timeout\r\n", 0), 0U) << http;
    EXPECT_NE(http.find("no complete request head within 300 ms"), std::string::npos) << http;
    const auto closed_after = std::chrono::steady_clock::now() - t0;
    EXPECT_LT(closed_after, 2s) << "closed by the handshake timeout, not the stall timeout";
    ReceivedFrame f;
    auto r = starved.value()->next(f, 3s);
    ASSERT_FALSE(r.ok());
    EXPECT_NE(r.error().message.find(
                  "disconnected, no frame within 300 ms of the handshake (nothing published for bird 64x32)"),
              std::string::npos)
        << r.error().message;
    // The fed client keeps receiving well past the timeout.
    std::this_thread::sleep_for(500ms);
    expectFrame(*fed.value());
    const auto s = m_server->stats();
    EXPECT_EQ(s.handshake_timeouts, 3U);
    EXPECT_EQ(s.first_frame_timeouts, 1U);
    EXPECT_EQ(s.clients, 1U);
    const std::string metrics = m_server->metricsText();
    EXPECT_NE(metrics.find("navmap_stream_timeouts_total{kind=\"handshake\"} 3\n"), std::string::npos) << metrics;
    EXPECT_NE(metrics.find("navmap_stream_timeouts_total{kind=\"first_frame\"} 1\n"), std::string::npos) << metrics;
    for (int fd : {silent_unix, silent_tcp, half_http}) {
        close(fd);
    }
    pub.stop();
}

TEST_F(StreamAccessTest, RingMemoryHasACeiling) {
    FrameServerOptions o = options();
    o.http_port = 0;
    o.ring_slots = 3;
    // 64x32 RGBA8 needs 40 KiB (a header page and three 12 KiB slots), RGB565 28 KiB: one fits.
    o.ring_memory_bytes = 64 * 1024;
    start(o);
    ASSERT_EQ(FrameRingLayout::make(3, 64, 32, PixelFormat::Rgba8).total_bytes, 40960U);
    auto first = StreamClient::connectUnix(path(), request("bird", 64, 32));
    ASSERT_TRUE(first.ok()) << first.error().message;
    auto second = StreamClient::connectUnix(path(), request("bird", 64, 32, StreamPayload::Shm, PixelFormat::Rgb565));
    ASSERT_FALSE(second.ok());
    EXPECT_EQ(second.error().message, "handshake refused by " + path() +
                                          ": ring memory: bird 64x32 rgb565 needs 28.0 KiB, 40.0 KiB of 64.0 KiB are "
                                          "in use; try again later");
    const std::string mjpeg = httpGet(m_server->httpPort(), "/stream.mjpg?width=128&height=64&view=bird");
    EXPECT_EQ(mjpeg.rfind("HTTP/1.0 503 Service Unavailable\r\n", 0), 0U) << mjpeg;
    // Another client of the ring that exists costs nothing.
    auto same = StreamClient::connectUnix(path(), request("bird", 64, 32));
    ASSERT_TRUE(same.ok()) << same.error().message;
    auto s = m_server->stats();
    EXPECT_EQ(s.refused_ring_memory, 2U);
    EXPECT_EQ(s.ring_bytes, 40960U);
    const std::string metrics = m_server->metricsText();
    EXPECT_NE(metrics.find("navmap_stream_refusals_total{reason=\"ring_memory\"} 2\n"), std::string::npos) << metrics;
    EXPECT_NE(metrics.find("navmap_stream_ring_bytes{stat=\"limit\"} 65536\n"), std::string::npos) << metrics;
    // When the ring's clients leave, they may still map it: it stays, counted, and is reused.
    first.value().reset();
    same.value().reset();
    ASSERT_TRUE(waitFor([&] { return m_server->stats().rings == 0 && m_server->stats().rings_idle == 1; }));
    EXPECT_EQ(m_server->stats().ring_bytes, 40960U);
    auto later = StreamClient::connectUnix(path(), request("bird", 64, 32, StreamPayload::Shm, PixelFormat::Rgb565));
    ASSERT_FALSE(later.ok());
    EXPECT_EQ(later.error().message, "handshake refused by " + path() +
                                         ": ring memory: bird 64x32 rgb565 needs 28.0 KiB, 40.0 KiB of 64.0 KiB are "
                                         "in use (1 idle ring kept for reuse); try again later");
    auto again = StreamClient::connectUnix(path(), request("bird", 64, 32));
    ASSERT_TRUE(again.ok()) << again.error().message;
    ASSERT_TRUE(waitFor([&] { return m_server->stats().rings == 1; }));  // counted after the reply
    s = m_server->stats();
    EXPECT_EQ(s.rings, 1U);
    EXPECT_EQ(s.rings_idle, 0U);
    EXPECT_EQ(s.rings_reused, 1U);
    EXPECT_EQ(s.ring_bytes, 40960U);
}

namespace {

// Shared memory of the frame server's rings that this process really has: every mapping of a
// "navmap-ring-" memfd in /proc/self/maps, each memfd (inode) once, at its largest mapping.
// The server maps every ring it keeps whole; a client's mapping keeps a freed ring alive.
struct RingMappings {
    std::size_t bytes = 0;
    std::size_t memfds = 0;
};

RingMappings ringMappings() {
    std::ifstream maps("/proc/self/maps");
    std::map<std::string, std::size_t> by_inode;
    for (std::string line; std::getline(maps, line);) {
        if (line.find("/memfd:navmap-ring-") == std::string::npos) {
            continue;
        }
        std::istringstream in(line);
        std::string range, perms, offset, dev, inode;
        in >> range >> perms >> offset >> dev >> inode;
        const auto dash = range.find('-');
        const std::size_t size =
            std::stoull(range.substr(dash + 1), nullptr, 16) - std::stoull(range.substr(0, dash), nullptr, 16);
        by_inode[dev + ":" + inode] = std::max(by_inode[dev + ":" + inode], size);
    }
    RingMappings r;
    for (const auto& [inode, size] : by_inode) {
        r.bytes += size;
        ++r.memfds;
    }
    return r;
}

}  // namespace

// A client connects, maps the ring, closes the descriptor and disconnects, again and again, over
// profiles of several sizes and both formats: every mapping stays. Freed and made anew each
// cycle, the rings would grow shared memory by one ring per cycle while ring_bytes said 0; kept
// and reused, the rings this process really maps stay under the ceiling and are all counted.
TEST_F(StreamAccessTest, RingMemoryCeilingHoldsAgainstMapCloseDisconnectCycles) {
    FrameServerOptions o = options();
    o.ring_slots = 3;
    o.ring_memory_bytes = 256 * 1024;
    start(o);
    const RingMappings before = ringMappings();
    ASSERT_EQ(before.memfds, 0U);
    struct Mapping {
        void* base;
        std::size_t bytes;
    };
    std::vector<Mapping> kept;  // the client's mappings, alive after their descriptors and connections
    int accepted = 0;
    int refused = 0;
    for (int i = 0; i < 150; ++i) {
        // 8 widths x 2 formats: 16 rings of 28..76 KiB, more than 256 KiB together.
        const int width = 64 + 16 * (i % 8);
        const PixelFormat format = (i / 8) % 2 == 0 ? PixelFormat::Rgba8 : PixelFormat::Rgb565;
        const auto layout = FrameRingLayout::make(3, static_cast<std::uint32_t>(width), 32, format);
        {
            auto raw =
                rawShmHandshake(path(), formatStreamRequest(request("bird", width, 32, StreamPayload::Shm, format)));
            if (raw->reply.find("\"ok\":true") != std::string::npos) {
                ASSERT_GE(raw->ring_fd, 0) << raw->reply;
                void* p = ::mmap(nullptr, layout.total_bytes, PROT_READ, MAP_SHARED, raw->ring_fd, 0);
                ASSERT_NE(p, MAP_FAILED) << std::strerror(errno);
                kept.push_back({p, layout.total_bytes});
                ++accepted;
            } else {
                ASSERT_NE(raw->reply.find("ring memory: bird " + std::to_string(width) + "x32"), std::string::npos)
                    << raw->reply;
                ++refused;
            }
        }  // the descriptor and the connection close here; the mapping stays
        ASSERT_TRUE(waitFor([&] { return m_server->stats().connections == 0; })) << "cycle " << i;
    }
    const auto s = m_server->stats();
    const RingMappings after = ringMappings();
    std::printf("150 cycles: %d accepted, %d refused; rings mapped %zu (%zu bytes), ring_bytes %zu, ceiling %zu\n",
                accepted, refused, after.memfds, after.bytes, s.ring_bytes, o.ring_memory_bytes);
    EXPECT_LE(after.bytes, o.ring_memory_bytes);
    EXPECT_EQ(after.bytes, s.ring_bytes) << "shared memory the server does not count";
    EXPECT_EQ(after.memfds, s.rings_idle);
    EXPECT_EQ(s.rings, 0U);
    EXPECT_GT(refused, 0);
    EXPECT_EQ(s.refused_ring_memory, static_cast<std::uint64_t>(refused));
    EXPECT_EQ(s.rings_reused, static_cast<std::uint64_t>(accepted) - s.rings_idle);
    const std::string metrics = m_server->metricsText();
    EXPECT_NE(metrics.find("navmap_stream_refusals_total{reason=\"ring_memory\"} " + std::to_string(refused) + "\n"),
              std::string::npos)
        << metrics;
    EXPECT_NE(metrics.find("navmap_stream_rings{state=\"idle\"} " + std::to_string(s.rings_idle) + "\n"),
              std::string::npos)
        << metrics;
    EXPECT_NE(metrics.find("navmap_stream_ring_bytes{stat=\"used\"} " + std::to_string(s.ring_bytes) + "\n"),
              std::string::npos)
        << metrics;
    for (const auto& m : kept) {
        ::munmap(m.base, m.bytes);
    }
}

// A ring that comes back from idle gives its new client frames rendered from then on, not the
// frame its last client saw; rings only socket clients used (never handed out) are freed.
TEST_F(StreamAccessTest, AReusedRingStartsWithTheNextFrameAndSocketOnlyRingsAreFreed) {
    FrameServerOptions o = options();
    o.tcp_port = 0;
    start(o);
    const auto px1 = sequencePattern(64, 32, 1);
    {
        auto c = StreamClient::connectUnix(path(), request("bird", 64, 32));
        ASSERT_TRUE(c.ok()) << c.error().message;
        ASSERT_TRUE(waitFor([&] { return m_server->stats().rings == 1; }));  // in the publish set after the reply
        ASSERT_EQ(m_server->publish("bird", FrameView{px1.data(), 64, 32, 0, PixelFormat::Rgba8, 0, 0, {}, {}}), 1U);
        ReceivedFrame f;
        auto r = c.value()->next(f, 3s);
        ASSERT_TRUE(r.ok() && r.value());
        EXPECT_EQ(f.header.sequence, 1U);
    }
    ASSERT_TRUE(waitFor([&] { return m_server->stats().rings_idle == 1; }));
    // Nothing is rendered for an idle ring.
    EXPECT_TRUE(m_server->activeProfiles().empty());
    EXPECT_EQ(m_server->publish("bird", FrameView{px1.data(), 64, 32, 0, PixelFormat::Rgba8, 0, 0, {}, {}}), 0U);
    for (const auto payload : {StreamPayload::Shm, StreamPayload::Raw}) {
        auto c = payload == StreamPayload::Shm
                     ? StreamClient::connectUnix(path(), request("bird", 64, 32, payload))
                     : StreamClient::connectTcp("127.0.0.1", m_server->tcpPort(), request("bird", 64, 32, payload));
        ASSERT_TRUE(c.ok()) << c.error().message;
        ASSERT_TRUE(waitFor([&] { return m_server->stats().rings == 1; }));
        ReceivedFrame f;
        auto r = c.value()->next(f, 300ms);
        ASSERT_TRUE(r.ok()) << r.error().message;
        EXPECT_FALSE(r.value()) << "got frame " << f.header.sequence << " rendered before the ring was idle";
        const std::uint64_t seq = m_server->stats().published + 7;
        const auto px = sequencePattern(64, 32, seq);
        ASSERT_EQ(m_server->publish("bird", FrameView{px.data(), 64, 32, 0, PixelFormat::Rgba8, 0, 0, {}, {}}), 1U);
        r = c.value()->next(f, 3s);
        ASSERT_TRUE(r.ok() && r.value());
        EXPECT_EQ(f.pixels, px);
    }
    ASSERT_TRUE(waitFor([&] { return m_server->stats().rings == 0 && m_server->stats().connections == 0; }));
    EXPECT_EQ(m_server->stats().rings_reused, 2U);
    EXPECT_EQ(m_server->stats().rings_idle, 1U);
    // TCP alone at another size: its ring goes with its client.
    {
        auto c =
            StreamClient::connectTcp("127.0.0.1", m_server->tcpPort(), request("bird", 96, 32, StreamPayload::Raw));
        ASSERT_TRUE(c.ok()) << c.error().message;
        ASSERT_TRUE(waitFor([&] { return m_server->stats().rings == 1; }));
    }
    ASSERT_TRUE(waitFor([&] { return m_server->stats().rings == 0 && m_server->stats().connections == 0; }));
    EXPECT_EQ(m_server->stats().rings_idle, 1U);
    EXPECT_EQ(m_server->stats().ring_bytes, FrameRingLayout::make(3, 64, 32, PixelFormat::Rgba8).total_bytes);
}

TEST_F(StreamAccessTest, NoClientCanMakeTheRingWritable) {
    start(options());
    auto raw = rawShmHandshake(path(), formatStreamRequest(request("bird", 64, 32)));
    ASSERT_NE(raw->reply.find("\"ok\":true"), std::string::npos) << raw->reply;
    ASSERT_GE(raw->ring_fd, 0) << "no descriptor with the reply";
    const int fd = raw->ring_fd;
    const std::size_t bytes = FrameRingLayout::make(3, 64, 32, PixelFormat::Rgba8).total_bytes;
    const int seals = ::fcntl(fd, F_GET_SEALS);
    EXPECT_EQ(seals, F_SEAL_SEAL | F_SEAL_SHRINK | F_SEAL_GROW | F_SEAL_FUTURE_WRITE) << std::hex << seals;

    // The descriptor as received: read-only.
    errno = 0;
    EXPECT_EQ(::mmap(nullptr, bytes, PROT_READ | PROT_WRITE, MAP_SHARED, fd, 0), MAP_FAILED);
    EXPECT_EQ(errno, EACCES);
    void* ro = ::mmap(nullptr, bytes, PROT_READ, MAP_SHARED, fd, 0);
    ASSERT_NE(ro, MAP_FAILED);
    EXPECT_EQ(::mprotect(ro, bytes, PROT_READ | PROT_WRITE), -1);

    // Re-opened read-write through /proc: it opens, but nothing can write through it.
    const std::string proc = "/proc/self/fd/" + std::to_string(fd);
    const int rw = ::open(proc.c_str(), O_RDWR | O_CLOEXEC);
    ASSERT_GE(rw, 0) << std::strerror(errno);
    errno = 0;
    EXPECT_EQ(::mmap(nullptr, bytes, PROT_READ | PROT_WRITE, MAP_SHARED, rw, 0), MAP_FAILED);
    EXPECT_EQ(errno, EPERM);
    void* rw_read = ::mmap(nullptr, bytes, PROT_READ, MAP_SHARED, rw, 0);
    ASSERT_NE(rw_read, MAP_FAILED);
    EXPECT_EQ(::mprotect(rw_read, bytes, PROT_READ | PROT_WRITE), -1);
    const char junk[16] = "drawn by client";
    EXPECT_EQ(::pwrite(rw, junk, sizeof(junk), 4096 + 256), -1);
    EXPECT_EQ(errno, EPERM);
    EXPECT_EQ(::fallocate(rw, FALLOC_FL_PUNCH_HOLE | FALLOC_FL_KEEP_SIZE, 4096, 4096), -1);
    EXPECT_EQ(errno, EPERM);
    EXPECT_EQ(::ftruncate(rw, 0), -1);
    // A private writable mapping is possible, but its writes are copies nobody else sees.
    void* priv = ::mmap(nullptr, bytes, PROT_READ | PROT_WRITE, MAP_PRIVATE, rw, 0);
    ASSERT_NE(priv, MAP_FAILED);
    std::memset(static_cast<std::uint8_t*>(priv) + 4096, 0x5A, bytes - 4096);

    // Frames still arrive whole, to this client and to another one.
    auto other = StreamClient::connectUnix(path(), request("bird", 64, 32));
    ASSERT_TRUE(other.ok()) << other.error().message;
    const auto px = sequencePattern(64, 32, 1);
    ASSERT_EQ(m_server->publish("bird", FrameView{px.data(), 64, 32, 0, PixelFormat::Rgba8, 0, 0, {}, {}}), 1U);
    ReceivedFrame f;
    auto r = other.value()->next(f, 3s);
    ASSERT_TRUE(r.ok() && r.value()) << (r.ok() ? "timeout" : r.error().message);
    EXPECT_EQ(0, std::memcmp(f.pixels.data(), px.data(), px.size()));
    const auto layout = FrameRingLayout::make(3, 64, 32, PixelFormat::Rgba8);
    std::vector<std::uint8_t> mine(layout.pixelBytes());
    FrameHeader h;
    ASSERT_TRUE(FrameRing::readMapped(static_cast<const std::uint8_t*>(ro), layout, 1, &h, mine.data()));
    EXPECT_EQ(mine, px);
    ::munmap(priv, bytes);
    ::munmap(rw_read, bytes);
    ::munmap(ro, bytes);
    ::close(rw);
}

TEST_F(StreamAccessTest, HttpChecksTheHostHeaderAndTheToken) {
    const std::string token = "s3cret-Token_0123456789";
    FrameServerOptions o = options();
    o.http_port = 0;
    o.http_token = token;
    start(o);
    const int port = m_server->httpPort();
    const std::string p = std::to_string(port);
    const auto status = [&](const std::string& head) {
        return httpExchange(port, "GET /status HTTP/1.1\r\n" + head + "\r\n");
    };
    const std::string expected = "(expected 127.0.0.1:" + p + " or localhost:" + p + ")";
    std::string r = status("");
    EXPECT_EQ(r.rfind("HTTP/1.0 400 Bad Request\r\n", 0), 0U) << r;
    EXPECT_NE(r.find("\r\n\r\nmissing Host header\n"), std::string::npos) << r;
    r = status("Host: evil.example:" + p + "\r\nAuthorization: Bearer " + token + "\r\n");
    EXPECT_EQ(r.rfind("HTTP/1.0 421 Misdirected Request\r\n", 0), 0U) << r;
    EXPECT_NE(r.find("\r\n\r\nHost \"evil.example:" + p + "\" is not this server " + expected + "\n"),
              std::string::npos)
        << r;
    r = status("Host: 127.0.0.1:1\r\nAuthorization: Bearer " + token + "\r\n");
    EXPECT_EQ(r.rfind("HTTP/1.0 421", 0), 0U) << r;
    r = status("Host: 127.0.0.1\r\nAuthorization: Bearer " + token + "\r\n");
    EXPECT_EQ(r.rfind("HTTP/1.0 421", 0), 0U) << r;
    // The right host, but no token or a wrong one.
    r = status("Host: localhost:" + p + "\r\n");
    EXPECT_EQ(r.rfind("HTTP/1.0 401 Unauthorized\r\n", 0), 0U) << r;
    EXPECT_NE(r.find("WWW-Authenticate: Bearer realm=\"navmap\"\r\n"), std::string::npos) << r;
    r = status("Host: localhost:" + p + "\r\nAuthorization: Bearer " + token + "x\r\n");
    EXPECT_EQ(r.rfind("HTTP/1.0 401", 0), 0U) << r;
    EXPECT_NE(r.find("\r\n\r\nwrong token\n"), std::string::npos) << r;
    r = httpGet(port, "/status?token=" + token.substr(0, token.size() - 1));
    EXPECT_EQ(r.rfind("HTTP/1.0 401", 0), 0U) << r;
    // Accepted: the header, the query (page, stream, status), localhost in any case.
    r = status("Host: LocalHost:" + p + "\r\nAuthorization: Bearer " + token + "\r\n");
    EXPECT_EQ(r.rfind("HTTP/1.0 200 OK\r\n", 0), 0U) << r;
    r = httpGet(port, "/?token=" + token);
    EXPECT_EQ(r.rfind("HTTP/1.0 200 OK\r\n", 0), 0U) << r;
    EXPECT_NE(r.find("get('token')"), std::string::npos) << "the page hands its token on";
    Publisher pub(*m_server, "bird", 64, 32, 30);
    MjpegReader mjpeg(port, "/stream.mjpg?width=64&height=32&view=bird&token=" + token);
    ASSERT_TRUE(mjpeg.ok()) << mjpeg.responseHead();
    EXPECT_FALSE(mjpeg.next(3s).empty());
    pub.stop();
    const auto s = m_server->stats();
    EXPECT_EQ(s.refused_host, 4U);
    EXPECT_EQ(s.refused_token, 3U);
}

TEST_F(StreamAccessTest, HttpOnEveryAddressTakesTheAddressOfTheConnection) {
    FrameServerOptions o = options();
    o.bind_address = "0.0.0.0";
    o.http_port = 0;
    start(o);
    const int port = m_server->httpPort();
    EXPECT_EQ(httpGet(port, "/status").rfind("HTTP/1.0 200 OK", 0), 0U);  // Host: 127.0.0.1:port
    const std::string r =
        httpExchange(port, "GET /status HTTP/1.1\r\nHost: rebound.example:" + std::to_string(port) + "\r\n\r\n");
    EXPECT_EQ(r.rfind("HTTP/1.0 421", 0), 0U) << r;
}
