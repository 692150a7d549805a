// SPDX-License-Identifier: Apache-2.0
// The client library against a server that lies (EvilStreamServer): a ring descriptor that is a
// regular file or a memfd that shrinks under the mapping, a memfd the server can still write or
// that is too short, replies with wrong JSON types and sizes out of range. The C++ client and
// the C API each run in a child process, so that a signal (SIGBUS, an abort) shows as the
// child's end instead of ending the test; each must end with an error return naming the problem.
// navmap-view and the C example (navmap-client-example) run as programs: exit status 1 and the
// reason on stderr / stdout, never a signal.

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstring>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "evil_stream_server.h"
#include "navmap/ipc/client/frame_meta.h"
#include "navmap/ipc/client/frame_ring.h"
#include "navmap/ipc/client/stream_client.h"
#include "navmap_client.h"

using namespace navmap::ipc;
using namespace navmap::stream_test;
using namespace std::chrono_literals;

namespace {

StreamRequest smallRequest() {
    StreamRequest r;
    r.profile.name = "evil";
    r.profile.width = 64;
    r.profile.height = 32;
    r.profile.view = "bird";
    r.payload = StreamPayload::Shm;
    return r;
}

// The C++ client: connect, then wait for a frame. "frame", or "error: <message>".
std::string cppClient(const std::string& path) {
    auto c = StreamClient::connectUnix(path, smallRequest(), 3s);
    if (!c) {
        return "error: " + c.error().message;
    }
    ReceivedFrame f;
    auto r = c.value()->next(f, 3s);
    if (!r) {
        return "error: " + r.error().message;
    }
    return r.value() ? "frame" : "timeout";
}

// The C API (navmap_client.h, frames held in place): "frame", or "error: <last error>".
std::string cClient(const std::string& path) {
    navmap_client_options o;
    navmap_client_options_init(&o);
    o.socket_path = path.c_str();
    o.profile = "evil";
    o.width = 64;
    o.height = 32;
    o.view = "bird";
    o.connect_timeout_ms = 3000;
    const char* error = nullptr;
    navmap_client* c = navmap_client_create(&o, &error);
    if (c == nullptr) {
        return std::string("create: ") + error;
    }
    navmap_frame f;
    const int r = navmap_client_next_frame(c, 400, &f);
    std::string out;
    if (r == NAVMAP_CLIENT_FRAME) {
        // Read the frame in place, as a display does: all of it.
        unsigned sum = 0;
        for (std::size_t i = 0; i < static_cast<std::size_t>(f.stride) * f.height; ++i) {
            sum += f.pixels[i];
        }
        out = "frame " + std::to_string(f.sequence) + " sum " + std::to_string(sum);
        navmap_client_release_frame(c, &f);
    } else {
        out = "error: " + std::string(navmap_client_last_error(c));
    }
    navmap_client_destroy(c);
    return out;
}

struct EvilCase {
    EvilBehaviour behaviour;
    std::string error;  ///< what the client's error message must contain after "handshake with PATH: "
};

std::string describe(const EvilCase& c) {
    return std::string(evilRingName(c.behaviour.ring)) +
           (c.behaviour.patch.empty() ? "" : " patch " + c.behaviour.patch) +
           (c.behaviour.line.empty() ? "" : " line " + c.behaviour.line);
}

std::vector<EvilCase> evilCases() {
    const auto total = FrameRingLayout::make(3, 64, 32, PixelFormat::Rgba8).total_bytes;
    const auto shm = [](EvilRing ring) {
        EvilBehaviour b;
        b.ring = ring;
        return b;
    };
    const auto patch = [](std::string p) {
        EvilBehaviour b;
        b.patch = std::move(p);
        return b;
    };
    const auto line = [](std::string l) {
        EvilBehaviour b;
        b.line = std::move(l);
        return b;
    };
    return {
        // The descriptor.
        {shm(EvilRing::RegularFile), "ring descriptor is not a memfd"},
        {shm(EvilRing::UnsealedMemfd),
         "ring descriptor is not sealed: seals 0x1, need F_SEAL_SHRINK, F_SEAL_GROW and F_SEAL_WRITE or "
         "F_SEAL_FUTURE_WRITE"},
        {shm(EvilRing::WritableMemfd), "ring descriptor is not sealed: seals 0x7"},
        {shm(EvilRing::ShortMemfd), "ring layout: shared memory has " + std::to_string(total - 4096) +
                                        " bytes, layout needs " + std::to_string(total)},
        {shm(EvilRing::None), "no shared-memory descriptor in the reply"},
        // Wrong JSON types.
        {patch(R"({"profile":{"width":"x"}})"), R"(reply: "profile.width" must be an integer)"},
        {patch(R"({"profile":{"height":[1]}})"), R"(reply: "profile.height" must be an integer)"},
        {patch(R"({"profile":{"fps":1.5}})"), R"(reply: "profile.fps" must be an integer)"},
        {patch(R"({"profile":{"view":7}})"), R"(reply: "profile.view" must be a string)"},
        {patch(R"({"profile":{"name":{}}})"), R"(reply: "profile.name" must be a string)"},
        {patch(R"({"profile":{"format":true}})"), R"(reply: "profile.format" must be a string)"},
        {patch(R"({"profile":"x"})"), R"(reply: "profile" must be an object)"},
        {patch(R"({"ring":"x"})"), R"(reply: "ring" must be an object)"},
        {patch(R"({"ring":{"slots":"x"}})"), R"(reply: "ring.slots" must be an integer)"},
        {patch(R"({"ring":{"total_bytes":"x"}})"), R"(reply: "ring.total_bytes" must be an integer)"},
        {patch(R"({"ring":{"slot_bytes":2.5}})"), R"(reply: "ring.slot_bytes" must be an integer)"},
        {patch(R"({"stride":"x"})"), R"(reply: "stride" must be an integer)"},
        {patch(R"({"ok":"yes"})"), R"(reply: "ok" must be true or false)"},
        {patch(R"({"payload":3})"), R"(reply: "payload" must be a string)"},
        {line("[1,2,3]"), "reply: not a JSON object"},
        {line(R"({"ok":true,"profile":{)"), "reply: not a JSON object"},
        // Out of range.
        {patch(R"({"profile":{"width":0}})"), R"(reply: "profile.width" = 0 outside [16, 4096])"},
        {patch(R"({"profile":{"width":-1}})"), R"(reply: "profile.width" = -1 outside [16, 4096])"},
        {patch(R"({"profile":{"height":100000}})"), R"(reply: "profile.height" = 100000 outside [16, 4096])"},
        {patch(R"({"profile":{"width":18446744073709551615}})"),
         R"(reply: "profile.width" = 18446744073709551615 outside [16, 4096])"},
        {patch(R"({"profile":{"fps":-3}})"), R"(reply: "profile.fps" = -3 outside [0, 1000])"},
        {patch(R"({"profile":{"width":128}})"), "reply: granted 128x32 rgba8, asked for 64x32 rgba8"},
        {patch(R"({"profile":{"format":"rgb565"}})"), "reply: granted 64x32 rgb565, asked for 64x32 rgba8"},
        {patch(R"({"profile":{"view":"sideways"}})"), R"(reply: "profile.view" must be bird, snail or hud)"},
        {patch(R"({"ring":{"slots":0}})"), R"(reply: "ring.slots" = 0 outside [1, 64])"},
        {patch(R"({"ring":{"slots":65}})"), R"(reply: "ring.slots" = 65 outside [1, 64])"},
        {patch(R"({"ring":{"slots":4}})"),
         R"(reply: "ring.total_bytes" = )" + std::to_string(total) + ", the layout of 4 slots of 64x32 rgba8 has " +
             std::to_string(FrameRingLayout::make(4, 64, 32, PixelFormat::Rgba8).total_bytes)},
        {patch(R"({"ring":{"total_bytes":1099511627776}})"),
         R"(reply: "ring.total_bytes" = 1099511627776, the layout of 3 slots of 64x32 rgba8 has )" +
             std::to_string(total)},
        {patch(R"({"ring":{"total_bytes":-5}})"), R"(reply: "ring.total_bytes" = -5 outside [0, )"},
        {patch(R"({"ring":{"total_bytes":null}})"), R"(reply: "ring.total_bytes" missing)"},
        {patch(R"({"ring":null})"), R"(reply: payload shm without "ring")"},
        {patch(R"({"stride":1})"), R"(reply: "stride" = 1, expected 256)"},
        {patch(R"({"header_bytes":81})"), R"(reply: "header_bytes" = 81, expected 80)"},
        {patch(R"({"payload":"raw"})"), R"(reply: payload "raw", asked for "shm")"},
        {patch(R"({"version":2})"), R"(reply: "version" = 2 outside [1, 1])"},
    };
}

}  // namespace

