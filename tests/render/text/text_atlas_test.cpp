// SPDX-License-Identifier: Apache-2.0
// SDF generation, atlas packing/growth/eviction, layout and metrics.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "navmap/render/text/atlas_packer.h"
#include "navmap/render/text/glyph_atlas.h"
#include "navmap/render/text/sdf_generator.h"
#include "navmap/render/text/text_engine.h"
#include "navmap/render/text/text_layout.h"
#include "navmap/render/text/text_shaper.h"
#include "text/label_text_style.h"
#include "text_test_util.h"

namespace {

using namespace navmap::render::text;

TEST(SdfGenerator, DiscHasSignedDistances) {
    // A disc of radius 40 px in a 128 x 128 coverage image, downsampled 4x -> 32 x 32 texels,
    // radius 10 texels, spread 4 texels.
    const int n = 128;
    std::vector<std::uint8_t> cov(n * n, 0);
    for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x)
            if (std::hypot(x + 0.5 - 64.0, y + 0.5 - 64.0) < 40.0) cov[y * n + x] = 255;
    const GrayImage sdf = makeSdf(cov, n, n, n, 4, 4.0f);
    ASSERT_EQ(sdf.width, 32);
    ASSERT_EQ(sdf.height, 32);
    for (int y = 0; y < 32; ++y) {
        for (int x = 0; x < 32; ++x) {
            const double d = 10.0 - std::hypot(x + 0.5 - 16.0, y + 0.5 - 16.0);  // texels, + inside
            const double expected = std::clamp(0.5 + d / 8.0, 0.0, 1.0) * 255.0;
            EXPECT_NEAR(sdf.pixels[y * 32 + x], expected, 10.0) << x << "," << y;
        }
    }
    EXPECT_EQ(sdf.pixels[16 * 32 + 16], 255);                    // center: 10 texels inside, saturated
    EXPECT_EQ(sdf.pixels[0], 0);                                 // corner: far outside
    EXPECT_TRUE(makeSdf(cov, n, n, n, 3, 4.0f).pixels.empty());  // 128 is not a multiple of 3
}

TEST(AtlasPacker, ShelvesFillRowsThenGrowDownwards) {
    AtlasPacker p(64, 32);
    const auto a = p.pack(30, 10);
    const auto b = p.pack(30, 9);
    ASSERT_TRUE(a && b);
    EXPECT_EQ(a->y, 0);
    EXPECT_EQ(b->y, 0);  // same shelf: 10 rows (+1 padding) holds 9 (+1)
    EXPECT_EQ(b->x, 31);
    const auto c = p.pack(20, 20);  // too tall for shelf 0: new shelf below
    ASSERT_TRUE(c);
    EXPECT_EQ(c->y, 11);
    EXPECT_FALSE(p.pack(50, 20));  // not beside c (21 + 51 > 64), no room below (11 + 21 + 21 > 32)
    EXPECT_EQ(p.usedHeight(), 32);
    p.grow(64);
    const auto d = p.pack(50, 20);
    ASSERT_TRUE(d);
    EXPECT_EQ(d->y, 32);
    EXPECT_EQ(d->x, 0);
    EXPECT_FALSE(p.pack(64, 1));  // 64 + 1 padding > width
    p.clear();
    EXPECT_EQ(p.pack(10, 10)->y, 0);
}

TEST(GlyphAtlas, SdfInsideAboveHalfOutsideBelow) {
    NAVMAP_REQUIRE_FONTS(fonts);
    TextShaper shaper(*fonts);
    GlyphAtlas atlas(*fonts);
    const ShapedText t = shaper.shape("I");  // one vertical stem
    ASSERT_EQ(t.glyphs.size(), 1u);
    const AtlasGlyph* g = atlas.glyph(t.glyphs[0].font, t.glyphs[0].glyph);
    ASSERT_NE(g, nullptr);
    ASSERT_FALSE(g->empty);
    const AtlasParams& p = atlas.params();
    // The quad spans the ink plus the spread margin on both sides.
    EXPECT_NEAR(g->width * p.base_em_px, g->texels.w, 1e-3);
    EXPECT_NEAR(g->height * p.base_em_px, g->texels.h, 1e-3);
    EXPECT_GT(g->texels.w, 2 * p.spread_px);
    auto at = [&](int x, int y) {
        return static_cast<int>(
            atlas.pixels()[static_cast<std::size_t>(g->texels.y + y) * atlas.width() + g->texels.x + x]);
    };
    const int cy = g->texels.h / 2;
    int peak = 0;
    for (int x = 0; x < g->texels.w; ++x)
        if (at(x, cy) > at(peak, cy)) peak = x;
    EXPECT_GT(at(peak, cy), 140) << "stem center is inside (> 0.5)";
    EXPECT_LT(at(1, cy), 100) << "margin left of the stem is outside (< 0.5)";
    EXPECT_LT(at(g->texels.w - 2, cy), 100);
    EXPECT_LT(at(peak, 0), 20) << "above the glyph, a full spread away: saturated outside";
    // Unimodal across the stem: falls off on both sides, crossing 0.5 once on each.
    int crossings = 0;
    for (int x = 1; x < g->texels.w; ++x) {
        if (x <= peak)
            EXPECT_LE(at(x - 1, cy), at(x, cy) + 2) << x;
        else
            EXPECT_GE(at(x - 1, cy) + 2, at(x, cy)) << x;
        crossings += (at(x - 1, cy) >= 128) != (at(x, cy) >= 128);
    }
    EXPECT_EQ(crossings, 2);
    // The field falls by about 255 / (2 spread) per texel near the edge.
    int left_edge = peak;
    while (left_edge > 0 && at(left_edge - 1, cy) >= 128) --left_edge;
    const int slope = at(left_edge, cy) - at(left_edge - 2, cy);
    EXPECT_NEAR(slope, 2 * 255 / (2 * p.spread_px), 6);
}

