// SPDX-License-Identifier: Apache-2.0
// GPU tests: need an EGL context (Mesa llvmpipe through the surfaceless platform in CI).
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

#include "gl/gl_features.h"
#include "gl/shader_program.h"
#include "navmap/render/renderer.h"
#include "terrain_scene.h"
#include "test_paths.h"

namespace {

using navmap::render::Camera;
using navmap::render::Renderer;
using navmap::render::RendererOptions;
using navmap::render::RenderError;

RendererOptions smallOptions() {
    RendererOptions o;
    o.width = 160;
    o.height = 96;
    return o;
}

const navmap::render::TerrainScene& andorra() {
    static const auto kScene = navmap::render::loadTerrainScene(navmap::test::dataDir() / "N42E001.hgt");
    return kScene;
}

TEST(GlesRenderer, CreatesAHeadlessEs3ContextWithMsaa) {
    RendererOptions o = smallOptions();
    o.msaa_samples = 4;
    auto r = Renderer::create(o);
    const auto& dev = r->device();
    EXPECT_EQ(dev.backend, "gles");
    EXPECT_FALSE(dev.renderer.empty());
    EXPECT_EQ(dev.gles_major, 3);
    EXPECT_NE(dev.version.find("OpenGL ES 3"), std::string::npos) << dev.version;
    EXPECT_GE(dev.msaa_samples, 2) << "Mesa llvmpipe and every ES 3.0 driver offer at least 4x MSAA";
    std::printf("[ info     ] %s platform, %s, %s\n", dev.platform.c_str(), dev.renderer.c_str(), dev.version.c_str());
}

// The features turned off on a context follow from its version and extensions (docs/gles-profile.md).
// In the ES 3.0 run (render_gpu_tests_goldens_es30: Mesa held to ES 3.0, GL_EXT_color_buffer_float
// hidden) the context is ES 3.0 and the shadow-volume roads are off.
TEST(GlesRenderer, ListsTheFeaturesItTurnsOffOnThisContext) {
    RendererOptions o = smallOptions();
    o.msaa_samples = 4;
    auto r = Renderer::create(o);
    const auto& dev = r->device();
    const std::string version = "OpenGL ES " + std::to_string(dev.gles_major) + "." + std::to_string(dev.gles_minor);
    EXPECT_EQ(dev.version.rfind(version, 0), 0u) << dev.version << ": not the context made, " << version;
    // The context's own extension list (the renderer's context is current after create()).
    const auto gl = navmap::render::gl::GlFeatures::current(dev.gles_major, dev.gles_minor);
    const bool float_buffers = gl.hasExtension("GL_EXT_color_buffer_float") || dev.gles_minor >= 2;
    const auto& off = dev.features_off;
    const bool sv_off = std::any_of(off.begin(), off.end(),
                                    [](const std::string& f) { return f.rfind("shadow-volume roads (", 0) == 0; });
    EXPECT_EQ(sv_off, !float_buffers) << version;
    // MSAA is ES 3.0 core: 4x asked for is never turned off.
    EXPECT_TRUE(std::none_of(off.begin(), off.end(), [](const std::string& f) { return f.rfind("MSAA", 0) == 0; }));
    const char* forced = std::getenv("MESA_GLES_VERSION_OVERRIDE");
    const char* hidden = std::getenv("MESA_EXTENSION_OVERRIDE");
    if (forced && std::string(forced) == "3.0" && dev.version.find("Mesa") != std::string::npos) {
        EXPECT_EQ(version, "OpenGL ES 3.0");
        EXPECT_EQ(sv_off, hidden && std::strstr(hidden, "-GL_EXT_color_buffer_float") != nullptr)
            << (hidden ? hidden : "(unset)");
    }
    std::string list;
    for (const auto& f : off) list += "\n  " + f;
    std::printf("[ info     ] %s; features off:%s\n", dev.version.c_str(), list.empty() ? " none" : list.c_str());
}

TEST(GlesRenderer, AutoMsaaIsOffOnlyOnSoftwareRasterizers) {
    auto r = Renderer::create(smallOptions());  // msaa_samples = -1 (auto)
    const auto& dev = r->device();
    if (dev.software) {
        EXPECT_EQ(dev.msaa_samples, 0) << dev.renderer;
    } else {
        EXPECT_GE(dev.msaa_samples, 2) << dev.renderer;
    }
}

TEST(GlesRenderer, SurfacelessPlatformCanBeForced) {
    RendererOptions o = smallOptions();
    o.platform = navmap::render::Platform::Surfaceless;
    auto r = Renderer::create(o);
    EXPECT_EQ(r->device().platform, "surfaceless");
}

TEST(GlesRenderer, DevicePlatformCanBeForced) {
    RendererOptions o = smallOptions();
    o.platform = navmap::render::Platform::Device;
    try {
        auto r = Renderer::create(o);
        EXPECT_EQ(r->device().platform.rfind("device#", 0), 0u) << r->device().platform;
        r->render({});
        EXPECT_EQ(r->readSync().width, 160);
    } catch (const RenderError& e) {
        // Drivers without EGL_EXT_platform_device: the error must say so.
        EXPECT_NE(std::string(e.what()).find("device"), std::string::npos) << e.what();
        GTEST_SKIP() << "this EGL offers no usable device platform: " << e.what();
    }
}

TEST(GlesRenderer, BadPlatformOverrideIsAClearError) {
    ::setenv("NAVMAP_EGL_PLATFORM", "wayland", 1);
    try {
        (void)Renderer::create(smallOptions());
        ::unsetenv("NAVMAP_EGL_PLATFORM");
        FAIL() << "an unknown platform must be rejected";
    } catch (const RenderError& e) {
        ::unsetenv("NAVMAP_EGL_PLATFORM");
        EXPECT_NE(std::string(e.what()).find("NAVMAP_EGL_PLATFORM=wayland"), std::string::npos) << e.what();
    }
}

TEST(GlesRenderer, ShaderCompileErrorsNameFileAndLine) {
    auto r = Renderer::create(smallOptions());  // makes a context current
    const char* vert = "layout(location = 0) in vec3 p;\nvoid main() { gl_Position = vec4(p, 1.0); }\n";
    const char* frag = "out vec4 o;\nvoid main() {\n  o = vec4(undefined_thing, 1.0);\n}\n";
    try {
        (void)navmap::render::gl::ShaderProgram::fromSources("test_ok.vert", vert, "test_broken.frag", frag);
        FAIL() << "the broken shader compiled";
    } catch (const RenderError& e) {
        EXPECT_NE(std::string(e.what()).find("test_broken.frag:3"), std::string::npos) << e.what();
    }
}

TEST(GlesRenderer, LooksAtTheSkyWhenTheTerrainIsBehind) {
    auto r = Renderer::create(smallOptions());
    r->setTerrain(andorra().mesh);
    Camera up;
    up.eye = {0.0, 0.0, 5000.0};
    up.target = {0.0, 1.0, 9000.0};  // straight up-ish
    r->render(up);
    const auto image = r->readSync();
    const auto* px = image.pixel(80, 48);
    EXPECT_EQ(px[0], 158);
    EXPECT_EQ(px[1], 191);
    EXPECT_EQ(px[2], 230);
}

TEST(GlesRenderer, RingReadbackMatchesSynchronousReadback) {
    RendererOptions o = smallOptions();
    o.readback_ring = 3;
    auto r = Renderer::create(o);
    r->setTerrain(andorra().mesh);
    std::vector<navmap::render::Image> sync;
    for (int i = 0; i < 5; ++i) {
        r->render(navmap::render::andorraFlyoverCamera(andorra().projection, i / 5.0));
        sync.push_back(r->readSync());
    }
    std::vector<navmap::render::Frame> ring;
    for (int i = 0; i < 5; ++i) {
        r->render(navmap::render::andorraFlyoverCamera(andorra().projection, i / 5.0));
        auto f = r->readAsync(static_cast<std::uint64_t>(i));
        EXPECT_EQ(f.has_value(), i >= 3) << "the ring of 3 hands back frames from the 4th submit on";
        if (f) ring.push_back(std::move(*f));
    }
    for (auto& f : r->drainReadbacks()) ring.push_back(std::move(f));
    ASSERT_EQ(ring.size(), 5u);
    for (int i = 0; i < 5; ++i) {
        EXPECT_EQ(ring[i].sequence, static_cast<std::uint64_t>(i));
        EXPECT_EQ(ring[i].image.rgba, sync[i].rgba) << "frame " << i;
    }
    EXPECT_NE(sync[0].rgba, sync[2].rgba) << "the fly-over moves";
}

// One slot (and automatic on llvmpipe): no pixel-pack buffer; readAsync reads the frame and the
// next collectReadbacks (or drainReadbacks) hands it out, in order, equal to a synchronous read.
TEST(GlesRenderer, DirectReadbackHandsOutEveryFrameOnCollect) {
    for (int slots : {1, 0}) {
        RendererOptions o = smallOptions();
        o.readback_ring = slots;
        auto r = Renderer::create(o);
        r->setTerrain(andorra().mesh);
        std::vector<navmap::render::Frame> got;
        std::vector<navmap::render::Image> sync;
        for (int i = 0; i < 4; ++i) {
            r->render(navmap::render::andorraFlyoverCamera(andorra().projection, i / 4.0));
            sync.push_back(r->readSync());
            const auto f = r->readAsync(static_cast<std::uint64_t>(10 + i));
            if (r->device().software || slots == 1) {
                EXPECT_FALSE(f.has_value()) << "read now, handed out on collect";
            }
            if (f) got.push_back(*f);
            if (i % 2 == 1) {
                for (auto& c : r->collectReadbacks()) got.push_back(std::move(c));
            }
        }
        for (auto& c : r->drainReadbacks()) got.push_back(std::move(c));
        ASSERT_EQ(got.size(), 4u) << "slots " << slots;
        for (int i = 0; i < 4; ++i) {
            EXPECT_EQ(got[i].sequence, static_cast<std::uint64_t>(10 + i));
            EXPECT_EQ(got[i].image.rgba, sync[i].rgba) << "frame " << i;
        }
        EXPECT_TRUE(r->collectReadbacks().empty());
    }
}

// One context serves several displays: each target has its size and readback ring; what a
// target shows does not depend on what the others rendered in between.
TEST(GlesRenderer, TargetsShareOneContextAndKeepTheirOwnFramesAndRings) {
    RendererOptions o = smallOptions();
    o.readback_ring = 2;
    auto shared = Renderer::create(o);
    shared->setTerrain(andorra().mesh);
    const navmap::render::TargetHandle first = shared->primaryTarget();
    const navmap::render::TargetHandle wide = shared->addTarget(200, 60);
    EXPECT_NE(wide, first);
    EXPECT_EQ(shared->targetCount(), 2u);
    EXPECT_THROW(shared->render(navmap::render::TargetHandle(), Camera{}), RenderError) << "a handle of no target";
    EXPECT_THROW(shared->addTarget(0, 10), RenderError);

    RendererOptions wo = o;
    wo.width = 200;
    wo.height = 60;
    auto alone_small = Renderer::create(o);
    auto alone_wide = Renderer::create(wo);
    alone_small->setTerrain(andorra().mesh);
    alone_wide->setTerrain(andorra().mesh);

    std::vector<navmap::render::Frame> got_small, got_wide;
    for (int i = 0; i < 4; ++i) {
        const Camera a = navmap::render::andorraFlyoverCamera(andorra().projection, i / 4.0);
        const Camera b = navmap::render::andorraFlyoverCamera(andorra().projection, 0.9 - i / 8.0);
        shared->render(first, a);
        if (auto f = shared->readAsync(first, static_cast<std::uint64_t>(100 + i))) got_small.push_back(std::move(*f));
        EXPECT_EQ(shared->width(wide), 200);
        EXPECT_EQ(shared->height(wide), 60);
        shared->render(wide, b);
        if (auto f = shared->readAsync(wide, static_cast<std::uint64_t>(200 + i))) got_wide.push_back(std::move(*f));
        alone_small->render(a);
        alone_wide->render(b);
        EXPECT_EQ(shared->readSync(wide).rgba, alone_wide->readSync().rgba) << "wide target, frame " << i;
        EXPECT_EQ(shared->readSync(first).rgba, alone_small->readSync().rgba) << "first target, frame " << i;
    }
    for (auto& f : shared->drainReadbacks(first)) got_small.push_back(std::move(f));
    for (auto& f : shared->drainReadbacks(wide)) got_wide.push_back(std::move(f));
    ASSERT_EQ(got_small.size(), 4u);
    ASSERT_EQ(got_wide.size(), 4u);
    for (int i = 0; i < 4; ++i) {
        EXPECT_EQ(got_small[i].sequence, static_cast<std::uint64_t>(100 + i));
        EXPECT_EQ(got_wide[i].sequence, static_cast<std::uint64_t>(200 + i));
        EXPECT_EQ(got_small[i].image.width, 160);
        EXPECT_EQ(got_wide[i].image.width, 200);
        EXPECT_EQ(got_wide[i].image.height, 60);
    }
    EXPECT_TRUE(shared->removeTarget(wide));
    EXPECT_FALSE(shared->removeTarget(wide));
    EXPECT_THROW(shared->readSync(wide), RenderError) << "a removed target's handle";
    EXPECT_FALSE(shared->removeTarget(first)) << "the primary target stays";
    EXPECT_EQ(shared->width(), 160);
}

}  // namespace
