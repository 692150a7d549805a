// SPDX-License-Identifier: Apache-2.0
// Wire formats of the frame stream: header, handshake, HTTP head, pixel formats, PNG, the ring's
// sequence lock (docs/frame-protocol.md).

#include <gtest/gtest.h>

#include <atomic>
#include <cstring>
#include <filesystem>
#include <thread>
#include <vector>

#include "navmap/ipc/client/frame_header.h"
#include "navmap/ipc/client/frame_png.h"
#include "navmap/ipc/client/frame_ring.h"
#include "navmap/ipc/client/stream_profile.h"
#include "navmap/ipc/stream/stream_http_request.h"
#include "navmap/render/image.h"
#include "stream_test_util.h"

using namespace navmap::ipc;

TEST(FrameHeader, RoundTripsEveryField) {
    FrameHeader h;
    h.kind = FrameKind::Frame;
    h.encoding = FrameEncoding::Raw;
    h.format = PixelFormat::Rgb565;
    h.sequence = 0x0102030405060708ULL;
    h.render_time_ns = 1700000000123456789LL;
    h.source_time_ns = 1700000000100000000LL;
    h.width = 800;
    h.height = 240;
    h.stride = 1600;
    h.payload_bytes = 1600 * 240;
    h.dropped = 17;
    h.slot = 3;
    const auto bytes = encodeFrameHeader(h);
    EXPECT_EQ(bytes[0], 'N');
    EXPECT_EQ(bytes[1], 'M');
    EXPECT_EQ(bytes[2], 'F');
    EXPECT_EQ(bytes[3], 'R');
    EXPECT_EQ(bytes[16], 0x08);  // little-endian sequence
    auto d = decodeFrameHeader(bytes.data(), bytes.size());
    ASSERT_TRUE(d.ok()) << d.error().message;
    EXPECT_EQ(d.value().sequence, h.sequence);
    EXPECT_EQ(d.value().render_time_ns, h.render_time_ns);
    EXPECT_EQ(d.value().source_time_ns, h.source_time_ns);
    EXPECT_EQ(d.value().width, 800U);
    EXPECT_EQ(d.value().stride, 1600U);
    EXPECT_EQ(d.value().format, PixelFormat::Rgb565);
    EXPECT_EQ(d.value().dropped, 17U);
    EXPECT_EQ(d.value().slot, 3U);
}

TEST(FrameHeader, RejectsBrokenHeadersWithReasons) {
    FrameHeader h;
    h.width = 64;
    h.height = 32;
    h.stride = 256;
    h.payload_bytes = 256 * 32;
    auto good = encodeFrameHeader(h);
    ASSERT_TRUE(decodeFrameHeader(good.data(), good.size()).ok());
    EXPECT_NE(decodeFrameHeader(good.data(), 79).error().message.find("79 bytes"), std::string::npos);
    auto bad = good;
    bad[0] = 'X';
    EXPECT_NE(decodeFrameHeader(bad.data(), bad.size()).error().message.find("magic"), std::string::npos);
    h.stride = 100;  // < 64 * 4
    auto b2 = encodeFrameHeader(h);
    EXPECT_NE(decodeFrameHeader(b2.data(), b2.size()).error().message.find("stride"), std::string::npos);
    h.stride = 256;
    h.payload_bytes = 5;
    auto b3 = encodeFrameHeader(h);
    EXPECT_NE(decodeFrameHeader(b3.data(), b3.size()).error().message.find("raw payload"), std::string::npos);
    h.payload_bytes = 256 * 32;
    h.format = static_cast<PixelFormat>(9);
    auto b4 = encodeFrameHeader(h);
    EXPECT_NE(decodeFrameHeader(b4.data(), b4.size()).error().message.find("pixel format"), std::string::npos);
}

