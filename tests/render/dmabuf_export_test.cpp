// SPDX-License-Identifier: Apache-2.0
// dma-buf frames on the GPU side (docs/gles-profile.md "dma-buf export"): where no DRM node can
// give buffers the renderer says why; where one can (a GPU, or vgem's buffers for llvmpipe in the
// qemu guest of tests/render/run_dmabuf_guest.sh), the exported buffer holds the frame the
// readback gets, byte for byte, top row first, with the overlay blended over it, and busy buffers
// are never written. NAVMAP_EXPECT_DMABUF=1 (the guest sets it) turns "cannot export here" from a
// skip into a failure.

#include <gtest/gtest.h>

#include <linux/dma-buf.h>
#include <poll.h>
#include <sys/ioctl.h>
#include <sys/mman.h>
#include <unistd.h>

#include <cstdlib>
#include <cstring>
#include <string>

#include "navmap/render/renderer.h"
#include "terrain_scene.h"
#include "test_paths.h"

namespace {

using navmap::render::DmabufFrame;
using navmap::render::Image;
using navmap::render::Renderer;
using navmap::render::RendererOptions;

bool expectDmabuf() {
    const char* e = std::getenv("NAVMAP_EXPECT_DMABUF");
    return e && std::string(e) == "1";
}

const navmap::render::TerrainScene& andorra() {
    static const auto kScene = navmap::render::loadTerrainScene(navmap::test::dataDir() / "N42E001.hgt");
    return kScene;
}

// A renderer that has drawn a terrain frame, or null (and the test skipped or failed) when this
// machine cannot export.
std::unique_ptr<Renderer> exportingRenderer(int width, int height) {
    RendererOptions o;
    o.width = width;
    o.height = height;
    auto r = Renderer::create(o);
    const auto& d = r->device().dmabuf;
    std::printf("[ info     ] %s, dma-buf export: %s\n", r->device().renderer.c_str(),
                d.available ? ("from " + d.drm_node).c_str() : ("off: " + d.reason).c_str());
    if (!d.available) return nullptr;
    r->setTerrain(andorra().mesh);
    r->render(navmap::render::andorraFlyoverCamera(andorra().projection, 0.3));
    return r;
}

#define EXPORTING_RENDERER(r, w, h)                                                           \
    auto r = exportingRenderer(w, h);                                                         \
    if (!r) {                                                                                 \
        if (expectDmabuf()) {                                                                 \
            FAIL() << "NAVMAP_EXPECT_DMABUF=1, but the renderer cannot export dma-bufs";      \
        }                                                                                     \
        GTEST_SKIP() << "this machine cannot export dma-bufs (the reason is printed above); " \
                        "tests/render/run_dmabuf_guest.sh runs this test where it can";       \
    }

// The buffer's bytes as the client sees them (mapped, read inside a DMA_BUF_IOCTL_SYNC bracket),
// width x 4 bytes per row without the stride's padding.
Image mapped(const DmabufFrame& f) {
    if (f.fence_fd >= 0) {
        pollfd p{f.fence_fd, POLLIN, 0};
        EXPECT_EQ(::poll(&p, 1, 5000), 1) << "the frame's fence did not signal";
        ::close(f.fence_fd);
    }
    const std::size_t bytes = std::size_t{f.stride} * static_cast<std::size_t>(f.height) + f.offset;
    void* map = ::mmap(nullptr, bytes, PROT_READ, MAP_SHARED, f.fd, 0);
    Image img;
    if (map == MAP_FAILED) {
        ADD_FAILURE() << "mmap of the dma-buf: " << std::strerror(errno);
        return img;
    }
    dma_buf_sync sync{DMA_BUF_SYNC_START | DMA_BUF_SYNC_READ};
    EXPECT_EQ(::ioctl(f.fd, DMA_BUF_IOCTL_SYNC, &sync), 0);
    img.width = f.width;
    img.height = f.height;
    img.rgba.resize(std::size_t(f.width) * f.height * 4);
    for (int y = 0; y < f.height; ++y) {
        std::memcpy(img.rgba.data() + std::size_t(y) * f.width * 4,
                    static_cast<const std::uint8_t*>(map) + f.offset + std::size_t(y) * f.stride,
                    std::size_t(f.width) * 4);
    }
    sync.flags = DMA_BUF_SYNC_END | DMA_BUF_SYNC_READ;
    ::ioctl(f.fd, DMA_BUF_IOCTL_SYNC, &sync);
    ::munmap(map, bytes);
    return img;
}

std::size_t differingPixels(const Image& a, const Image& b) {
    std::size_t n = 0;
    for (std::size_t i = 0; i + 3 < a.rgba.size() && i + 3 < b.rgba.size(); i += 4)
        n += std::memcmp(&a.rgba[i], &b.rgba[i], 4) != 0;
    return n;
}

TEST(DmabufExport, WithoutADrmNodeTheRendererSaysWhy) {
    RendererOptions o;
    o.width = 64;
    o.height = 32;
    auto r = Renderer::create(o);
    const auto& d = r->device().dmabuf;
    if (!navmap::render::findDrmNodes().empty())
        GTEST_SKIP() << "this machine has DRM nodes (" << navmap::render::findDrmNodes().front()
                     << "): DmabufExport.TheBufferHoldsTheReadBackFrameTopRowFirst covers it";
    EXPECT_FALSE(d.available);
    EXPECT_FALSE(r->exportFrame(r->primaryTarget(), 0).has_value());
    const std::string prefix = r->device().renderer.substr(0, r->device().renderer.find(' ')) + " on the " +
                               r->device().platform + " platform: ";
    EXPECT_EQ(d.reason.rfind(prefix, 0), 0U) << d.reason;
    EXPECT_NE(d.reason.find("no DRM node (/dev/dri/renderD*, /dev/dri/card*)"), std::string::npos) << d.reason;
}

TEST(DmabufExport, TheBufferHoldsTheReadBackFrameTopRowFirst) {
    EXPORTING_RENDERER(r, 160, 96);
    const Image read = r->readSync();
    auto f = r->exportFrame(r->primaryTarget(), 0);
    ASSERT_TRUE(f.has_value());
    EXPECT_EQ(f->width, 160);
    EXPECT_EQ(f->height, 96);
    EXPECT_EQ(f->fourcc, 0x34324241U) << "DRM_FORMAT_ABGR8888 ('AB24'): R, G, B, A bytes";
    EXPECT_EQ(f->modifier, 0U) << "DRM_FORMAT_MOD_LINEAR";
    EXPECT_GE(f->stride, 160U * 4);
    EXPECT_GE(f->fd, 0);
    const Image got = mapped(*f);
    ASSERT_EQ(got.rgba.size(), read.rgba.size());
    EXPECT_EQ(differingPixels(got, read), 0U) << "the exported frame differs from the read-back one";
    // Not a blank frame: sky at the top, terrain at the bottom (the rows are not upside down).
    EXPECT_NE(std::memcmp(&got.rgba[0], &got.rgba[(95 * 160) * 4], 4), 0);
    EXPECT_EQ(std::memcmp(&got.rgba[0], &read.rgba[0], 4), 0);
}

TEST(DmabufExport, TheOverlayIsBlendedOverTheCopyOnly) {
    EXPORTING_RENDERER(r, 160, 96);
    const Image read = r->readSync();
    Image overlay;  // premultiplied: half-transparent red, and one fully transparent column
    overlay.width = 12;
    overlay.height = 6;
    overlay.rgba.resize(12 * 6 * 4);
    for (int i = 0; i < 12 * 6; ++i) {
        const bool clear = i % 12 == 0;
        overlay.rgba[i * 4 + 0] = clear ? 0 : 128;
        overlay.rgba[i * 4 + 3] = clear ? 0 : 128;
    }
    const navmap::render::FrameOverlay o{&overlay, 100, 80, 1};
    auto f = r->exportFrame(r->primaryTarget(), 0, &o);
    ASSERT_TRUE(f.has_value());
    const Image got = mapped(*f);
    std::size_t inside = 0, outside = 0;
    for (int y = 0; y < 96; ++y) {
        for (int x = 0; x < 160; ++x) {
            const std::size_t i = (std::size_t(y) * 160 + x) * 4;
            const bool in = x > 100 && x < 112 && y >= 80 && y < 86;  // column 100 is transparent
            if (!in) {
                outside += std::memcmp(&got.rgba[i], &read.rgba[i], 4) != 0;
                continue;
            }
            ++inside;
            const int want_r = 128 + read.rgba[i] * 127 / 255;  // src + dst * (1 - 128/255)
            EXPECT_NEAR(got.rgba[i], want_r, 2) << x << "," << y;
            EXPECT_NEAR(got.rgba[i + 1], read.rgba[i + 1] * 127 / 255, 2) << x << "," << y;
        }
    }
    EXPECT_EQ(inside, 11U * 6);
    EXPECT_EQ(outside, 0U) << "pixels changed outside the overlay";
}

TEST(DmabufExport, BusyBuffersAreNeverWrittenAndANewSizeGetsNewBuffers) {
    EXPORTING_RENDERER(r, 64, 48);
    const auto t = r->primaryTarget();
    auto a = r->exportFrame(t, 0);
    ASSERT_TRUE(a.has_value());
    const auto first = a->buffer;
    const auto first_generation = a->generation;
    // Every buffer but one busy: that one is used, whatever the round robin would pick.
    for (int free = 0; free < navmap::render::kDmabufBuffers; ++free) {
        const std::uint32_t busy = ((1U << navmap::render::kDmabufBuffers) - 1) & ~(1U << free);
        auto f = r->exportFrame(t, busy);
        ASSERT_TRUE(f.has_value());
        EXPECT_EQ(f->buffer, free);
        if (f->fence_fd >= 0) ::close(f->fence_fd);
    }
    EXPECT_FALSE(r->exportFrame(t, (1U << navmap::render::kDmabufBuffers) - 1).has_value())
        << "every buffer busy: no export";
    // A buffer keeps its allocation (generation) while the size stays.
    for (int i = 0; i < navmap::render::kDmabufBuffers; ++i) {
        auto f = r->exportFrame(t, 0);
        ASSERT_TRUE(f.has_value());
        if (f->buffer == first) {
            EXPECT_EQ(f->generation, first_generation);
        }
        if (f->fence_fd >= 0) ::close(f->fence_fd);
    }
    r->resize(t, 80, 40);
    r->render(navmap::render::andorraFlyoverCamera(andorra().projection, 0.3));
    auto b = r->exportFrame(t, 0);
    ASSERT_TRUE(b.has_value());
    EXPECT_EQ(b->width, 80);
    EXPECT_GT(b->generation, first_generation) << "a new size: a new buffer, which clients must be told of";
    EXPECT_EQ(differingPixels(mapped(*b), r->readSync()), 0U);
}

}  // namespace