// The honest server of this file is a real one: the same client gets its frame from it, so each
// refusal below comes from what the case changes, nothing else.
TEST(EvilServer, AnHonestReplyGivesAFrame) {
    EvilStreamServer server({});
    const auto cpp = runInChild([&] { return cppClient(server.path()); });
    EXPECT_EQ(cpp.how, "exit 0");
    EXPECT_EQ(cpp.result, "frame");
    const auto c = runInChild([&] { return cClient(server.path()); });
    EXPECT_EQ(c.how, "exit 0");
    // 64x32 pixels of sequencePattern(1): R = 1, G = B = 0, A = 255.
    EXPECT_EQ(c.result, "frame 1 sum " + std::to_string(64 * 32 * 256));
}

TEST(EvilServer, TheCppClientReturnsAnErrorForEveryLie) {
    for (const auto& ec : evilCases()) {
        SCOPED_TRACE(describe(ec));
        EvilStreamServer server(ec.behaviour);
        const auto out = runInChild([&] { return cppClient(server.path()); });
        EXPECT_EQ(out.how, "exit 0") << "the client died instead of returning an error";
        EXPECT_EQ(out.result.rfind("error: handshake with " + server.path() + ": ", 0), 0U) << out.result;
        EXPECT_NE(out.result.find(ec.error), std::string::npos) << out.result;
        // Refused before mapping: nothing was left to shrink under a mapping.
        EXPECT_EQ(server.truncations(), 0);
    }
}

