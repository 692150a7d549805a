// SPDX-License-Identifier: Apache-2.0
#pragma once
// Shared helpers of the text tests: the Debian fonts or a skip saying which are missing.

#include <gtest/gtest.h>

#include <memory>
#include <string>

#include "navmap/render/text/font_collection.h"

namespace navmap::test {

/// The fonts of debianFontFiles() with the CJK fallback, or nullptr and `why`.
inline std::unique_ptr<render::text::FontCollection> loadDebianFonts(std::string* why) {
    const render::text::FontFiles files = render::text::debianFontFiles();
    if (files.regular.size() < 2) {
        *why = "needs fonts-dejavu-core and fonts-droid-fallback (DejaVuSans.ttf, DroidSansFallbackFull.ttf)";
        return nullptr;
    }
    return std::make_unique<render::text::FontCollection>(files);
}

}  // namespace navmap::test

/// Skips the test (saying why) when the Debian fonts are not installed. `fonts_var` names the
/// variables it declares, so it cannot be parenthesized.
// NOLINTBEGIN(bugprone-macro-parentheses)
#define NAVMAP_REQUIRE_FONTS(fonts_var)                                 \
    std::string fonts_var##_why;                                        \
    auto fonts_var = ::navmap::test::loadDebianFonts(&fonts_var##_why); \
    if (!fonts_var) GTEST_SKIP() << fonts_var##_why
// NOLINTEND(bugprone-macro-parentheses)