TEST(GlyphAtlas, SpaceIsEmptyAndCjkIsRasterized) {
    NAVMAP_REQUIRE_FONTS(fonts);
    TextShaper shaper(*fonts);
    GlyphAtlas atlas(*fonts);
    const ShapedText sp = shaper.shape(" ");
    const AtlasGlyph* g = atlas.glyph(sp.glyphs[0].font, sp.glyphs[0].glyph);
    ASSERT_NE(g, nullptr);
    EXPECT_TRUE(g->empty);
    const ShapedText cjk = shaper.shape("安");
    const AtlasGlyph* c = atlas.glyph(cjk.glyphs[0].font, cjk.glyphs[0].glyph);
    ASSERT_NE(c, nullptr);
    EXPECT_FALSE(c->empty);
    EXPECT_GT(c->width, 0.9f);  // a CJK ideograph is about one em wide (+ margins)
    EXPECT_EQ(atlas.stats().rasterized, 1u);
    EXPECT_EQ(atlas.glyph(cjk.glyphs[0].font, cjk.glyphs[0].glyph), c);  // cached
    EXPECT_EQ(atlas.stats().rasterized, 1u);
}

TEST(GlyphAtlas, GrowsThenEvictsUnusedGlyphs) {
    NAVMAP_REQUIRE_FONTS(fonts);
    TextShaper shaper(*fonts);
    AtlasParams params;
    params.width = 256;
    params.initial_height = 32;
    params.max_height = 256;
    GlyphAtlas atlas(*fonts, params);
    const ShapedText upper = shaper.shape("ABCDEFGHIJKLMNOPQRSTUVWXYZ");
    const ShapedText lower = shaper.shape("abcdefghijklmnopqrstuvwxyz");
    auto request = [&](const ShapedText& t) {
        std::size_t refused = 0;
        for (const ShapedGlyph& g : t.glyphs) refused += atlas.glyph(g.font, g.glyph) == nullptr;
        return refused;
    };
    // Frame 1: the upper case fits after growing; the lower case overflows the maximum height.
    const AtlasGlyph first = *atlas.glyph(upper.glyphs[0].font, upper.glyphs[0].glyph);
    EXPECT_EQ(request(upper), 0u);
    EXPECT_GT(atlas.height(), 32);
    EXPECT_EQ(atlas.glyph(upper.glyphs[0].font, upper.glyphs[0].glyph)->texels.y,
              first.texels.y);  // growth keeps texels
    const std::size_t refused = request(lower);
    ASSERT_GT(refused, 0u);
    EXPECT_EQ(atlas.stats().overflows, refused);
    EXPECT_EQ(atlas.height(), 256);
    // Frame 2: everything was used in frame 1, nothing can go; only the lower case is used.
    atlas.beginFrame();
    EXPECT_EQ(atlas.stats().evicted, 0u);
    EXPECT_GT(request(lower), 0u);
    // Frame 3: the upper case (unused in frame 2) is evicted, the rest repacked; all fits.
    const std::uint64_t v = atlas.version();
    atlas.beginFrame();
    EXPECT_EQ(atlas.stats().evicted, 26u);
    EXPECT_EQ(atlas.stats().repacks, 1u);
    EXPECT_GT(atlas.version(), v);
    EXPECT_EQ(atlas.dirtyFirstRow(), 0);
    EXPECT_EQ(atlas.dirtyEndRow(), 256);
    EXPECT_EQ(request(lower), 0u);
    EXPECT_EQ(atlas.stats().glyphs, 26u);
}

