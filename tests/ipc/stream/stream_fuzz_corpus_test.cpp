// SPDX-License-Identifier: Apache-2.0
// Runs the stream fuzz entry (tests/fuzz/stream_handshake_fuzz.cpp) on a corpus of broken
// handshakes, HTTP heads and frame headers: prefixes and byte flips of good ones plus nasties.

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "fuzz_corpus.h"
#include "navmap/ipc/client/frame_header.h"
#include "navmap/ipc/client/frame_ring.h"
#include "navmap/ipc/client/stream_profile.h"

int navmapFuzzStreamHandshake(const std::uint8_t* data, std::size_t size);

TEST(StreamFuzzCorpus, HandshakeHttpAndHeaderParsersSurviveBrokenInputs) {
    navmap::ipc::FrameHeader h;
    h.width = 1280;
    h.height = 480;
    h.stride = 5120;
    h.payload_bytes = 5120 * 480;
    const auto hb = navmap::ipc::encodeFrameHeader(h);
    navmap::ipc::StreamRequest req;
    req.profile = *navmap::ipc::defaultStreamProfile("cluster");
    // A server's reply to a hud shm request (what the fuzz entry asks for), as navmapd words it.
    const auto hud = navmap::ipc::FrameRingLayout::make(3, 800, 240, navmap::ipc::PixelFormat::Rgba8);
    const std::string reply =
        R"({"header_bytes":80,"ok":true,"payload":"shm","profile":{"format":"rgba8","fps":30,"height":240,)"
        R"("name":"hud","view":"hud","width":800},"ring":{"header_offset":64,"pixel_offset":256,"slot_bytes":)" +
        std::to_string(hud.slot_bytes) + R"(,"slots":3,"total_bytes":)" + std::to_string(hud.total_bytes) +
        R"(},"stride":3200,"version":1})"
        "\n";
    const std::vector<std::string> seeds = {
        navmap::ipc::formatStreamRequest(req),
        reply,
        "{\"ok\":false,\"error\":\"ring memory: try again later\"}\n",
        "{\"version\":1,\"profile\":\"x\",\"width\":320,\"height\":200,\"view\":\"bird\",\"format\":\"rgb565\"}\n",
        "GET /stream.mjpg?profile=hud&fps=5 HTTP/1.1\r\nHost: localhost\r\nAccept: */*\r\n\r\n",
        std::string(hb.begin(), hb.end()),
    };
    const std::vector<std::string> extra = {
        "{\"version\":1e999,\"profile\":\"hud\"}",
        "{\"version\":1,\"profile\":\"hud\",\"width\":1.5}",
        "{\"version\":1,\"profile\":\"hud\",\"width\":18446744073709551615}",
        "{\"version\":1,\"profile\":\"hud\",\"width\":-9223372036854775808}",
        "{\"version\":1,\"profile\":\"\\ud800\"}",
        std::string(100000, '['),
        std::string("{\"version\":1,\"profile\":\"hud\"\0}", 30),
        "GET /?&&&==&a HTTP/1.1\r\n\r\n",
        "GET / HTTP/1.1\r\n:\r\n\r\n",
        std::string(80, '\xff'),
        std::string(80, '\0'),
        R"({"ok":true,"profile":{"width":"x"},"ring":{"slots":3,"total_bytes":1}})",
        R"({"ok":true,"profile":{"width":800,"height":240},"ring":"x"})",
        R"({"ok":true,"ring":{"slots":18446744073709551615,"total_bytes":-1}})",
        R"({"ok":true,"ring":{"slots":3,"total_bytes":1e300}})",
        R"({"ok":"yes"})",
        R"({"ok":false,"error":7})",
    };
    const std::size_t runs = navmap::test::runFuzzCorpus(navmapFuzzStreamHandshake, seeds, extra, 500);
    EXPECT_GT(runs, 2000U);
}

// Every file of the checked-in libFuzzer corpus (tests/fuzz/corpus/stream_handshake).
TEST(StreamFuzzCorpus, CheckedInCorpus) {
    EXPECT_GE(navmap::test::runCheckedInCorpus(navmapFuzzStreamHandshake, "stream_handshake"), 20U);
}