TEST(EvilServer, TheCApiReturnsDisconnectedWithTheReason) {
    for (const auto& ec : evilCases()) {
        SCOPED_TRACE(describe(ec));
        EvilStreamServer server(ec.behaviour);
        const auto out = runInChild([&] { return cClient(server.path()); });
        EXPECT_EQ(out.how, "exit 0") << "the client died instead of returning an error";
        EXPECT_EQ(out.result.rfind("error: handshake with " + server.path() + ": ", 0), 0U) << out.result;
        EXPECT_NE(out.result.find(ec.error), std::string::npos) << out.result;
        EXPECT_GE(server.handshakes(), 1);
        EXPECT_EQ(server.truncations(), 0);
    }
}

// A refusal is still read as one, and its text reaches the caller.
TEST(EvilServer, ARefusalKeepsTheServersWords) {
    EvilStreamServer server({EvilRing::None, "", R"({"ok":false,"error":"ring memory: try again later"})"});
    const auto out = runInChild([&] { return cppClient(server.path()); });
    EXPECT_EQ(out.how, "exit 0");
    EXPECT_EQ(out.result, "error: handshake refused by " + server.path() + ": ring memory: try again later");
    EvilStreamServer silent({EvilRing::None, "", R"({"ok":false,"error":5})"});
    const auto out2 = runInChild([&] { return cppClient(silent.path()); });
    EXPECT_EQ(out2.result, "error: handshake refused by " + silent.path() + ": ?");
}

// The programs: a subset of the lies (each descriptor kind, a wrong type in the profile and in
// the ring, sizes out of range), each with the honest reply first as a control.
std::vector<EvilCase> programCases() {
    std::vector<EvilCase> picked;
    for (const auto& ec : evilCases()) {
        const auto& p = ec.behaviour.patch;
        if (ec.behaviour.ring != EvilRing::Sealed || p == R"({"profile":{"width":"x"}})" || p == R"({"ring":"x"})" ||
            p == R"({"ring":{"slots":65}})" || p == R"({"ring":{"total_bytes":1099511627776}})" ||
            p == R"({"profile":{"width":18446744073709551615}})") {
            picked.push_back(ec);
        }
    }
    return picked;
}

