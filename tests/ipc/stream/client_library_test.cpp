// SPDX-License-Identifier: Apache-2.0
// libnavmap-client as an HMI integrator uses it: the C example (examples/c_client) against an
// in-process frame server reads the frames in place with the right pixels, waits for a server
// that is not there yet and comes back after a restart; and the shared library links nothing of
// the server (no zlib, no JPEG): only the C and C++ runtime.

#include <gtest/gtest.h>
#include <sys/wait.h>

#include <atomic>
#include <cstdio>
#include <future>
#include <memory>
#include <regex>
#include <set>
#include <sstream>
#include <thread>

#include "navmap/ipc/client/frame_meta.h"
#include "navmap/ipc/stream/frame_server.h"
#include "stream_test_util.h"

using namespace navmap::ipc;
using namespace navmap::stream_test;
using namespace std::chrono_literals;

namespace {

struct ProgramRun {
    int status = -1;
    std::string out;
};

ProgramRun run(const std::string& cmd) {
    ProgramRun r;
    FILE* p = ::popen((cmd + " 2>&1").c_str(), "r");
    if (p == nullptr) {
        return r;
    }
    char buf[4096];
    std::size_t n = 0;
    while ((n = std::fread(buf, 1, sizeof buf, p)) > 0) {
        r.out.append(buf, n);
    }
    const int st = ::pclose(p);
    r.status = WIFEXITED(st) ? WEXITSTATUS(st) : -1;
    return r;
}

/// Frame `seq`'s validity: odd frames stale_pose+degraded (tiles missing), even ones fresh; the
/// pose age is the sequence.
FrameValidity renderValidity(std::uint64_t seq) {
    FrameValidity v;
    v.version = kFrameValidityVersion;
    v.pose_age_ms = static_cast<std::uint32_t>(seq);
    if (seq % 2 == 1) {
        v.flags = kValidityStalePose | kValidityDegraded;
        v.degraded = kDegradedTilesMissing;
    }
    return v;
}

/// Odd frames carry this metadata block (the speed limit their sequence mod 100), even ones none.
std::shared_ptr<const std::vector<std::uint8_t>> renderBlock(std::uint64_t seq) {
    if (seq % 2 == 0) {
        return nullptr;
    }
    FrameMeta m;
    m.has_pose = true;
    m.lat_deg = 42.5;
    m.lon_deg = 1.375;
    m.heading_deg = 271.25;
    m.has_next = true;
    m.next_type = 3;  // turn_left
    m.next_distance_m = 120.5;
    m.next_street = "Carrer Major";
    m.lanes_known = true;
    m.lanes = {kLaneLeft | kLaneRecommended, kLaneStraight};
    m.has_remaining = true;
    m.remaining_m = 900.5;
    m.remaining_s = 60.5;
    m.current_street = "Avinguda Meritxell";
    m.speed_limit_kmh = static_cast<std::uint16_t>(seq % 100 + 1);
    return std::make_shared<const std::vector<std::uint8_t>>(encodeFrameMeta(m));
}

// Publishes the hud profile (800x240, view hud) with every pixel carrying its sequence number,
// and the validity and metadata block above.
class Render {
public:
    explicit Render(FrameServer& server) {
        m_thread = std::thread([this, &server] {
            std::uint64_t seq = 0;
            while (m_run) {
                const auto px = sequencePattern(800, 240, seq + 1);
                // Ring sequences restart with a new ring; the pattern follows them.
                const FrameView view{
                    px.data(), 800, 240, 0, PixelFormat::Rgba8, 0, 0, renderValidity(seq + 1), renderBlock(seq + 1)};
                seq = server.publish("hud", view) > 0 ? seq + 1 : 0;
                std::this_thread::sleep_for(15ms);
            }
        });
    }
    ~Render() {
        m_run = false;
        m_thread.join();
    }

private:
    std::atomic<bool> m_run{true};
    std::thread m_thread;
};

std::unique_ptr<FrameServer> startServer(const std::string& path) {
    FrameServerOptions o;
    o.unix_path = path;
    o.ring_slots = 2;  // as navmapd
    auto s = std::make_unique<FrameServer>(o);
    EXPECT_TRUE(s->start().ok());
    return s;
}

}  // namespace

