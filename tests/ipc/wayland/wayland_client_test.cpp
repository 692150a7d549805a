// SPDX-License-Identifier: Apache-2.0
// navmap-wayland's frame copy into display buffers: formats, scaling, centring; its feed's
// fallback from dma-buf frames to shm.

#include <gtest/gtest.h>

#include <unistd.h>

#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include "frame_blit.h"
#include "frame_feed.h"
#include "wayland_test_util.h"

using namespace navmap::ipc;
using namespace navmap::ipc::wayland;
using namespace navmap::wayland_test;

TEST(FrameBlit, RgbaIntoXbgrIsTheSameBytesAndIntoXrgbSwapsRedAndBlue) {
    const auto src = patternFrame(33, 7, 1);
    const SourcePixels in{src.data(), 33, 7, 33 * 4, PixelFormat::Rgba8};
    std::vector<std::uint8_t> out(40 * 4 * 7, 0xAA);  // a stride wider than the row
    const Placement p = blitFrame(in, {out.data(), 33, 7, 40 * 4, ShmFormat::Xbgr8888});
    EXPECT_FALSE(p.scaled);
    for (int y = 0; y < 7; ++y) {
        EXPECT_EQ(std::memcmp(&out[y * 160], &src[y * 132], 132), 0) << "row " << y;
        EXPECT_EQ(out[y * 160 + 132], 0xAA) << "wrote past the row";
    }
    blitFrame(in, {out.data(), 33, 7, 40 * 4, ShmFormat::Xrgb8888});
    const std::uint8_t* px = &out[3 * 160 + 20 * 4];  // pixel (20, 3)
    std::uint8_t rgb[3];
    patternPixel(20, 3, 1, rgb);
    EXPECT_EQ(px[0], rgb[2]);
    EXPECT_EQ(px[1], rgb[1]);
    EXPECT_EQ(px[2], rgb[0]);
    EXPECT_EQ(px[3], 0xFF);
}

TEST(FrameBlit, Rgb565FramesAreCopiedOrWidened) {
    std::vector<std::uint8_t> src(16 * 2 * 2);
    for (int i = 0; i < 32; ++i) {
        const std::uint16_t v = i == 5 ? 0xF800 : static_cast<std::uint16_t>(i * 2047);
        std::memcpy(&src[i * 2], &v, 2);
    }
    const SourcePixels in{src.data(), 16, 2, 32, PixelFormat::Rgb565};
    std::vector<std::uint8_t> out565(64);
    blitFrame(in, {out565.data(), 16, 2, 32, ShmFormat::Rgb565});
    EXPECT_EQ(out565, src);
    std::vector<std::uint8_t> out32(16 * 2 * 4);
    blitFrame(in, {out32.data(), 16, 2, 64, ShmFormat::Xrgb8888});
    EXPECT_EQ(out32[5 * 4 + 2], 255);  // pure red: R 0x1F -> 255
    EXPECT_EQ(out32[5 * 4 + 1], 0);
    EXPECT_EQ(out32[5 * 4 + 0], 0);
}

TEST(FrameBlit, AnotherSizeIsScaledToFitAndCentredOnBlack) {
    EXPECT_EQ(fitCentred(320, 200, 160, 205).y, 52);
    EXPECT_EQ(fitCentred(320, 200, 160, 205).height, 100);
    const Placement wide = fitCentred(100, 100, 300, 100);
    EXPECT_EQ(wide.x, 100);
    EXPECT_EQ(wide.width, 100);
    EXPECT_TRUE(wide.scaled);

    const auto src = patternFrame(320, 200, 2);
    std::vector<std::uint8_t> out(160 * 205 * 4, 0x77);
    const Placement p =
        blitFrame({src.data(), 320, 200, 1280, PixelFormat::Rgba8}, {out.data(), 160, 205, 640, ShmFormat::Xbgr8888});
    EXPECT_TRUE(p.scaled);
    EXPECT_EQ(p.x, 0);
    EXPECT_EQ(p.y, 52);
    for (int y = 0; y < 205; ++y) {
        for (int x = 0; x < 160; ++x) {
            const std::uint8_t* o = &out[(y * 160 + x) * 4];
            std::uint8_t e[3] = {0, 0, 0};
            if (y >= 52 && y < 152) patternPixel(2 * x + 1, 2 * (y - 52) + 1, 2, e);
            ASSERT_TRUE(o[0] == e[0] && o[1] == e[1] && o[2] == e[2]) << "pixel " << x << "," << y;
        }
    }
}

// --dmabuf: navmapd (here a FrameServer that exports nothing, as on llvmpipe) refuses dma-buf
// frames; the feed streams shm instead and says why in one log line, whatever the reconnects.
TEST(FrameFeed, DmabufFallsBackToShmWithOneLogLine) {
    const std::string sock = "/tmp/navmap-wl-dmabuf-" + std::to_string(::getpid()) + ".sock";
    PatternServer server(sock, 7);
    ASSERT_TRUE(server.started()) << server.error();
    char* text = nullptr;
    std::size_t text_bytes = 0;
    std::FILE* log = open_memstream(&text, &text_bytes);
    ASSERT_NE(log, nullptr);
    {
        ReconnectOptions o;
        o.unix_path = sock;
        o.request.profile = *defaultStreamProfile("hud");
        o.request.payload = StreamPayload::Dmabuf;
        o.request.dmabuf_fallback_shm = true;
        FrameFeed feed(o, false, log);
        FeedFrame f;
        bool got = false;
        for (int i = 0; i < 100 && !got; ++i) got = feed.next(f, std::chrono::milliseconds(50));
        ASSERT_TRUE(got);
        EXPECT_EQ(f.header.width, 800U);
        std::uint8_t rgb[3];
        patternPixel(5, 3, 7, rgb);
        const std::uint8_t* px = f.pixels + 3 * f.header.stride + 5 * 4;
        EXPECT_EQ(px[0], rgb[0]);
        EXPECT_EQ(px[1], rgb[1]);
        EXPECT_EQ(px[2], rgb[2]);
        EXPECT_EQ(feed.client().client()->payload(), StreamPayload::Shm);
        feed.release();
    }
    std::fclose(log);
    const std::string lines(text, text_bytes);
    std::free(text);
    const std::string fallback =
        "navmap-wayland: no dma-buf frames (handshake refused by " + sock +
        ": handshake: dmabuf frames are not available here (this server exports no dma-buf frames); ask for shm); "
        "using wl_shm buffers\n";
    EXPECT_NE(lines.find(fallback), std::string::npos) << lines;
    EXPECT_EQ(lines.find("navmap-wayland: no dma-buf"), lines.rfind("navmap-wayland: no dma-buf"))
        << "logged once: " << lines;
    EXPECT_NE(lines.find("(payload shm)"), std::string::npos) << lines;
}