TEST(EvilServer, NavmapViewExitsWithOneAndTheReason) {
    const std::string args = " --profile evil --width 64 --height 32 --view bird --frames 1";
    {
        EvilStreamServer honest({});
        const auto out = runCommand(std::string(NAVMAP_VIEW_EXE) + " --unix " + honest.path() + args);
        EXPECT_EQ(out.how, "exit 0") << out.result;
        EXPECT_NE(out.result.find("frames 1 "), std::string::npos) << out.result;
    }
    for (const auto& ec : programCases()) {
        SCOPED_TRACE(describe(ec));
        EvilStreamServer server(ec.behaviour);
        const auto out = runCommand(std::string(NAVMAP_VIEW_EXE) + " --unix " + server.path() + args);
        EXPECT_EQ(out.how, "exit 1") << out.result;
        EXPECT_EQ(out.result.rfind("navmap-view: handshake with " + server.path() + ": ", 0), 0U) << out.result;
        EXPECT_NE(out.result.find(ec.error), std::string::npos) << out.result;
        EXPECT_EQ(server.truncations(), 0);
    }
}

TEST(EvilServer, TheCExampleWaitsWithTheReasonAndExitsWithOne) {
    // navmap-client-example SOCKET PROFILE FRAMES SECONDS: the hud profile (800x240), one frame
    // wanted within one second. Its "waiting:" line is navmap_client_last_error(); the exact
    // words per lie are checked through the C API above (they name the 64x32 request there).
    {
        EvilStreamServer honest({});
        const auto out = runCommand(std::string(NAVMAP_CLIENT_EXAMPLE) + " " + honest.path() + " hud 1 5");
        EXPECT_EQ(out.how, "exit 0") << out.result;
        EXPECT_NE(out.result.find("frame 1 800x240 stride 3200 pixel 1,0,0,255"), std::string::npos) << out.result;
    }
    for (const auto& ec : programCases()) {
        SCOPED_TRACE(describe(ec));
        EvilStreamServer server(ec.behaviour);
        const auto out = runCommand(std::string(NAVMAP_CLIENT_EXAMPLE) + " " + server.path() + " hud 1 1");
        EXPECT_EQ(out.how, "exit 1") << out.result;
        EXPECT_NE(out.result.find("waiting: handshake with " + server.path() + ": "), std::string::npos) << out.result;
        EXPECT_NE(out.result.find("frames 0 connects 0 failed_attempts "), std::string::npos) << out.result;
        EXPECT_EQ(server.truncations(), 0);
    }
}

// --- Frame validity and the metadata block (docs/frame-protocol.md): a client that asked for
// metadata checks every block and every validity byte like the rest of what the server sends.

namespace {

FrameMeta fullMeta() {
    FrameMeta m;
    m.has_pose = true;
    m.lat_deg = 42.5063;
    m.lon_deg = 1.5218;
    m.heading_deg = 87.5;
    m.pose_time_ns = 1700000000123456789LL;
    m.has_next = true;
    m.next_type = 12;  // roundabout
    m.next_exit = 2;
    m.next_distance_m = 312.5;
    m.next_street = "Avinguda Meritxell";
    m.has_remaining = true;
    m.remaining_m = 4210.0;
    m.remaining_s = 420.0;
    m.current_street = "Carrer de la Unió";
    return m;
}

// The C++ client asking for metadata: "frame <validity> <next street>|<current street>", or "error: ...".
std::string cppMetaClient(const std::string& path, bool ask = true) {
    StreamRequest request = smallRequest();
    request.meta = ask;
    auto c = StreamClient::connectUnix(path, request, 3s);
    if (!c) {
        return "error: " + c.error().message;
    }
    ReceivedFrame f;
    auto r = c.value()->next(f, 3s);
    if (!r) {
        return "error: " + r.error().message;
    }
    if (!r.value()) {
        return "timeout";
    }
    return "frame " + validityText(f.header.validity) + " " +
           (f.meta ? f.meta->next_street + "|" + f.meta->current_street : std::string("no meta"));
}

// The C API asking for metadata: "frame <flags> <age> <next type> <next street>|<current street>".
std::string cMetaClient(const std::string& path) {
    navmap_client_options o;
    navmap_client_options_init(&o);
    o.socket_path = path.c_str();
    o.profile = "evil";
    o.width = 64;
    o.height = 32;
    o.view = "bird";
    o.connect_timeout_ms = 3000;
    o.reconnect_initial_ms = 5000;  // no second attempt within the wait: last_error is the first one's
    navmap_client* c = navmap_client_create(&o, nullptr);
    if (c == nullptr || navmap_client_request_meta(c, 1) != 0) {
        return "create failed";
    }
    navmap_frame f;
    std::string out;
    if (navmap_client_next_frame(c, 400, &f) == NAVMAP_CLIENT_FRAME) {
        navmap_frame_validity v;
        navmap_frame_meta m;
        const int vr = navmap_client_frame_validity(c, &f, &v);
        const int mr = navmap_client_frame_meta(c, &f, &m);
        out = "frame " + std::to_string(vr) + " " + std::to_string(v.flags) + " " + std::to_string(v.pose_age_ms) +
              " " + std::to_string(mr) + " " + m.next_type + " " + m.next_street + "|" + m.current_street + " lanes " +
              std::to_string(m.lane_count);
        navmap_client_release_frame(c, &f);
    } else {
        out = "error: " + std::string(navmap_client_last_error(c));
    }
    navmap_client_destroy(c);
    return out;
}

EvilBehaviour withMeta(std::vector<std::uint8_t> block, int meta_bytes = -1,
                       std::function<void(std::uint8_t*)> edit = {}) {
    EvilBehaviour b;
    b.meta = std::move(block);
    b.meta_bytes = meta_bytes;
    b.edit_header = std::move(edit);
    return b;
}

// A valid block with the bytes at `offset` replaced.
std::vector<std::uint8_t> patched(std::size_t offset, std::vector<std::uint8_t> bytes) {
    auto block = encodeFrameMeta(fullMeta());
    std::copy(bytes.begin(), bytes.end(), block.begin() + static_cast<std::ptrdiff_t>(offset));
    return block;
}

std::vector<std::uint8_t> f64(double v) {
    std::vector<std::uint8_t> out(8);
    std::memcpy(out.data(), &v, 8);  // little-endian host, as the tests run
    return out;
}

}  // namespace

