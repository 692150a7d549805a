// SPDX-License-Identifier: Apache-2.0
#include "golden.h"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>

#include "test_paths.h"

namespace navmap::test {

GoldenComparison compareImages(const render::Image& expected, const render::Image& actual, int channel_tolerance) {
    GoldenComparison result;
    result.sizes_match = expected.width == actual.width && expected.height == actual.height;
    if (!result.sizes_match) return result;
    result.diff = render::Image(expected.width, expected.height);
    for (int y = 0; y < expected.height; ++y) {
        for (int x = 0; x < expected.width; ++x) {
            const std::uint8_t* e = expected.pixel(x, y);
            const std::uint8_t* a = actual.pixel(x, y);
            int worst = 0;
            for (int c = 0; c < 4; ++c) worst = std::max(worst, std::abs(int(e[c]) - int(a[c])));
            result.max_channel_difference = std::max(result.max_channel_difference, worst);
            std::uint8_t* d = result.diff.pixel(x, y);
            if (worst > channel_tolerance) {
                ++result.differing_pixels;
                d[0] = 255, d[1] = 0, d[2] = 0;
            } else {
                const int grey = (e[0] + e[1] + e[2]) / 12;  // dimmed golden for context
                d[0] = d[1] = d[2] = static_cast<std::uint8_t>(grey);
            }
            d[3] = 255;
        }
    }
    result.differing_fraction =
        static_cast<double>(result.differing_pixels) / (static_cast<double>(expected.width) * expected.height);
    return result;
}

::testing::AssertionResult matchesGolden(const render::Image& actual, const std::string& golden_relative_path,
                                         const GoldenTolerance& tolerance) {
    const std::filesystem::path golden = sourceDir() / "tests" / golden_relative_path;
    const std::filesystem::path failures = binaryDir() / "golden-failures";
    std::error_code unwritable;  // then a failure's images cannot be written; the verdict stands
    std::filesystem::create_directories(failures, unwritable);
    std::string flat = golden_relative_path;
    std::replace(flat.begin(), flat.end(), '/', '_');
    const auto actual_path = failures / (std::filesystem::path(flat).stem().string() + ".actual.png");
    const auto diff_path = failures / (std::filesystem::path(flat).stem().string() + ".diff.png");
    const auto target_path = failures / (std::filesystem::path(flat).stem().string() + ".target");
    std::string error;
    // scripts/approve-goldens.sh reads <name>.target to know where <name>.actual.png belongs.
    auto note_target = [&] { std::ofstream(target_path) << "tests/" << golden_relative_path << "\n"; };

    render::Image expected;
    if (!render::readImage(golden, &expected, &error)) {
        (void)render::writePng(actual_path, actual, nullptr);
        note_target();
        return ::testing::AssertionFailure()
               << "golden " << golden << " unreadable (" << error << "); actual image written to " << actual_path
               << " (approve with scripts/approve-goldens.sh)";
    }
    const GoldenComparison cmp = compareImages(expected, actual, tolerance.channel);
    if (!cmp.sizes_match) {
        (void)render::writePng(actual_path, actual, nullptr);
        note_target();
        return ::testing::AssertionFailure()
               << "golden " << golden << " is " << expected.width << "x" << expected.height << ", actual "
               << actual.width << "x" << actual.height << "; actual written to " << actual_path;
    }
    if (cmp.differing_fraction > tolerance.max_differing_fraction) {
        (void)render::writePng(actual_path, actual, nullptr);
        (void)render::writePng(diff_path, cmp.diff, nullptr);
        note_target();
        std::ostringstream msg;
        msg.precision(3);
        msg << "image differs from golden " << golden << ": " << cmp.differing_pixels << " pixels ("
            << cmp.differing_fraction * 100.0 << "%, allowed " << tolerance.max_differing_fraction * 100.0
            << "%) beyond channel tolerance " << tolerance.channel << ", max channel difference "
            << cmp.max_channel_difference << "\n  actual: " << actual_path << "\n  diff:   " << diff_path;
        return ::testing::AssertionFailure() << msg.str();
    }
    // How close a passing image came, in the test's output (side-by-side comparisons across
    // machines and GL versions read it: docs/packaging.md, docs/gles-profile.md).
    std::printf("golden %s: max channel difference %d, %zu pixels (%.3f%%) beyond %d\n", golden_relative_path.c_str(),
                cmp.max_channel_difference, cmp.differing_pixels, cmp.differing_fraction * 100.0, tolerance.channel);
    // Stale results of an earlier failure go; a read-only build tree (a test run inside a guest
    // that mounts it read-only) has none to remove and is no failure.
    std::error_code ignored;
    std::filesystem::remove(actual_path, ignored);
    std::filesystem::remove(diff_path, ignored);
    std::filesystem::remove(target_path, ignored);
    return ::testing::AssertionSuccess();
}

}  // namespace navmap::test
