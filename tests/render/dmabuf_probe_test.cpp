// SPDX-License-Identifier: Apache-2.0
// The dma-buf export probe (docs/gles-profile.md "dma-buf export"): the decision from a
// display's extensions and render nodes, and what the no-op backend reports.

#include <gtest/gtest.h>

#include <unistd.h>

#include <filesystem>
#include <fstream>

#include "navmap/render/dmabuf_probe.h"
#include "navmap/render/renderer.h"

namespace {

using navmap::render::decideDmabuf;
using navmap::render::DmabufProbeInput;

constexpr const char* kAllExport =
    "EGL_KHR_image_base EGL_KHR_gl_texture_2D_image EGL_MESA_image_dma_buf_export EGL_KHR_surfaceless_context";

TEST(DmabufProbe, LlvmpipeWithoutExportOrRenderNodeSaysWhy) {
    const auto c = decideDmabuf({"EGL_KHR_image_base EGL_KHR_gl_texture_2D_image EGL_KHR_fence_sync",
                                 "surfaceless",
                                 "llvmpipe (LLVM 15.0.6, 256 bits)",
                                 {}});
    EXPECT_FALSE(c.available);
    EXPECT_FALSE(c.native_fence_sync);
    EXPECT_EQ(c.render_node, "");
    EXPECT_EQ(c.reason,
              "llvmpipe on the surfaceless platform: no EGL_MESA_image_dma_buf_export, no render node "
              "(/dev/dri/renderD*)");
}

TEST(DmabufProbe, NamesEveryMissingExtensionInOrder) {
    const auto c = decideDmabuf({"EGL_KHR_surfaceless_context", "device#0", "Mali-G78", {"/dev/dri/renderD128"}});
    EXPECT_FALSE(c.available);
    EXPECT_EQ(c.render_node, "/dev/dri/renderD128");
    EXPECT_EQ(c.reason,
              "Mali-G78 on the device#0 platform: no EGL_KHR_image_base, no EGL_KHR_gl_texture_2D_image, no "
              "EGL_MESA_image_dma_buf_export");
}

TEST(DmabufProbe, AvailableWithTheExtensionsAndARenderNode) {
    auto c = decideDmabuf({kAllExport, "surfaceless", "Mali-G78", {"/dev/dri/renderD128", "/dev/dri/renderD129"}});
    EXPECT_TRUE(c.available);
    EXPECT_EQ(c.reason, "");
    EXPECT_EQ(c.render_node, "/dev/dri/renderD128");
    EXPECT_FALSE(c.native_fence_sync);  // glFinish would synchronise
    c = decideDmabuf({std::string(kAllExport) + " EGL_KHR_fence_sync EGL_ANDROID_native_fence_sync",
                      "surfaceless",
                      "Mali-G78",
                      {"/dev/dri/renderD128"}});
    EXPECT_TRUE(c.available);
    EXPECT_TRUE(c.native_fence_sync);
    // A name that only starts like an extension is not it.
    c = decideDmabuf({"EGL_KHR_image_base EGL_KHR_gl_texture_2D_image EGL_MESA_image_dma_buf_export_x",
                      "surfaceless",
                      "Mali-G78",
                      {"/dev/dri/renderD128"}});
    EXPECT_FALSE(c.available);
    EXPECT_EQ(c.reason, "Mali-G78 on the surfaceless platform: no EGL_MESA_image_dma_buf_export");
}

TEST(DmabufProbe, FindsRenderNodesSortedAndNothingInAMissingFolder) {
    const auto dir = std::filesystem::temp_directory_path() / ("navmap-dri-" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir);
    for (const char* name : {"renderD129", "card0", "renderD128"}) std::ofstream(dir / name) << "";
    const auto nodes = navmap::render::findRenderNodes(dir.string());
    ASSERT_EQ(nodes.size(), 2U);
    EXPECT_EQ(nodes[0], (dir / "renderD128").string());
    EXPECT_EQ(nodes[1], (dir / "renderD129").string());
    std::filesystem::remove_all(dir);
    EXPECT_TRUE(navmap::render::findRenderNodes(dir.string()).empty());
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