TEST(TextLayout, MetricsScaleLinearlyWithSize) {
    NAVMAP_REQUIRE_FONTS(fonts);
    TextShaper shaper(*fonts);
    GlyphAtlas atlas(*fonts);
    const ShapedText t = shaper.shape("Sant Julià de Lòria");
    const TextMetrics m10 = measureText(t, 10.0f);
    const TextMetrics m30 = measureText(t, 30.0f);
    EXPECT_NEAR(m30.width, 3.0f * m10.width, 1e-3f);
    EXPECT_NEAR(m30.height, 3.0f * m10.height, 1e-3f);
    EXPECT_NEAR(m10.height, m10.ascent + m10.descent, 1e-4f);
    EXPECT_GT(m10.width, 80.0f);  // 19 characters at 10 px
    EXPECT_LT(m10.width, 130.0f);
    EXPECT_NEAR(m10.height, 11.64f, 0.05f);  // DejaVu Sans: ascender 0.928, descender -0.236
    // Quads scale the same way and are centered on the anchor.
    const LaidOutText l10 = layoutText(t, atlas, 10.0f);
    const LaidOutText l30 = layoutText(t, atlas, 30.0f);
    ASSERT_EQ(l10.quads.size(), 16u);  // 19 glyphs, 3 spaces without quads
    ASSERT_EQ(l30.quads.size(), l10.quads.size());
    float minx = 1e9f, maxx = -1e9f;
    for (std::size_t i = 0; i < l10.quads.size(); ++i) {
        EXPECT_NEAR(l30.quads[i].p0.x, 3.0f * l10.quads[i].p0.x, 1e-3f);
        EXPECT_NEAR(l30.quads[i].p1.y, 3.0f * l10.quads[i].p1.y, 1e-3f);
        EXPECT_EQ(l30.quads[i].t0, l10.quads[i].t0);  // same atlas texels at any size
        minx = std::min(minx, l10.quads[i].p0.x);
        maxx = std::max(maxx, l10.quads[i].p1.x);
    }
    const float margin = static_cast<float>(atlas.params().spread_px) / atlas.params().base_em_px * 10.0f;
    EXPECT_NEAR(minx + maxx, 0.0f, 1.5f);  // symmetric about the anchor (up to side bearings)
    EXPECT_LT(maxx, 0.5f * m10.width + margin + 0.5f);
}

TEST(TextLayout, IconTextPutsTheIconFirst) {
    NAVMAP_REQUIRE_FONTS(fonts);
    TextShaper shaper(*fonts);
    GlyphAtlas atlas(*fonts);
    const LabelTextStyle poi = labelTextStyle(navmap::map::LabelKind::Poi, 2);
    ASSERT_FALSE(poi.icon.empty());
    const ShapedText icon = shaper.shape(poi.icon, poi.font);
    EXPECT_EQ(icon.missing, 0u) << "DejaVu Sans has the POI symbols";
    const ShapedText name = shaper.shape("Museu del Tabac", poi.font);
    const LaidOutText l = layoutIconText(icon, name, atlas, 20.0f);
    ASSERT_EQ(l.quads.size(), 1u + 13u);
    EXPECT_EQ(l.quads[0].layer, 1);
    for (std::size_t i = 1; i < l.quads.size(); ++i) {
        EXPECT_EQ(l.quads[i].layer, 0);
        EXPECT_GT(l.quads[i].p1.x, l.quads[0].p1.x);
    }
    EXPECT_GT(l.metrics.width, measureText(name, 20.0f).width + 20.0f);
}

TEST(LabelTextStyle, PlacesShrinkWithClass) {
    using navmap::map::LabelKind;
    using navmap::map::PlaceClass;
    const auto size = [](PlaceClass c) {
        return labelTextStyle(LabelKind::Place, static_cast<std::uint8_t>(c)).size_px;
    };
    EXPECT_GT(size(PlaceClass::City), size(PlaceClass::Town));
    EXPECT_GT(size(PlaceClass::Town), size(PlaceClass::Village));
    EXPECT_GT(size(PlaceClass::Village), size(PlaceClass::Hamlet));
    // Unknown subclass: the smallest class's size, which still has readable capitals (15 px type,
    // 11 px caps; docs/labels.md "Text sizes").
    EXPECT_EQ(labelTextStyle(LabelKind::Place, 200).size_px, size(PlaceClass::Other));
    EXPECT_GE(size(PlaceClass::Other), 15.0f);
    const LabelTextStyle road = labelTextStyle(LabelKind::Road, 5);
    EXPECT_TRUE(road.icon.empty());
    EXPECT_GT(road.style.outline_px, 0.0f);  // seed 4.5.2: dark outline ...
    EXPECT_GT(road.style.halo_px, 0.0f);     // ... and halo
    EXPECT_LT(road.style.outline.r, 0.2f);
}

