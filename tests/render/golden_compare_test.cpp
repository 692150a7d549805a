// SPDX-License-Identifier: Apache-2.0
// The golden-image helper itself: it must catch a changed rendering and pass an equal one.
#include <gtest/gtest.h>

#include "golden.h"
#include "test_paths.h"

namespace {

using navmap::render::Image;

Image gradient(int w, int h) {
    Image img(w, h);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            auto* p = img.pixel(x, y);
            p[0] = static_cast<std::uint8_t>(x * 255 / w);
            p[1] = static_cast<std::uint8_t>(y * 255 / h);
            p[2] = 40;
            p[3] = 255;
        }
    return img;
}

TEST(GoldenCompare, EqualImagesHaveNoDifference) {
    const Image a = gradient(32, 16);
    const auto cmp = navmap::test::compareImages(a, a, 0);
    EXPECT_TRUE(cmp.sizes_match);
    EXPECT_EQ(cmp.differing_pixels, 0u);
    EXPECT_EQ(cmp.max_channel_difference, 0);
}

TEST(GoldenCompare, CountsPixelsBeyondTheChannelTolerance) {
    const Image a = gradient(32, 16);
    Image b = a;
    b.pixel(3, 4)[1] = static_cast<std::uint8_t>(b.pixel(3, 4)[1] + 20);  // beyond tolerance 8
    b.pixel(5, 6)[2] = static_cast<std::uint8_t>(b.pixel(5, 6)[2] + 5);   // within
    const auto cmp = navmap::test::compareImages(a, b, 8);
    EXPECT_EQ(cmp.differing_pixels, 1u);
    EXPECT_EQ(cmp.max_channel_difference, 20);
    EXPECT_EQ(cmp.diff.pixel(3, 4)[0], 255);  // marked red
    EXPECT_EQ(cmp.diff.pixel(3, 4)[1], 0);
}

TEST(GoldenCompare, SizeMismatchIsReported) {
    const auto cmp = navmap::test::compareImages(gradient(8, 8), gradient(8, 9), 8);
    EXPECT_FALSE(cmp.sizes_match);
}

TEST(GoldenCompare, MissingGoldenFailsAndWritesTheActualImage) {
    const auto result = navmap::test::matchesGolden(gradient(8, 8), "render/golden/does_not_exist.png");
    EXPECT_FALSE(result);
    EXPECT_NE(std::string(result.message()).find("does_not_exist.actual.png"), std::string::npos) << result.message();
    // Leave nothing for scripts/approve-goldens.sh to pick up.
    const auto failures = navmap::test::binaryDir() / "golden-failures";
    EXPECT_TRUE(std::filesystem::remove(failures / "render_golden_does_not_exist.target"));
    EXPECT_TRUE(std::filesystem::remove(failures / "render_golden_does_not_exist.actual.png"));
}

}  // namespace