TEST(ClientLibrary, TheCExampleReadsFramesInPlaceAndReconnects) {
    const std::string path = uniqueSocketPath("c-client");
    // The client starts first: navmapd is not there yet.
    auto client = std::async(std::launch::async,
                             [&] { return run(std::string(NAVMAP_CLIENT_EXAMPLE) + " " + path + " hud 40 30"); });
    std::this_thread::sleep_for(400ms);
    {
        auto server = startServer(path);
        Render render(*server);
        for (int i = 0; i < 300 && server->stats().frames_sent < 20; ++i) std::this_thread::sleep_for(10ms);
        EXPECT_GE(server->stats().frames_sent, 20U);
    }  // the daemon goes away ...
    std::this_thread::sleep_for(300ms);
    auto server = startServer(path);  // ... and comes back
    Render render(*server);
    ASSERT_EQ(client.wait_for(30s), std::future_status::ready);
    const ProgramRun r = client.get();
    EXPECT_EQ(r.status, 0) << r.out;
    EXPECT_NE(r.out.find("waiting: connect(" + path + "): No such file or directory"), std::string::npos) << r.out;
    // Each frame's top-left pixel, read in place in the ring, carries its own sequence number; the
    // two lines after it are that frame's validity and metadata block.
    const std::regex line(R"(frame (\d+) 800x240 stride 3200 pixel (\d+),(\d+),(\d+),255)");
    int frames = 0;
    int blocks = 0;
    std::istringstream in(r.out);
    for (std::string l; std::getline(in, l);) {
        std::smatch m;
        if (std::regex_match(l, m, line)) {
            const auto seq = std::stoull(m[1]);
            EXPECT_EQ(std::stoul(m[2]), seq & 0xff) << l;
            EXPECT_EQ(std::stoul(m[3]), (seq >> 8) & 0xff) << l;
            EXPECT_EQ(std::stoul(m[4]), (seq >> 16) & 0xff) << l;
            ++frames;
            const std::string s = std::to_string(seq);
            std::string validity;
            std::string meta;
            std::getline(in, validity);
            std::getline(in, meta);
            EXPECT_EQ(validity, seq % 2 == 1 ? "validity " + s + " stale_pose+degraded pose_age_ms " + s +
                                                   " degraded tiles_missing"
                                             : "validity " + s + " fresh pose_age_ms " + s + " degraded -");
            const std::string block = "meta " + s +
                                      " pose 42.500000,1.375000 heading 271.25 next turn_left exit 0 in 120.5 m "
                                      "onto \"Carrer Major\" lanes 81,04 remaining 900.5 m 60.5 s street \"Avinguda "
                                      "Meritxell\" speed_limit " +
                                      std::to_string(seq % 100 + 1);
            // A notified frame overwritten before it was read is replaced by the newest, without
            // its block (docs/frame-protocol.md "Metadata block"): "none" is allowed, counted.
            if (seq % 2 == 1 && meta == block) {
                ++blocks;
            } else {
                EXPECT_EQ(meta, "meta " + s + " none") << (seq % 2 == 1 ? "or " + block : "");
            }
        }
    }
    EXPECT_EQ(frames, 40) << r.out;
    EXPECT_GE(blocks, 15) << "odd frames with their block\n" << r.out;
    std::smatch m;
    ASSERT_TRUE(std::regex_search(
        r.out, m, std::regex(R"(frames 40 connects (\d+) failed_attempts (\d+) disconnects (\d+) held_overwritten 0)")))
        << r.out;
    EXPECT_EQ(m[1], "2") << "one connection per server generation";
    EXPECT_GE(std::stoi(m[2]), 1) << "attempts while no server was there";
    EXPECT_EQ(m[3], "1");
}

