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
#include <string>
#include <vector>

#include "evil_stream_server.h"
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
    const auto shm = [](EvilRing ring) { return EvilBehaviour{ring, "", ""}; };
    const auto patch = [](std::string p) { return EvilBehaviour{EvilRing::Sealed, std::move(p), ""}; };
    const auto line = [](std::string l) { return EvilBehaviour{EvilRing::Sealed, "", std::move(l)}; };
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
