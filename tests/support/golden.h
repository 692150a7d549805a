// SPDX-License-Identifier: Apache-2.0
#pragma once
// Golden-image comparison (Filament backend tests / MapLibre render-test style). Goldens live
// beside their tests (tests/<module>/golden/<name>.png), the render goldens as data in
// tests/render/cases/<name>/expected.png (docs/architecture.md "Render cases"). On a mismatch the actual image and a
// diff image are written to <build>/golden-failures/ and named in the failure message;
// scripts/approve-goldens.sh copies the actual images over the goldens.

#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "navmap/render/image.h"

namespace navmap::test {

/// How far an image may drift from its golden.
struct GoldenTolerance {
    int channel = 8;                        ///< max |difference| per channel for a pixel to count as equal
    double max_differing_fraction = 0.005;  ///< fraction of pixels allowed to differ beyond `channel`
};

struct GoldenComparison {
    bool sizes_match = false;
    std::size_t differing_pixels = 0;
    double differing_fraction = 0.0;
    int max_channel_difference = 0;
    render::Image diff;  ///< differing pixels red over a dimmed copy of the golden
};

/// Pure comparison (also unit-tested).
GoldenComparison compareImages(const render::Image& expected, const render::Image& actual, int channel_tolerance);

/// Compares `actual` with tests/<golden_relative_path>. Passes or describes the failure,
/// writing the actual and diff images. A missing golden fails and writes the actual image.
::testing::AssertionResult matchesGolden(const render::Image& actual, const std::string& golden_relative_path,
                                         const GoldenTolerance& tolerance = {});

}  // namespace navmap::test

/// EXPECT_GOLDEN(image, "render/cases/andorra_heightfield/expected.png", tolerance)
#define EXPECT_GOLDEN(image, path, ...) \
    EXPECT_TRUE(::navmap::test::matchesGolden((image), (path)__VA_OPT__(, ) __VA_ARGS__))
