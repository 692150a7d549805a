// SPDX-License-Identifier: Apache-2.0
// Day to night without a flash (docs/rendering.md "Day and night"): real frames of the Andorra
// store rendered across the 2 s cross-fade at the shipped profiles' 30 frames per second, as
// navmapd draws them (one renderer, the style set before each frame). The mean luminance of no
// frame differs from the previous frame's by more than 10 %, and the end frames are the day and
// the night frames.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <vector>

#include "andorra_drive.h"
#include "navmap/render/renderer.h"
#include "navmap/render/style_fade.h"

namespace {

using namespace navmap::render;

// Rec. 709 luma of the 8-bit sRGB values, averaged over the frame, 0..1.
double meanLuminance(const Image& image) {
    double sum = 0.0;
    for (std::size_t i = 0; i + 3 < image.rgba.size(); i += 4)
        sum += 0.2126 * image.rgba[i] + 0.7152 * image.rgba[i + 1] + 0.0722 * image.rgba[i + 2];
    return sum / (255.0 * double(image.rgba.size() / 4));
}

bool samePixels(const Image& a, const Image& b) {
    return a.width == b.width && a.height == b.height && a.rgba.size() == b.rgba.size() &&
           std::memcmp(a.rgba.data(), b.rgba.data(), a.rgba.size()) == 0;
}

struct Profile {
    const char* name;
    ViewMode view;
    int width, height;
    double fps;
};

class StyleFadeFrames : public ::testing::TestWithParam<Profile> {};

TEST_P(StyleFadeFrames, NoFrameStepsMoreThanTenPercentInLuminance) {
    const Profile p = GetParam();
    const MapFrame frame = navmap::test::settledAndorraFrame(p.view, p.width, p.height);
    RendererOptions o;
    o.width = p.width;
    o.height = p.height;
    const auto render_with = [&](Renderer& r, const MapStyle& style) {
        r.setMapStyle(style);
        r.renderMap(frame);
        return r.readSync();
    };
    const auto fresh = Renderer::create(o);
    const Image day = render_with(*fresh, MapStyle::day());
    const Image night = render_with(*fresh, MapStyle::night());

    for (const bool to_night : {true, false}) {
        const auto renderer = Renderer::create(o);
        StyleFade fade;
        fade.reset(!to_night);
        const double start_s = 50.0;
        fade.target(to_night, start_s);
        const int frames = static_cast<int>(std::lround(kStyleFadeS * p.fps));
        std::vector<double> luminance;
        Image first, last;
        for (int k = 0; k <= frames; ++k) {
            const float w = fade.weightAt(start_s + k / p.fps);
            const Image image = render_with(*renderer, mixStyles(MapStyle::day(), MapStyle::night(), w));
            luminance.push_back(meanLuminance(image));
            if (k == 0) first = image;
            if (k == frames) last = image;
        }
        double worst = 0.0;
        int worst_at = 0;
        for (std::size_t k = 1; k < luminance.size(); ++k) {
            const double step = std::abs(luminance[k] - luminance[k - 1]) / luminance[k - 1];
            if (step > worst) {
                worst = step;
                worst_at = static_cast<int>(k);
            }
        }
        std::printf("%s %s: %zu frames, mean luminance %.4f -> %.4f, largest step %.2f %% (frame %d)\n", p.name,
                    to_night ? "day->night" : "night->day", luminance.size(), luminance.front(), luminance.back(),
                    100.0 * worst, worst_at);
        EXPECT_LE(worst, 0.10) << p.name << " at frame " << worst_at;
        EXPECT_TRUE(samePixels(first, to_night ? day : night)) << p.name << ": the first frame is not the start style";
        EXPECT_TRUE(samePixels(last, to_night ? night : day)) << p.name << ": the last frame is not the end style";
        // A fade that does something: night is much darker than day.
        EXPECT_LT(std::min(luminance.front(), luminance.back()), 0.7 * std::max(luminance.front(), luminance.back()));
    }
}

// The shipped profiles (daemon/profiles.cpp): the cluster's snail's view and the centre display's
// bird's-eye view, both at 30 frames per second.
INSTANTIATE_TEST_SUITE_P(StyleFade, StyleFadeFrames,
                         ::testing::Values(Profile{"cluster", ViewMode::Snail, 1280, 480, 30.0},
                                           Profile{"center", ViewMode::Bird, 1280, 720, 30.0}),
                         [](const auto& param_info) { return std::string(param_info.param.name); });

}  // namespace