TEST(FrameHeader, StatusKindCarriesAUtf8PayloadOfAtMost64KiB) {
    FrameHeader h;
    h.kind = FrameKind::Status;
    const std::string json = R"({"state":"loading","view":"snail","tiles_wanted":12,"held_back":30,"waited_ms":1500})";
    h.payload_bytes = static_cast<std::uint32_t>(json.size());
    const auto bytes = encodeFrameHeader(h);
    EXPECT_EQ(bytes[8], 2);  // kind 2 = status, little-endian u16 at offset 8
    EXPECT_EQ(bytes[9], 0);
    auto d = decodeFrameHeader(bytes.data(), bytes.size());
    ASSERT_TRUE(d.ok()) << d.error().message;
    EXPECT_EQ(d.value().kind, FrameKind::Status);
    EXPECT_EQ(d.value().payload_bytes, json.size());
    const auto* p = reinterpret_cast<const std::uint8_t*>(json.data());
    EXPECT_TRUE(validateTextPayload(FrameKind::Status, p, json.size()).ok());
    // Two-, three- and four-byte characters pass; a lone continuation byte, an overlong '/', a
    // UTF-16 surrogate, a code point above U+10FFFF and a sequence cut short do not.
    const std::string accented = "{\"state\":\"chargement termin\xc3\xa9\",\"\xe2\x82\xac\":\"\xf0\x9f\x97\xba\"}";
    EXPECT_TRUE(
        validateTextPayload(FrameKind::Status, reinterpret_cast<const std::uint8_t*>(accented.data()), accented.size())
            .ok());
    const std::pair<std::string, std::string> bad[] = {
        {"{\"a\":\"\x80\"}", "status: not UTF-8 (byte 0x80 at offset 6)"},
        {"ab\xc0\xaf", "status: not UTF-8 (byte 0xc0 at offset 2)"},
        {"\xed\xa0\x80", "status: not UTF-8 (byte 0xed at offset 0)"},
        {"x\xf4\x90\x80\x80", "status: not UTF-8 (byte 0xf4 at offset 1)"},
        {"xyz\xe2\x82", "status: not UTF-8 (byte 0xe2 at offset 3)"},
    };
    for (const auto& [text, why] : bad) {
        const auto s =
            validateTextPayload(FrameKind::Status, reinterpret_cast<const std::uint8_t*>(text.data()), text.size());
        ASSERT_FALSE(s.ok()) << why;
        EXPECT_EQ(s.message(), why);
    }
    // Exactly 64 KiB passes; one byte more is refused by the header already and by the payload check.
    h.payload_bytes = kMaxStatusPayloadBytes;
    auto at_limit = encodeFrameHeader(h);
    EXPECT_TRUE(decodeFrameHeader(at_limit.data(), at_limit.size()).ok());
    const std::string big(kMaxStatusPayloadBytes + 1, 'x');
    EXPECT_TRUE(
        validateTextPayload(FrameKind::Status, reinterpret_cast<const std::uint8_t*>(big.data()), big.size() - 1).ok());
    EXPECT_EQ(
        validateTextPayload(FrameKind::Status, reinterpret_cast<const std::uint8_t*>(big.data()), big.size()).message(),
        "status: 65537 bytes (limit 65536)");
    h.payload_bytes = kMaxStatusPayloadBytes + 1;
    auto over = encodeFrameHeader(h);
    auto r = decodeFrameHeader(over.data(), over.size());
    ASSERT_FALSE(r.ok());
    EXPECT_EQ(r.error().message, "frame header: status of 65537 bytes (limit 65536)");
    // Kind 3 does not exist.
    over[8] = 3;
    EXPECT_EQ(decodeFrameHeader(over.data(), over.size()).error().message, "frame header: unknown kind 3");
}

TEST(PixelFormats, Rgb565RoundTripKeepsTheTopBits) {
    const std::uint8_t rgba[] = {255, 255, 255, 255, 0, 0, 0, 255, 0xF8, 0x04, 0x80, 7};
    std::uint8_t packed[6];
    convertRowFromRgba(rgba, PixelFormat::Rgb565, packed, 3);
    EXPECT_EQ(packed[0], 0xFF);
    EXPECT_EQ(packed[1], 0xFF);
    EXPECT_EQ(packed[2], 0x00);
    EXPECT_EQ(packed[3], 0x00);
    // r=0xF8 -> 31, g=0x04 -> 1, b=0x80 -> 16: 31<<11 | 1<<5 | 16 = 0xF830
    EXPECT_EQ(packed[4], 0x30);
    EXPECT_EQ(packed[5], 0xF8);
    std::uint8_t back[12];
    convertRowToRgba(packed, PixelFormat::Rgb565, back, 3);
    EXPECT_EQ(back[0], 255);
    EXPECT_EQ(back[4], 0);
    EXPECT_EQ(back[8], 0xFF);
    EXPECT_EQ(back[9], 0x04);
    EXPECT_EQ(back[10], 0x84);
    EXPECT_EQ(back[11], 255);
}

