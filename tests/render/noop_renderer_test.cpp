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
    const int second = r->addTarget(16, 4);
    EXPECT_NE(second, 0);
    EXPECT_EQ(r->currentTarget(), 0);
    EXPECT_FALSE(r->readAsync(1));
    r->useTarget(second);
    EXPECT_EQ(r->width(), 16);
    EXPECT_FALSE(r->readAsync(10)) << "the second target's ring is its own";
    EXPECT_FALSE(r->readAsync(11));
    auto oldest = r->readAsync(12);
    ASSERT_TRUE(oldest);
    EXPECT_EQ(oldest->sequence, 10u);
    EXPECT_EQ(oldest->image.width, 16);
    EXPECT_EQ(oldest->image.height, 4);
    r->useTarget(0);
    const auto first = r->drainReadbacks();
    ASSERT_EQ(first.size(), 1u);
    EXPECT_EQ(first[0].sequence, 1u);
    EXPECT_EQ(first[0].image.width, 8);
    EXPECT_THROW(r->useTarget(7), navmap::render::RenderError);
    EXPECT_TRUE(r->removeTarget(second));
    EXPECT_FALSE(r->removeTarget(0));
}

}  // namespace
