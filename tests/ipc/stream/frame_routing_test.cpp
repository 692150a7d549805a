// SPDX-License-Identifier: Apache-2.0
// Frames routed by profile, frames held in place (zero copy) and the reconnecting client, over
// real sockets in one process (docs/frame-protocol.md "Profiles", "Holding a frame").

#include <gtest/gtest.h>
#include <sys/mman.h>
#include <unistd.h>

#include <cstring>
#include <thread>

#include "navmap/ipc/client/frame_ring.h"
#include "navmap/ipc/client/reconnecting_client.h"
#include "navmap/ipc/client/stream_client.h"
#include "navmap/ipc/stream/frame_server.h"
#include "stream_test_util.h"
#include "wait_for.h"

using namespace navmap::ipc;
using namespace navmap::stream_test;
using namespace std::chrono_literals;

namespace {

StreamRequest named(const std::string& name, bool hold = false) {
    const int w = 64;
    const int h = 32;
    const std::string view = "bird";
    StreamRequest r;
    r.hold = hold;
    r.profile.name = name;
    r.profile.width = w;
    r.profile.height = h;
    r.profile.view = view;
    r.profile.fps = 0;
    return r;
}

// A frame of one colour, so that two profiles' frames differ in every pixel.
std::vector<std::uint8_t> solid(int w, int h, std::uint8_t r, std::uint8_t g, std::uint8_t b) {
    std::vector<std::uint8_t> px(static_cast<std::size_t>(w) * h * 4);
    for (std::size_t i = 0; i < px.size(); i += 4) {
        px[i] = r;
        px[i + 1] = g;
        px[i + 2] = b;
        px[i + 3] = 255;
    }
    return px;
}

bool publish(FrameServer& server, const std::string& profile, const std::vector<std::uint8_t>& px, int w = 64,
             int h = 32) {
    return server.publish(profile, FrameView{px.data(), w, h, 0, PixelFormat::Rgba8, 0, 0, {}, {}}) > 0;
}

class FrameServerFixture : public ::testing::Test {
protected:
    void start(FrameServerOptions o) {
        o.unix_path = m_path;
        m_server = std::make_unique<FrameServer>(std::move(o));
        auto s = m_server->start();
        ASSERT_TRUE(s.ok()) << s.message();
    }
    void TearDown() override {
        m_server.reset();
        EXPECT_EQ(countOpenFds(), m_fds) << "descriptors leaked";
    }
    template <typename Pred>
    static bool waitFor(Pred pred) {
        return navmap::test::waitFor(pred, std::chrono::seconds(3), std::chrono::milliseconds(10));
    }
    int m_fds = countOpenFds();
    std::string m_path = uniqueSocketPath("routing");
    std::unique_ptr<FrameServer> m_server;
};

}  // namespace

TEST_F(FrameServerFixture, TwoProfilesOfOneViewAndSizeGetTheirOwnFrames) {
    // Same view and size, different style (one with glowing roads, one without): two streams.
    FrameServerOptions o;
    o.rendered_profiles = {{"glow", "bird", 64, 32}, {"plain", "bird", 64, 32}};
    start(o);
    auto glow = StreamClient::connectUnix(m_path, named("glow"));
    auto plain = StreamClient::connectUnix(m_path, named("plain"));
    ASSERT_TRUE(glow.ok()) << glow.error().message;
    ASSERT_TRUE(plain.ok()) << plain.error().message;
    ASSERT_TRUE(waitFor([&] { return m_server->stats().rings == 2; }));  // the server thread counts after its reply
    const auto active = m_server->activeProfiles();
    ASSERT_EQ(active.size(), 2U);
    EXPECT_EQ(active[0].profile, "glow");
    EXPECT_EQ(active[1].profile, "plain");
    const auto red = solid(64, 32, 250, 10, 10);
    const auto blue = solid(64, 32, 10, 10, 250);
    int glow_frames = 0;
    int plain_frames = 0;
    ReceivedFrame f;
    for (int round = 0; round < 20; ++round) {
        // The render loop publishes both profiles each tick, as navmapd does.
        ASSERT_TRUE(publish(*m_server, "glow", red));
        ASSERT_TRUE(publish(*m_server, "plain", blue));
        for (auto* c : {glow.value().get(), plain.value().get()}) {
            auto r = c->next(f, 1s);
            ASSERT_TRUE(r.ok()) << r.error().message;
            if (!r.value()) continue;
            const bool is_glow = c == glow.value().get();
            // Every pixel is the client's own profile's colour: never the other profile's frame.
            const auto& want = is_glow ? red : blue;
            ASSERT_EQ(f.pixels, want) << (is_glow ? "glow" : "plain") << " client got frame " << f.header.sequence
                                      << " with pixel 0 = " << int(f.pixels[0]) << "," << int(f.pixels[2]);
            (is_glow ? glow_frames : plain_frames)++;
        }
    }
    EXPECT_GE(glow_frames, 10);
    EXPECT_GE(plain_frames, 10);
}