// The blocked (vectorised) conversion gives the bytes of the per-pixel formula for every width,
// whole blocks of 16 and the tail alike, and writes nothing past the row.
TEST(PixelFormats, Rgb565ConversionMatchesThePerPixelFormulaAtEveryWidth) {
    std::vector<std::uint8_t> rgba(1283 * 4);
    std::uint32_t v = 7;
    for (auto& b : rgba) {
        v = v * 1103515245U + 12345U;
        b = static_cast<std::uint8_t>(v >> 16);
    }
    for (int width : {0, 1, 15, 16, 17, 31, 32, 33, 47, 800, 1280, 1283}) {
        std::vector<std::uint8_t> out(static_cast<std::size_t>(width) * 2 + 2, 0xAB);
        convertRowFromRgba(rgba.data(), PixelFormat::Rgb565, out.data(), width);
        for (int x = 0; x < width; ++x) {
            const std::uint8_t* p = &rgba[static_cast<std::size_t>(x) * 4];
            const unsigned expect = ((p[0] >> 3) << 11) | ((p[1] >> 2) << 5) | (p[2] >> 3);
            const unsigned got = out[2 * x] | (out[2 * x + 1] << 8);
            ASSERT_EQ(got, expect) << "width " << width << ", pixel " << x;
        }
        EXPECT_EQ(out[out.size() - 2], 0xAB) << "width " << width;
        EXPECT_EQ(out[out.size() - 1], 0xAB) << "width " << width;
    }
}

TEST(Handshake, DefaultsAndOverrides) {
    auto r = parseStreamRequest("{\"version\":1,\"profile\":\"hud\"}\n");
    ASSERT_TRUE(r.ok()) << r.error().message;
    EXPECT_EQ(r.value().profile.width, 800);
    EXPECT_EQ(r.value().profile.height, 240);
    EXPECT_EQ(r.value().profile.view, "hud");
    EXPECT_EQ(r.value().payload, StreamPayload::Shm);
    r = parseStreamRequest(R"({"version":1,"profile":"cluster","fps":10,"format":"rgb565","payload":"zlib"})");
    ASSERT_TRUE(r.ok()) << r.error().message;
    EXPECT_EQ(r.value().profile.width, 1280);
    EXPECT_EQ(r.value().profile.fps, 10);
    EXPECT_EQ(r.value().profile.format, PixelFormat::Rgb565);
    EXPECT_EQ(r.value().payload, StreamPayload::Zlib);
    r = parseStreamRequest(R"({"version":1,"profile":"mirror","width":320,"height":200,"view":"bird"})");
    ASSERT_TRUE(r.ok()) << r.error().message;
    EXPECT_EQ(r.value().profile.name, "mirror");
    auto again = parseStreamRequest(formatStreamRequest(r.value()));
    ASSERT_TRUE(again.ok());
    EXPECT_EQ(again.value().profile.width, 320);
    EXPECT_EQ(again.value().profile.view, "bird");
}

TEST(Handshake, BadLinesNameTheProblem) {
    const std::pair<const char*, const char*> cases[] = {
        {"hello", "not a JSON line"},
        {"[1,2]", "JSON object"},
        {R"({"profile":"hud"})", "\"version\" missing"},
        {R"({"version":2,"profile":"hud"})", "unsupported version 2"},
        {R"({"version":1})", "give \"profile\""},
        {R"({"version":1,"profile":"nope"})", "not a default"},
        {R"({"version":1,"profile":"hud","width":"wide"})", "\"width\" must be an integer"},
        {R"({"version":1,"profile":"hud","width":99999})", "outside"},
        {R"({"version":1,"profile":"hud","fps":-1})", "\"fps\" = -1"},
        {R"({"version":1,"profile":"hud","view":"side"})", "unknown view"},
        {R"({"version":1,"profile":"hud","format":"bgr24"})", "unknown format"},
        {R"({"version":1,"profile":"hud","payload":"udp"})", "unknown payload"},
        {R"({"version":1,"profile":"hud","colour":1})", "unknown key \"colour\""},
        {R"({"version":1,"profile":"h\u0001d","width":20,"height":20,"view":"bird"})", "printable"},
    };
    for (const auto& [line, why] : cases) {
        auto r = parseStreamRequest(line);
        ASSERT_FALSE(r.ok()) << line;
        EXPECT_NE(r.error().message.find(why), std::string::npos) << line << " -> " << r.error().message;
    }
    EXPECT_FALSE(parseStreamRequest(std::string(5000, ' ')).ok());
}