TEST(EvilServerMeta, AnHonestBlockAndValidityReachBothApis) {
    EvilBehaviour b = withMeta(encodeFrameMeta(fullMeta()));
    b.validity.version = 1;
    b.validity.flags = kValidityStalePose | kValidityOffRoute;
    b.validity.pose_age_ms = 1500;
    EvilStreamServer server(b);
    const auto cpp = runInChild([&] { return cppMetaClient(server.path()); });
    EXPECT_EQ(cpp.result, "frame stale_pose+off_route Avinguda Meritxell|Carrer de la Unió") << cpp.how;
    const auto c = runInChild([&] { return cMetaClient(server.path()); });
    EXPECT_EQ(c.result, "frame 1 5 1500 1 roundabout Avinguda Meritxell|Carrer de la Unió lanes -1") << c.how;
}

TEST(EvilServerMeta, EveryMalformedBlockOrValidityIsAnErrorNamingIt) {
    const auto good = encodeFrameMeta(fullMeta());
    auto truncated_street = good;
    truncated_street[14] = 200;  // the next street claims more bytes than the block has
    auto bad_utf8 = good;
    bad_utf8[kFrameMetaFixedBytes] = 0xC3;  // first byte of the next street
    bad_utf8[kFrameMetaFixedBytes + 1] = 0x28;
    auto lanes = good;
    lanes.insert(lanes.begin() + kFrameMetaFixedBytes, std::uint8_t{0x40});  // bit 6 means nothing
    lanes[72] = 1;
    lanes[8] |= 0x08;
    lanes[6] = static_cast<std::uint8_t>(lanes.size());
    lanes[7] = static_cast<std::uint8_t>(lanes.size() >> 8);
    const std::vector<std::pair<EvilBehaviour, std::string>> cases = {
        {withMeta(patched(0, {'X'})), "metadata: bad magic"},
        {withMeta(patched(4, {2, 0})), "metadata: unsupported version 2"},
        {withMeta(patched(6, {90, 0})), "metadata: block says 90 bytes, header says"},
        {withMeta(patched(8, {0x30, 0})), "metadata: unknown flags 48"},
        {withMeta(patched(16, f64(91.0))), R"(metadata: "lat" 91 outside [-90, 90])"},
        {withMeta(patched(24, f64(-181.0))), R"(metadata: "lon" -181 outside [-180, 180])"},
        {withMeta(patched(32, f64(std::nan("")))), R"(metadata: "heading" nan outside [0, 360))"},
        {withMeta(patched(32, f64(360.0))), R"(metadata: "heading" 360 outside [0, 360))"},
        {withMeta(patched(48, f64(-1.0))), R"(metadata: "next_distance" -1 outside)"},
        {withMeta(patched(64, f64(1e300))), R"(metadata: "remaining_s" 1.0000000000000001e+300 outside)"},
        {withMeta(patched(10, {99})), "metadata: unknown manoeuvre type 99"},
        {withMeta(patched(12, {0x10, 0x27})), "metadata: speed limit 10000 km/h"},
        {withMeta(patched(75, {1})), "metadata: reserved byte 75 is not 0"},
        {withMeta(truncated_street), "metadata: "},
        {withMeta(bad_utf8), R"(metadata: "next_street": not UTF-8 (byte 0xc3 at offset 0))"},
        {withMeta(lanes), "metadata: lane 0 has unknown bits"},
        {withMeta(std::vector<std::uint8_t>(good.begin(), good.begin() + 40), 40),
         "frame header: metadata of 40 bytes"},
        {withMeta(good, 5000), "frame header: metadata of 5000 bytes"},
        // The block's bytes announced but the connection closes before they all came.
        {withMeta(std::vector<std::uint8_t>(good.begin(), good.begin() + 90), static_cast<int>(good.size())), ""},
        {withMeta({}, -1, [](std::uint8_t* h) { h[68] = 7; }), "frame header: unsupported validity version 7"},
        {withMeta({}, -1, [](std::uint8_t* h) { h[69] = 1; }),
         "frame header: validity fields set without a validity version"},
        {withMeta({}, -1,
                  [](std::uint8_t* h) {
                      h[68] = 1;
                      h[69] = 0x08;
                  }),
         "frame header: unknown validity flags 8"},
        {withMeta({}, -1,
                  [](std::uint8_t* h) {
                      h[68] = 1;
                      h[69] = 0x02;
                  }),
         "frame header: degraded flag and reasons disagree"},
        {withMeta({}, -1,
                  [](std::uint8_t* h) {
                      h[68] = 1;
                      h[70] = 0x01;
                  }),
         "frame header: degraded flag and reasons disagree"},
        {withMeta({}, -1,
                  [](std::uint8_t* h) {
                      h[68] = 1;
                      h[69] = 2;
                      h[70] = 0x40;
                  }),
         "frame header: unknown degraded reasons 64"},
        {withMeta({}, -1, [](std::uint8_t* h) { h[79] = 1; }), "frame header: reserved bytes 78..79 are not 0"},
    };
    for (const auto& [behaviour, error] : cases) {
        SCOPED_TRACE(error);
        EvilStreamServer server(behaviour);
        const auto cpp = runInChild([&] { return cppMetaClient(server.path()); });
        EXPECT_FALSE(cpp.signalled()) << cpp.how;
        EXPECT_EQ(cpp.result.rfind(error.empty() ? "error: " : "error: " + server.path() + ": ", 0), 0U) << cpp.result;
        EXPECT_NE(cpp.result.find(error), std::string::npos) << cpp.result;
        const auto c = runInChild([&] { return cMetaClient(server.path()); });
        EXPECT_FALSE(c.signalled()) << c.how;
        EXPECT_EQ(c.result.rfind("error: ", 0), 0U) << c.result;
        EXPECT_NE(c.result.find(error), std::string::npos) << c.result;
    }
}