TEST_F(FrameServerFixture, ARequestResolvesByNameThenByViewAndSize) {
    FrameServerOptions o;
    o.rendered_profiles = {{"glow", "bird", 64, 32}, {"plain", "bird", 64, 32}};
    start(o);
    // Another name: the first rendered profile of that view and size.
    auto anon = StreamClient::connectUnix(m_path, named("some-recorder"));
    ASSERT_TRUE(anon.ok()) << anon.error().message;
    ASSERT_TRUE(waitFor([&] { return m_server->activeProfiles().size() == 1; }));
    EXPECT_EQ(m_server->activeProfiles()[0].profile, "glow");
    // A rendered name with another size is refused, naming what the profile is.
    StreamRequest big = named("plain");
    big.profile.width = 128;
    big.profile.height = 64;
    auto wrong = StreamClient::connectUnix(m_path, big);
    ASSERT_FALSE(wrong.ok());
    EXPECT_EQ(wrong.error().message, "handshake refused by " + m_path +
                                         ": handshake: profile plain is rendered as bird 64x32, not bird 128x64");
    EXPECT_EQ(m_server->stats().refused_not_rendered, 1U);
}

TEST_F(FrameServerFixture, AHeldFrameStaysUnchangedWhileTheRingMovesOn) {
    FrameServerOptions o;
    o.ring_slots = 2;  // navmapd's rings: a held frame leaves one slot for the writer
    start(o);
    auto holder = StreamClient::connectUnix(m_path, named("h", true));
    auto copier = StreamClient::connectUnix(m_path, named("h"));
    ASSERT_TRUE(holder.ok() && copier.ok());
    ASSERT_TRUE(publish(*m_server, "bird", sequencePattern(64, 32, 1)));
    HeldFrame held;
    auto r = holder.value()->nextHeld(held, 2s);
    ASSERT_TRUE(r.ok() && r.value()) << (r.ok() ? "timeout" : r.error().message);
    ASSERT_EQ(held.header.sequence, 1U);
    const std::vector<std::uint8_t> first(held.pixels, held.pixels + held.header.pixelBytes());
    EXPECT_EQ(first, sequencePattern(64, 32, 1));
    // The render loop goes on; the other client copies every frame. The held slot is never taken.
    ReceivedFrame f;
    for (std::uint64_t seq = 2; seq <= 40; ++seq) {
        ASSERT_TRUE(publish(*m_server, "bird", sequencePattern(64, 32, seq)));
        auto c = copier.value()->next(f, 1s);
        ASSERT_TRUE(c.ok()) << c.error().message;
        ASSERT_TRUE(std::equal(first.begin(), first.end(), held.pixels)) << "the held frame changed at " << seq;
    }
    EXPECT_EQ(f.pixels, sequencePattern(64, 32, f.header.sequence));  // the copier saw the new frames
    EXPECT_GT(f.header.sequence, 30U);
    auto released = holder.value()->release();
    ASSERT_TRUE(released.ok());
    EXPECT_TRUE(released.value()) << "release says the held frame was overwritten";
    EXPECT_EQ(m_server->stats().pinned_overwrites, 0U);
    // After the release the holder gets the newest frame again (notified on its ack).
    r = holder.value()->nextHeld(held, 2s);
    ASSERT_TRUE(r.ok() && r.value());
    EXPECT_EQ(held.header.sequence, 40U);
    EXPECT_EQ(0, std::memcmp(held.pixels, sequencePattern(64, 32, 40).data(), held.header.pixelBytes()));
}

TEST_F(FrameServerFixture, WhenEverySlotIsHeldTheStreamGoesOnAndTheHolderIsTold) {
    FrameServerOptions o;
    o.ring_slots = 2;
    start(o);
    auto a = StreamClient::connectUnix(m_path, named("h", true));
    auto b = StreamClient::connectUnix(m_path, named("h", true));
    auto watcher = StreamClient::connectUnix(m_path, named("h"));
    ASSERT_TRUE(a.ok() && b.ok() && watcher.ok());
    HeldFrame ha;
    HeldFrame hb;
    ASSERT_TRUE(publish(*m_server, "bird", sequencePattern(64, 32, 1)));
    auto r = a.value()->nextHeld(ha, 2s);
    ASSERT_TRUE(r.ok() && r.value());
    ASSERT_TRUE(publish(*m_server, "bird", sequencePattern(64, 32, 2)));
    // b was notified of frame 1 too; it takes that one back and holds frame 2.
    r = b.value()->nextHeld(hb, 2s);
    ASSERT_TRUE(r.ok() && r.value());
    if (hb.header.sequence == 1) {
        r = b.value()->nextHeld(hb, 2s);
        ASSERT_TRUE(r.ok() && r.value());
    }
    ASSERT_EQ(ha.header.sequence, 1U);
    ASSERT_EQ(hb.header.sequence, 2U);
    // Both slots are held: the writer must still write (a client may never stop the stream).
    ASSERT_TRUE(publish(*m_server, "bird", sequencePattern(64, 32, 3)));
    ReceivedFrame f;
    bool saw_three = false;
    for (int i = 0; i < 5 && !saw_three; ++i) {
        auto w = watcher.value()->next(f, 1s);
        ASSERT_TRUE(w.ok()) << w.error().message;
        saw_three = w.value() && f.header.sequence == 3;
    }
    EXPECT_TRUE(saw_three);
    EXPECT_EQ(f.pixels, sequencePattern(64, 32, 3));
    // The oldest held frame (1, slot of the oldest write) was overwritten; its holder learns it.
    auto ra = a.value()->release();
    auto rb = b.value()->release();
    ASSERT_TRUE(ra.ok() && rb.ok());
    EXPECT_FALSE(ra.value());
    EXPECT_TRUE(rb.value());
    EXPECT_EQ(a.value()->stats().held_overwritten, 1U);
    EXPECT_TRUE([&] {
        for (int i = 0; i < 100 && m_server->stats().pinned_overwrites != 1; ++i) std::this_thread::sleep_for(10ms);
        return m_server->stats().pinned_overwrites == 1;
    }());
    EXPECT_NE(m_server->metricsText().find("navmap_stream_held_frames_overwritten_total 1\n"), std::string::npos);
}