// The client's side: the server's reply line, read against the request it answers. (Every wrong
// type and range, end to end through the clients: evil_server_test.cpp.)
TEST(Handshake, RepliesAreReadAgainstTheRequest) {
    StreamRequest asked;
    asked.profile = *defaultStreamProfile("hud");
    asked.profile.fps = 10;
    asked.hold = true;
    const auto l = FrameRingLayout::make(2, 800, 240, PixelFormat::Rgba8);
    const std::string ring = R"("ring":{"slots":2,"slot_bytes":)" + std::to_string(l.slot_bytes) +
                             R"(,"total_bytes":)" + std::to_string(l.total_bytes) +
                             R"(,"header_offset":64,"pixel_offset":256})";
    auto r = parseStreamReply(R"({"ok":true,"version":1,"profile":{"name":"hud2","width":800,"height":240,"fps":5,)"
                              R"("view":"hud","format":"rgba8"},"payload":"shm","hold":true,"stride":3200,)"
                              R"("header_bytes":80,)" +
                                  ring + "}",
                              asked);
    ASSERT_TRUE(r.ok()) << r.error().message;
    EXPECT_TRUE(r.value().accepted);
    EXPECT_EQ(r.value().profile.name, "hud2");
    EXPECT_EQ(r.value().profile.fps, 5);
    EXPECT_EQ(r.value().ring_slots, 2U);
    EXPECT_EQ(r.value().ring_total_bytes, l.total_bytes);
    // Absent optional fields keep the request's; the ring's size is required for shm.
    r = parseStreamReply(R"({"ok":true,"ring":{"slots":2,"total_bytes":)" + std::to_string(l.total_bytes) + "}}",
                         asked);
    ASSERT_TRUE(r.ok()) << r.error().message;
    EXPECT_EQ(r.value().profile.name, "hud");
    EXPECT_EQ(r.value().profile.fps, 10);
    r = parseStreamReply(R"({"ok":true})", asked);
    ASSERT_FALSE(r.ok());
    EXPECT_EQ(r.error().message, R"(reply: payload shm without "ring")");
    StreamRequest raw = asked;
    raw.payload = StreamPayload::Raw;
    raw.hold = false;
    r = parseStreamReply(R"({"ok":true,"payload":"raw"})", raw);
    ASSERT_TRUE(r.ok()) << r.error().message;
    EXPECT_EQ(r.value().ring_slots, 0U);
    // A refusal keeps the server's words.
    r = parseStreamReply(R"x({"ok":false,"error":"too many unix clients (limit 32)"})x", asked);
    ASSERT_TRUE(r.ok());
    EXPECT_FALSE(r.value().accepted);
    EXPECT_EQ(r.value().refusal, "too many unix clients (limit 32)");
    const std::pair<std::string, std::string> bad[] = {
        {R"({"ok":true,"hold":false,)" + ring + "}", R"(reply: "hold" must be true as asked)"},
        {R"({"ok":true,"profile":{"width":800.0},)" + ring + "}", R"(reply: "profile.width" must be an integer)"},
        {R"({"ok":true,"profile":{"name":"a\u0001"},)" + ring + "}",
         R"(reply: "profile.name" must be printable ASCII)"},
        {R"({"ok":true,"profile":{"height":4097},)" + ring + "}",
         R"(reply: "profile.height" = 4097 outside [16, 4096])"},
        {std::string(5000, ' '), "reply: longer than 4096 bytes"},
    };
    for (const auto& [line, why] : bad) {
        r = parseStreamReply(line, asked);
        ASSERT_FALSE(r.ok()) << line;
        EXPECT_EQ(r.error().message, why) << line;
    }
}

TEST(HttpRequest, ParsesGetWithQueryAndRejectsJunk) {
    auto r = parseStreamHttpRequest("GET /stream.mjpg?profile=hud&fps=5 HTTP/1.1\r\nHost: x\r\n\r\n");
    ASSERT_TRUE(r.ok()) << r.error().message;
    EXPECT_EQ(r.value().method, "GET");
    EXPECT_EQ(r.value().path, "/stream.mjpg");
    EXPECT_EQ(r.value().query.at("profile"), "hud");
    EXPECT_EQ(r.value().query.at("fps"), "5");
    EXPECT_FALSE(parseStreamHttpRequest("GET / HTTP/9.9\r\n\r\n").ok());
    EXPECT_FALSE(parseStreamHttpRequest("GET nope HTTP/1.1\r\n\r\n").ok());
    EXPECT_FALSE(parseStreamHttpRequest("get / HTTP/1.1\r\n\r\n").ok());
    EXPECT_FALSE(parseStreamHttpRequest("GET / HTTP/1.1\r\nno colon here\r\n\r\n").ok());
    EXPECT_FALSE(parseStreamHttpRequest("\r\n\r\n").ok());
}