TEST(EvilServerMeta, ABlockNobodyAskedForAndAMissingMetaReplyAreErrors) {
    {
        EvilStreamServer server(withMeta(encodeFrameMeta(fullMeta())));
        const auto out = runInChild([&] { return cppMetaClient(server.path(), false); });
        EXPECT_NE(out.result.find("frame 1: metadata block without asking for it"), std::string::npos) << out.result;
    }
    {
        EvilBehaviour b;
        b.patch = R"({"meta":null})";
        EvilStreamServer server(b);
        const auto out = runInChild([&] { return cppMetaClient(server.path()); });
        EXPECT_NE(out.result.find(R"(reply: "meta" must be 1)"), std::string::npos) << out.result;
    }
    {
        EvilBehaviour b;
        b.patch = R"({"meta":1})";
        EvilStreamServer server(b);
        const auto out = runInChild([&] { return cppMetaClient(server.path(), false); });
        EXPECT_NE(out.result.find(R"(reply: "meta" without asking for metadata)"), std::string::npos) << out.result;
    }
    {
        // Asked, and the frame comes without a block: a frame, with no metadata.
        EvilStreamServer server({});
        const auto out = runInChild([&] { return cppMetaClient(server.path()); });
        EXPECT_EQ(out.result, "frame unknown no meta");
    }
}