TEST(ClientLibrary, TheCExampleSaysWhyWhenTheProfileIsRefused) {
    const std::string path = uniqueSocketPath("c-client-refused");
    FrameServerOptions o;
    o.unix_path = path;
    o.rendered_profiles = {{"cluster", "snail", 1280, 480}};
    FrameServer server(o);
    ASSERT_TRUE(server.start().ok());
    const ProgramRun r = run(std::string(NAVMAP_CLIENT_EXAMPLE) + " " + path + " hud 1 1");
    EXPECT_EQ(r.status, 1) << r.out;
    EXPECT_NE(r.out.find("waiting: handshake refused by " + path +
                         ": handshake: hud 800x240 is not rendered here; rendered: cluster (snail 1280x480)"),
              std::string::npos)
        << r.out;
    EXPECT_NE(r.out.find("frames 0 connects 0"), std::string::npos) << r.out;
}

TEST(ClientLibrary, LinksOnlyTheCAndCxxRuntime) {
    const ProgramRun r = run(std::string("readelf -d ") + NAVMAP_CLIENT_LIBRARY);
    ASSERT_EQ(r.status, 0) << r.out;
    std::set<std::string> needed;
    const std::regex lib(R"(\(NEEDED\)\s+Shared library: \[([^\]]+)\])");
    for (auto it = std::sregex_iterator(r.out.begin(), r.out.end(), lib); it != std::sregex_iterator(); ++it) {
        needed.insert((*it)[1]);
    }
    std::printf("libnavmap-client NEEDED:");
    for (const auto& n : needed) std::printf(" %s", n.c_str());
    std::printf("\n");
    const std::set<std::string> runtime = {"libstdc++.so.6", "libm.so.6", "libgcc_s.so.1", "libc.so.6"};
    for (const auto& n : needed) {
        EXPECT_TRUE(runtime.count(n) == 1) << "libnavmap-client needs " << n << ", which is not the C or C++ runtime";
    }
    EXPECT_EQ(needed.count("libc.so.6"), 1U);
    EXPECT_NE(r.out.find("(SONAME)             Library soname: [libnavmap-client.so.0]"), std::string::npos) << r.out;
    // ldd: everything resolves, and neither zlib nor libturbojpeg comes in indirectly.
    const ProgramRun ldd = run(std::string("ldd ") + NAVMAP_CLIENT_LIBRARY);
    ASSERT_EQ(ldd.status, 0) << ldd.out;
    EXPECT_EQ(ldd.out.find("not found"), std::string::npos) << ldd.out;
    EXPECT_EQ(ldd.out.find("libz."), std::string::npos) << ldd.out;
    EXPECT_EQ(ldd.out.find("turbojpeg"), std::string::npos) << ldd.out;
    // Its exports are the documented API: the C functions and navmap::ipc's client classes, no
    // server code (FrameServer) and no private helpers (stream_detail).
    const ProgramRun nm = run(std::string("nm -D --defined-only -C ") + NAVMAP_CLIENT_LIBRARY);
    ASSERT_EQ(nm.status, 0) << nm.out;
    EXPECT_NE(nm.out.find("navmap_client_next_frame"), std::string::npos);
    EXPECT_NE(nm.out.find("navmap::ipc::StreamClient::nextHeld"), std::string::npos);
    for (const char* symbol :
         {"navmap_client_request_meta", "navmap_client_frame_validity", "navmap_client_frame_meta",
          "navmap_client_request_dmabuf", "navmap_client_payload", "navmap_client_payload_fallback",
          "navmap::ipc::decodeFrameMeta", "navmap::ipc::encodeFrameMeta", "navmap_client_frame_dmabuf",
          "navmap::ipc::decodeDmabufBlock", "navmap::ipc::StreamClient::nextDmabuf"}) {
        EXPECT_NE(nm.out.find(symbol), std::string::npos) << symbol;
    }
    EXPECT_EQ(nm.out.find("FrameServer"), std::string::npos);
    EXPECT_EQ(nm.out.find("stream_detail"), std::string::npos);
}