TEST(FramePng, WritesAPngThatReadsBackExactly) {
    FrameHeader h;
    h.width = 37;
    h.height = 11;
    h.format = PixelFormat::Rgba8;
    h.stride = 37 * 4 + 12;  // padded rows
    std::vector<std::uint8_t> px(static_cast<std::size_t>(h.stride) * h.height);
    for (std::size_t i = 0; i < px.size(); ++i) {
        // Opaque: the image reader premultiplies alpha, which would change translucent colours.
        px[i] = i % 4 == 3 ? 255 : static_cast<std::uint8_t>(i * 7);
    }
    const auto path =
        std::filesystem::temp_directory_path() / ("navmap_frame_png_" + std::to_string(getpid()) + ".png");
    ASSERT_TRUE(writeFramePng(path.string(), h, px.data()).ok());
    navmap::render::Image img;
    std::string err;
    ASSERT_TRUE(navmap::render::readImage(path, &img, &err)) << err;
    ASSERT_EQ(img.width, 37);
    ASSERT_EQ(img.height, 11);
    for (int y = 0; y < 11; ++y) {
        for (int x = 0; x < 37; ++x) {
            for (int c = 0; c < 4; ++c) {
                ASSERT_EQ(img.pixel(x, y)[c], px[static_cast<std::size_t>(y) * h.stride + x * 4 + c]) << x << "," << y;
            }
        }
    }
    std::filesystem::remove(path);
    auto bad = writeFramePng("/nonexistent-dir/x.png", h, px.data());
    ASSERT_FALSE(bad.ok());
    EXPECT_EQ(bad.message(), "/nonexistent-dir/x.png: cannot write: No such file or directory");
}

// The sequence lock: a reader racing a writer that laps it on a 2-slot ring must never accept a
// frame whose pixels belong to two different writes.
TEST(FrameRing, ReaderNeverAcceptsATornFrame) {
    constexpr int kW = 256, kH = 128;
    auto ring = FrameRing::create("navmap-test-ring", 2, kW, kH, PixelFormat::Rgba8);
    ASSERT_TRUE(ring.ok()) << ring.error().message;
    FrameRing& r = *ring.value();
    std::atomic<bool> run{true};
    std::thread writer([&] {
        std::uint64_t i = 0;
        while (run) {
            ++i;
            const auto px = navmap::stream_test::sequencePattern(kW, kH, i);
            FrameView f{px.data(), kW, kH, 0, PixelFormat::Rgba8, 0, 0, {}, {}};
            r.write(f);
        }
    });
    std::vector<std::uint8_t> out(r.layout().pixelBytes());
    int accepted = 0, refused = 0;
    const auto until = std::chrono::steady_clock::now() + std::chrono::milliseconds(400);
    while (std::chrono::steady_clock::now() < until) {
        // Alternate between the newest frame and the one before it, whose slot is the next to be
        // overwritten on a 2-slot ring: many reads race the writer.
        const std::uint64_t latest = r.latestSequence();
        const std::uint64_t seq = (accepted + refused) % 2 == 0 || latest < 2 ? latest : latest - 1;
        FrameHeader h;
        if (!r.read(seq, &h, out.data())) {
            ++refused;
            continue;
        }
        ++accepted;
        ASSERT_EQ(h.sequence, seq);
        const auto want = navmap::stream_test::sequencePattern(kW, kH, seq);
        ASSERT_EQ(0, std::memcmp(out.data(), want.data(), out.size())) << "torn frame " << seq;
    }
    run = false;
    writer.join();
    EXPECT_GT(accepted, 10);
    EXPECT_GT(refused, 0);  // the race did happen, and the lock caught it
    std::printf("ring race: %d frames accepted, %d refused as overwritten\n", accepted, refused);
    // A sequence that is gone is refused.
    EXPECT_FALSE(r.read(1, nullptr, nullptr));
}