TEST_F(FrameServerFixture, TheReconnectingClientWaitsForTheServerAndComesBackAfterARestart) {
    ReconnectOptions ro;
    ro.unix_path = m_path;
    ro.request = named("r");
    ro.initial_backoff = 20ms;
    ro.max_backoff = 100ms;
    ro.connect_timeout = 500ms;
    ReconnectingClient client(ro);
    ReceivedFrame f;
    // No server yet: no frame, no exception, the reason at hand, attempts backing off.
    EXPECT_FALSE(client.next(f, 300ms));
    EXPECT_FALSE(client.connected());
    EXPECT_EQ(client.lastError(), "connect(" + m_path + "): No such file or directory");
    const auto failed_before = client.reconnectStats().failed_attempts;
    EXPECT_GE(failed_before, 2U);
    EXPECT_LE(failed_before, 8U);  // 20, 40, 80, 100 ms ... not a busy loop
    for (int generation = 1; generation <= 2; ++generation) {
        start(FrameServerOptions{});
        std::atomic<bool> run{true};
        std::thread render([&] {
            // Ring sequences start at 1 when the client's ring is made; the pattern follows them.
            for (std::uint64_t seq = 0; run;) {
                seq = publish(*m_server, "bird", sequencePattern(64, 32, seq + 1)) ? seq + 1 : 0;
                std::this_thread::sleep_for(10ms);
            }
        });
        int frames = 0;
        for (int i = 0; i < 100 && frames < 5; ++i) {
            if (client.next(f, 200ms)) {
                ++frames;
                ASSERT_EQ(f.pixels, sequencePattern(64, 32, f.header.sequence));
            }
        }
        run = false;
        render.join();
        EXPECT_EQ(frames, 5) << "generation " << generation << ": " << client.lastError();
        EXPECT_EQ(client.reconnectStats().connects, static_cast<std::uint64_t>(generation));
        m_server.reset();  // the daemon goes away (restart)
    }
    EXPECT_FALSE(client.next(f, 100ms));
    EXPECT_FALSE(client.connected());
    EXPECT_FALSE(client.lastError().empty());
    EXPECT_EQ(client.reconnectStats().disconnects, 2U);
    // A copying client may not hold frames: the server would not keep them for it.
    HeldFrame held;
    EXPECT_FALSE(client.nextHeld(held, 10ms));
    EXPECT_EQ(client.lastError(),
              "nextHeld() needs request.hold (payload shm: the frame stays in the shared-memory ring)");
}

TEST(FrameRingMapping, AClientChecksTheRingHeaderItMapped) {
    auto ring = FrameRing::create("navmap-test-ring", 2, 16, 16, PixelFormat::Rgba8);
    ASSERT_TRUE(ring.ok()) << ring.error().message;
    auto ro = ring.value()->openReadOnly();
    ASSERT_TRUE(ro.ok());
    const FrameRingLayout& l = ring.value()->layout();
    void* p = ::mmap(nullptr, l.total_bytes, PROT_READ, MAP_SHARED, ro.value(), 0);
    ::close(ro.value());
    ASSERT_NE(p, MAP_FAILED);
    const auto* base = static_cast<const std::uint8_t*>(p);
    EXPECT_TRUE(FrameRing::checkMapped(base, l).ok());
    std::uint32_t version = 0;
    std::memcpy(&version, base + 4, sizeof version);
    EXPECT_EQ(version, kRingVersion);
    FrameRingLayout other = FrameRingLayout::make(3, 16, 16, PixelFormat::Rgba8);
    EXPECT_EQ(FrameRing::checkMapped(base, other).message(), "ring header: geometry differs from the handshake");
    ::munmap(p, l.total_bytes);
}
