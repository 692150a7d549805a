// SPDX-License-Identifier: Apache-2.0
// Shaping of real Andorran names: glyph counts, no .notdef, per-glyph font fallback.
#include <gtest/gtest.h>

#include <string>

#include "navmap/render/text/text_shaper.h"
#include "text_test_util.h"

namespace {

using namespace navmap::render::text;

TEST(TextShaping, DebianChainIsDejaVuThenDroidFallback) {
    NAVMAP_REQUIRE_FONTS(fonts);
    const auto& regular = fonts->chain(FontStyle::Regular);
    ASSERT_EQ(regular.size(), 2u);
    EXPECT_EQ(fonts->name(regular[0]), "DejaVu Sans");
    EXPECT_EQ(fonts->name(regular[1]), "Droid Sans Fallback");
    EXPECT_EQ(fonts->name(fonts->chain(FontStyle::Bold)[0]), "DejaVu Sans Bold");
    // The fallback file is loaded once for both chains.
    EXPECT_EQ(fonts->chain(FontStyle::Bold)[1], regular[1]);
    EXPECT_EQ(fonts->size(), 3u);
}

struct NameCase {
    const char* utf8;
    std::size_t glyphs;
};

TEST(TextShaping, AndorranNamesShapeWithoutNotdef) {
    NAVMAP_REQUIRE_FONTS(fonts);
    TextShaper shaper(*fonts);
    // Precomposed à, ò and the middle dot of l·l are single glyphs in DejaVu Sans.
    const NameCase cases[] = {{"Sant Julià de Lòria", 19}, {"Col·legi", 8}, {"Ordino", 6}};
    for (const NameCase& c : cases) {
        for (FontStyle style : {FontStyle::Regular, FontStyle::Bold}) {
            const ShapedText t = shaper.shape(c.utf8, style);
            EXPECT_EQ(t.glyphs.size(), c.glyphs) << c.utf8;
            EXPECT_EQ(t.missing, 0u) << c.utf8;
            EXPECT_EQ(t.invalid_bytes, 0u);
            const FontId primary = fonts->chain(style)[0];
            for (const ShapedGlyph& g : t.glyphs) {
                EXPECT_NE(g.glyph, 0u) << c.utf8 << " cluster " << g.cluster;
                EXPECT_EQ(g.font, primary) << c.utf8 << ": Latin text must come from DejaVu Sans";
            }
            EXPECT_GT(t.advance, 0.3f * static_cast<float>(c.glyphs));
        }
    }
}

TEST(TextShaping, ClustersAreByteOffsetsOfTheSource) {
    NAVMAP_REQUIRE_FONTS(fonts);
    TextShaper shaper(*fonts);
    const ShapedText t = shaper.shape("Col·legi");  // '·' is two bytes (C2 B7)
    ASSERT_EQ(t.glyphs.size(), 8u);
    const std::uint32_t expected[] = {0, 1, 2, 3, 5, 6, 7, 8};
    for (std::size_t i = 0; i < 8; ++i) EXPECT_EQ(t.glyphs[i].cluster, expected[i]) << i;
}

TEST(TextShaping, CjkNameFromTheOsmDataComesFromTheFallbackFont) {
    NAVMAP_REQUIRE_FONTS(fonts);
    TextShaper shaper(*fonts);
    const FontId dejavu = fonts->chain(FontStyle::Regular)[0];
    const FontId fallback = fonts->chain(FontStyle::Regular)[1];
    EXPECT_FALSE(fonts->hasCodepoint(dejavu, U'安'));
    // name= of a parking node in andorra-2021-04-14.osm.pbf, and "Andorra" in Chinese.
    for (const char* name : {"利奥尔茨小镇停车场", "安道尔"}) {
        const ShapedText t = shaper.shape(name);
        EXPECT_EQ(t.missing, 0u) << name;
        for (const ShapedGlyph& g : t.glyphs) {
            EXPECT_NE(g.glyph, 0u) << name;
            EXPECT_EQ(g.font, fallback) << name;
        }
    }
    EXPECT_EQ(shaper.shape("安道尔").glyphs.size(), 3u);
}

TEST(TextShaping, MixedScriptsSwitchFontPerGlyph) {
    NAVMAP_REQUIRE_FONTS(fonts);
    TextShaper shaper(*fonts);
    const FontId dejavu = fonts->chain(FontStyle::Regular)[0];
    const FontId fallback = fonts->chain(FontStyle::Regular)[1];
    const ShapedText t = shaper.shape("Andorra 安道尔 la Vella");
    ASSERT_EQ(t.glyphs.size(), 20u);
    EXPECT_EQ(t.missing, 0u);
    // "Andorra " from DejaVu (the space stays with the preceding Latin run), CJK from Droid.
    for (std::size_t i = 0; i < 8; ++i) EXPECT_EQ(t.glyphs[i].font, dejavu) << i;
    for (std::size_t i = 8; i < 11; ++i) EXPECT_EQ(t.glyphs[i].font, fallback) << i;
    for (std::size_t i = 12; i < 20; ++i) EXPECT_EQ(t.glyphs[i].font, dejavu) << i;
}

TEST(TextShaping, CombiningMarkStaysWithItsBase) {
    NAVMAP_REQUIRE_FONTS(fonts);
    TextShaper shaper(*fonts);
    // "Lòria" with a decomposed ò (o + U+0300): DejaVu composes or positions the mark.
    const ShapedText t = shaper.shape("Lo\xCC\x80ria");
    EXPECT_EQ(t.missing, 0u);
    for (const ShapedGlyph& g : t.glyphs) EXPECT_EQ(g.font, fonts->chain(FontStyle::Regular)[0]);
    const ShapedText pre = shaper.shape("Lòria");
    EXPECT_NEAR(t.advance, pre.advance, 1e-3f);
}

TEST(TextShaping, MalformedUtf8IsReplacedAndCounted) {
    NAVMAP_REQUIRE_FONTS(fonts);
    TextShaper shaper(*fonts);
    const std::string bad = std::string("Ordi") + "\xC3" + "no" + "\xE4\xB8" + "\xF8\x88\x80\x80\x80";
    const ShapedText t = shaper.shape(bad);
    EXPECT_EQ(t.invalid_bytes, 1u + 2u + 5u);
    EXPECT_EQ(t.glyphs.size(), 6u + 8u);  // every bad byte is one U+FFFD (DejaVu has it)
    EXPECT_EQ(t.missing, 0u);
    for (const ShapedGlyph& g : t.glyphs) EXPECT_LT(g.cluster, bad.size());
    EXPECT_TRUE(shaper.shape("").glyphs.empty());
}

TEST(TextShaping, MissingFontFileNamesTheFile) {
    FontFiles files;
    files.regular = {"/nonexistent/NoSuchFont.ttf"};
    files.bold = files.regular;
    try {
        FontCollection fonts(files);
        FAIL() << "expected TextError";
    } catch (const TextError& e) {
        EXPECT_NE(std::string(e.what()).find("/nonexistent/NoSuchFont.ttf: "), std::string::npos) << e.what();
    }
    FontFiles empty;
    EXPECT_THROW(FontCollection{empty}, TextError);
}

TEST(TextShaping, Deterministic) {
    NAVMAP_REQUIRE_FONTS(fonts);
    TextShaper a(*fonts);
    TextShaper b(*fonts);
    const ShapedText x = a.shape("Sant Julià de Lòria 安道尔");
    (void)a.shape("Ordino");
    const ShapedText y = b.shape("Sant Julià de Lòria 安道尔");
    ASSERT_EQ(x.glyphs.size(), y.glyphs.size());
    for (std::size_t i = 0; i < x.glyphs.size(); ++i) {
        EXPECT_EQ(x.glyphs[i].glyph, y.glyphs[i].glyph);
        EXPECT_EQ(x.glyphs[i].x_advance, y.glyphs[i].x_advance);
    }
}

}  // namespace
