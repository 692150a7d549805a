// SPDX-License-Identifier: Apache-2.0
// The dma-buf export probe (docs/gles-profile.md "dma-buf export"): the decision from a
// display's extensions and DRM nodes, a failed allocation as the reason, and what the no-op
// backend reports.

#include <gtest/gtest.h>

#include <unistd.h>

#include <filesystem>
#include <fstream>

#include "navmap/render/dmabuf_probe.h"
#include "navmap/render/renderer.h"

namespace {

using navmap::render::decideDmabuf;
using navmap::render::DmabufProbeInput;

constexpr const char* kEglExport = "EGL_KHR_image_base EGL_EXT_image_dma_buf_import EGL_KHR_surfaceless_context";
constexpr const char* kGlExport = "GL_EXT_color_buffer_float GL_OES_EGL_image";

TEST(DmabufProbe, LlvmpipeWithoutADrmNodeSaysWhy) {
    const auto c = decideDmabuf({kEglExport, kGlExport, "surfaceless", "llvmpipe (LLVM 15.0.6, 256 bits)", {}});
    EXPECT_FALSE(c.available);
    EXPECT_FALSE(c.native_fence_sync);
    EXPECT_EQ(c.drm_node, "");
    EXPECT_EQ(c.reason, "llvmpipe on the surfaceless platform: no DRM node (/dev/dri/renderD*, /dev/dri/card*)");
}

TEST(DmabufProbe, NamesEveryMissingExtensionInOrder) {
    const auto c = decideDmabuf(
        {"EGL_KHR_surfaceless_context", "GL_OES_EGL_image_external", "device#0", "Mali-G78", {"/dev/dri/renderD128"}});
    EXPECT_FALSE(c.available);
    EXPECT_EQ(c.drm_node, "/dev/dri/renderD128");
    EXPECT_EQ(c.reason,
              "Mali-G78 on the device#0 platform: no EGL_KHR_image_base, no EGL_EXT_image_dma_buf_import, no "
              "GL_OES_EGL_image");
}

TEST(DmabufProbe, AvailableWithTheExtensionsAndADrmNode) {
    auto c =
        decideDmabuf({kEglExport, kGlExport, "surfaceless", "Mali-G78", {"/dev/dri/renderD128", "/dev/dri/card0"}});
    EXPECT_TRUE(c.available);
    EXPECT_EQ(c.reason, "");
    EXPECT_EQ(c.drm_node, "/dev/dri/renderD128");
    EXPECT_FALSE(c.native_fence_sync);  // glFinish synchronises
    c = decideDmabuf({std::string(kEglExport) + " EGL_KHR_fence_sync EGL_ANDROID_native_fence_sync",
                      kGlExport,
                      "surfaceless",
                      "Mali-G78",
                      {"/dev/dri/card0"}});
    EXPECT_TRUE(c.available);
    EXPECT_TRUE(c.native_fence_sync);
    // A name that only starts like an extension is not it.
    c = decideDmabuf({"EGL_KHR_image_base EGL_EXT_image_dma_buf_import_modifiers",
                      kGlExport,
                      "surfaceless",
                      "Mali-G78",
                      {"/dev/dri/renderD128"}});
    EXPECT_FALSE(c.available);
    EXPECT_EQ(c.reason, "Mali-G78 on the surfaceless platform: no EGL_EXT_image_dma_buf_import");
}

TEST(DmabufProbe, AFailedAllocationBecomesTheReason) {
    auto c = decideDmabuf(
        {kEglExport, kGlExport, "surfaceless", "llvmpipe (LLVM 15.0.6, 256 bits)", {"/dev/dri/renderD128"}});
    ASSERT_TRUE(c.available);
    navmap::render::refuseDmabuf(c, "llvmpipe (LLVM 15.0.6, 256 bits)", "surfaceless",
                                 "/dev/dri/renderD128: no buffer (Permission denied)");
    EXPECT_FALSE(c.available);
    EXPECT_EQ(c.reason,
              "llvmpipe on the surfaceless platform: GBM allocates no linear ABGR8888 render buffer "
              "(/dev/dri/renderD128: no buffer (Permission denied))");
}

TEST(DmabufProbe, FindsRenderNodesFirstThenPrimaryNodesAndNothingInAMissingFolder) {
    const auto dir = std::filesystem::temp_directory_path() / ("navmap-dri-" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir);
    for (const char* name : {"renderD129", "card1", "card0", "renderD128", "by-path"}) std::ofstream(dir / name) << "";
    const auto nodes = navmap::render::findDrmNodes(dir.string());
    ASSERT_EQ(nodes.size(), 4U);
    EXPECT_EQ(nodes[0], (dir / "renderD128").string());
    EXPECT_EQ(nodes[1], (dir / "renderD129").string());
    EXPECT_EQ(nodes[2], (dir / "card0").string());
    EXPECT_EQ(nodes[3], (dir / "card1").string());
    std::filesystem::remove_all(dir);
    EXPECT_TRUE(navmap::render::findDrmNodes(dir.string()).empty());
}

TEST(DmabufProbe, TheNoopRendererExportsNothing) {
    navmap::render::RendererOptions o;
    o.width = 64;
    o.height = 32;
    const auto r = navmap::render::Renderer::createNoop(o);
    EXPECT_FALSE(r->device().dmabuf.available);
    EXPECT_EQ(r->device().dmabuf.reason, "the no-op renderer draws into no GPU buffers");
}

}  // namespace
