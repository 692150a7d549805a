// SPDX-License-Identifier: Apache-2.0
// The no-op backend: the Renderer API without a GL context, for tests outside render/.
#include <gtest/gtest.h>

#include "navmap/render/renderer.h"

namespace {

using navmap::render::Renderer;
using navmap::render::RendererOptions;

TEST(NoopRenderer, FramesHaveTheRequestedSizeAndSkyColour) {
    RendererOptions options;
    options.width = 64;
    options.height = 32;
    auto r = Renderer::createNoop(options);
    EXPECT_EQ(r->device().backend, "noop");
    r->render({});
    const auto image = r->readSync();
    ASSERT_EQ(image.width, 64);
    ASSERT_EQ(image.height, 32);
    const auto* px = image.pixel(10, 10);
    EXPECT_EQ(px[0], 158);  // default sky 0.62, 0.75, 0.90
    EXPECT_EQ(px[1], 191);
    EXPECT_EQ(px[2], 230);
    EXPECT_EQ(px[3], 255);
}

TEST(NoopRenderer, AsyncReadbackFollowsTheRingContract) {
    RendererOptions options;
    options.width = 8;
    options.height = 8;
    options.readback_ring = 3;
    auto r = Renderer::createNoop(options);
    EXPECT_FALSE(r->readAsync(0));
    EXPECT_FALSE(r->readAsync(1));
    EXPECT_FALSE(r->readAsync(2));
    auto oldest = r->readAsync(3);
    ASSERT_TRUE(oldest);
    EXPECT_EQ(oldest->sequence, 0u);
    const auto rest = r->drainReadbacks();
    ASSERT_EQ(rest.size(), 3u);
    EXPECT_EQ(rest[0].sequence, 1u);
    EXPECT_EQ(rest[2].sequence, 3u);
}

TEST(NoopRenderer, TargetsHaveTheirOwnSizeAndRing) {
    RendererOptions options;
    options.width = 8;
    options.height = 8;
    options.readback_ring = 2;
    auto r = Renderer::createNoop(options);
    const navmap::render::TargetHandle first = r->primaryTarget();
    const navmap::render::TargetHandle second = r->addTarget(16, 4);
    EXPECT_NE(second, first);
    EXPECT_FALSE(r->readAsync(first, 1));
    EXPECT_EQ(r->width(second), 16);
    EXPECT_EQ(r->width(first), 8);
    EXPECT_FALSE(r->readAsync(second, 10)) << "the second target's ring is its own";
    EXPECT_FALSE(r->readAsync(second, 11));
    auto oldest = r->readAsync(second, 12);
    ASSERT_TRUE(oldest);
    EXPECT_EQ(oldest->sequence, 10u);
    EXPECT_EQ(oldest->image.width, 16);
    EXPECT_EQ(oldest->image.height, 4);
    const auto drained = r->drainReadbacks(first);
    ASSERT_EQ(drained.size(), 1u);
    EXPECT_EQ(drained[0].sequence, 1u);
    EXPECT_EQ(drained[0].image.width, 8);
    EXPECT_THROW(r->renderMap(navmap::render::TargetHandle(), navmap::render::MapFrame{}), navmap::render::RenderError);
    EXPECT_TRUE(r->removeTarget(second));
    EXPECT_FALSE(r->removeTarget(second));
    EXPECT_THROW(r->readSync(second), navmap::render::RenderError) << "a removed target's handle";
    EXPECT_FALSE(r->removeTarget(first));
}

}  // namespace