// Glyphs made ahead on the prefetch thread (start-up) give the atlas exactly the pixels and
// quads of glyphs rasterized when asked for, and are taken instead of rasterized again; names
// with letters outside the prefetched set are rasterized as before.
TEST(TextEngine, PrefetchedGlyphsLayOutAsTheOnesRasterizedOnDemand) {
    NAVMAP_REQUIRE_FONTS(fonts);
    TextEngine plain, prefetched;
    prefetched.prefetchGlyphs(TextEngine::latinCodepoints());
    prefetched.atlas().waitForPrefetch();
    const char* names[] = {"Andorra la Vella",  "Sant Julià de Lòria", "Escaldes-Engordany", "Encamp 1200 m",
                           "Ordino (Església)", "Pas de la Casa",      "Ζ Ω Ж 東京"};
    for (const char* name : names) {
        for (const FontStyle style : {FontStyle::Regular, FontStyle::Bold}) {
            plain.beginFrame();
            prefetched.beginFrame();
            const LaidOutText a = plain.layout(plain.run(name, style), 18.0f);
            const LaidOutText b = prefetched.layout(prefetched.run(name, style), 18.0f);
            ASSERT_EQ(a.quads.size(), b.quads.size()) << name;
            for (std::size_t i = 0; i < a.quads.size(); ++i) {
                EXPECT_EQ(a.quads[i].p0, b.quads[i].p0) << name << " glyph " << i;
                EXPECT_EQ(a.quads[i].p1, b.quads[i].p1) << name << " glyph " << i;
                EXPECT_EQ(a.quads[i].t0, b.quads[i].t0) << name << " glyph " << i;
                EXPECT_EQ(a.quads[i].t1, b.quads[i].t1) << name << " glyph " << i;
            }
        }
    }
    EXPECT_EQ(plain.atlas().pixels(), prefetched.atlas().pixels());
    EXPECT_EQ(plain.atlas().stats().prefetched, 0U);
    EXPECT_GT(prefetched.atlas().stats().prefetched, 40U);
    // Only what no prefetched glyph covered was rasterized when asked for: the Greek, Cyrillic and
    // CJK letters of the last name (two styles).
    EXPECT_GT(prefetched.atlas().stats().rasterized, 0U);
    EXPECT_LE(prefetched.atlas().stats().rasterized, 12U);
    EXPECT_EQ(prefetched.atlas().stats().rasterized + prefetched.atlas().stats().prefetched,
              plain.atlas().stats().rasterized);
}

TEST(TextEngine, AnEngineDestroyedWhilePrefetchingStopsItsThread) {
    NAVMAP_REQUIRE_FONTS(fonts);
    for (int i = 0; i < 5; ++i) {
        TextEngine engine;
        engine.prefetchGlyphs(TextEngine::latinCodepoints());
        engine.beginFrame();
        EXPECT_FALSE(engine.layout(engine.run("Canillo"), 16.0f).quads.empty());
    }  // destroyed at once: the thread stops between glyphs and is joined
}

TEST(TextEngine, CachesRunsAndLaysOut) {
    std::string why;
    if (navmap::render::text::debianFontFiles().regular.size() < 2)
        GTEST_SKIP() << "needs fonts-dejavu-core and fonts-droid-fallback";
    TextEngineOptions options;
    options.max_runs = 2;
    TextEngine engine(options);
    engine.beginFrame();
    const RunId a = engine.run("Ordino");
    const RunId b = engine.run("Ordino", FontStyle::Bold);
    EXPECT_NE(a, b);
    EXPECT_EQ(engine.run("Ordino"), a);
    engine.run("Canillo");
    EXPECT_EQ(engine.shaped(a).glyphs.size(), 6u);
    const LaidOutText l = engine.layout(a, 16.0f);
    EXPECT_EQ(l.quads.size(), 6u);
    EXPECT_FLOAT_EQ(l.metrics.width, engine.measure(a, 16.0f).width);
    EXPECT_GT(engine.measure(b, 16.0f).width, l.metrics.width);  // bold is wider
    engine.beginFrame();                                         // 3 runs > max_runs 2: emptied
    EXPECT_EQ(engine.runsGeneration(), 1u);
    EXPECT_EQ(engine.run("Canillo"), 0u);
}

}  // namespace
