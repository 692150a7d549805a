// SPDX-License-Identifier: Apache-2.0
// The current street's bar (MapFrame::street_bar, docs/rendering.md "Street bar") in rendered
// frames of the Andorra store: a translucent dark panel at the bottom centre with the street's
// name and ref in white text, nothing when there is no street, long names cut with an ellipsis
// within the bar's widest, the night style's dimmer text; and labels kept out of it, by the
// layout's boxes and by the pixels.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "andorra_drive.h"
#include "gl/street_bar_layout.h"
#include "navmap/render/renderer.h"
#include "navmap/render/text/text_engine.h"

namespace {

using namespace navmap::render;
using navmap::render::gl::StreetBarLayout;

// The cluster's size.
constexpr int kW = 1280, kH = 480;
// The center display's bird's-eye view, where labels crowd the bottom of the frame.
constexpr int kBirdW = 1280, kBirdH = 720;

const StreetBar kMeritxell{"Avinguda Meritxell", "CG-1"};

// NAVMAP_GUIDANCE_DUMP=<dir> writes the images a test looks at.
void dump(const Image& image, const std::string& name) {
    if (const char* dir = std::getenv("NAVMAP_GUIDANCE_DUMP"))
        (void)writePng(std::string(dir) + "/" + name + ".png", image, nullptr);
}

StreetBarLayout layoutOf(const StreetBar& bar, int w, int h) {
    static text::TextEngine engine;
    engine.beginFrame();
    return gl::streetBarLayout(engine, bar, w, h);
}

MapFrame clusterFrame() { return navmap::test::settledAndorraFrame(ViewMode::Snail, kW, kH, 1800.0, 8.0); }

Image render(const MapFrame& frame, const MapStyle& style, int w, int h) {
    RendererOptions o;
    o.width = w;
    o.height = h;
    auto r = Renderer::create(o);
    r->setMapStyle(style);
    r->renderMap(frame);
    return r->readSync();
}

int maxDiff(const std::uint8_t* a, const std::uint8_t* b) {
    return std::max({std::abs(a[0] - b[0]), std::abs(a[1] - b[1]), std::abs(a[2] - b[2])});
}

bool inRect(int x, int y, glm::vec2 lo, glm::vec2 hi, float grow) {
    return x + 0.5f >= lo.x - grow && x + 0.5f <= hi.x + grow && y + 0.5f >= lo.y - grow && y + 0.5f <= hi.y + grow;
}

// What a bar changed against the same frame without it.
struct BarPixels {
    std::size_t outside = 0;  ///< pixels changed outside the panel (2 px of antialiasing allowed)
    std::size_t panel = 0;    ///< panel pixels (beside the text's box) as the panel colour over the map
    std::size_t panel_all = 0;
    std::size_t text = 0;  ///< bright text pixels in the text's box
    int text_max = 0;      ///< the brightest channel of the text
    int text_right = -1;   ///< the rightmost column of bright text
};

BarPixels barPixels(const Image& with, const Image& without, const StreetBarLayout& l, const MapStyle& style) {
    BarPixels n;
    const glm::vec4 panel = style.street_bar_panel;
    const float text_half_w = 0.5f * (l.hi.x - l.lo.x) - 16.0f * 1.6f;
    for (int y = 0; y < with.height; ++y)
        for (int x = 0; x < with.width; ++x) {
            const auto* a = with.pixel(x, y);
            const auto* b = without.pixel(x, y);
            if (!inRect(x, y, l.lo, l.hi, 2.0f)) {
                n.outside += maxDiff(a, b) > 0;
                continue;
            }
            const bool in_text = std::abs(x + 0.5f - l.text_centre.x) <= text_half_w + 2.0f &&
                                 std::abs(y + 0.5f - l.text_centre.y) <= 0.5f * l.text_px * 1.2f;
            if (in_text) {
                const int lum = std::min({a[0], a[1], a[2]});
                if (lum >= 180) {
                    ++n.text;
                    n.text_max = std::max(n.text_max, int(std::max({a[0], a[1], a[2]})));
                    n.text_right = std::max(n.text_right, x);
                }
                continue;
            }
            // Clear of the rounded corners: the panel's colour blended over the frame.
            const bool corner = (x < l.lo.x + l.corner_px || x > l.hi.x - l.corner_px) &&
                                (y < l.lo.y + l.corner_px || y > l.hi.y - l.corner_px);
            if (!inRect(x, y, l.lo, l.hi, -1.0f) || corner) continue;
            ++n.panel_all;
            bool as_blended = true;
            for (int c = 0; c < 3; ++c) {
                const float want = (1.0f - panel.a) * float(b[c]) + panel.a * 255.0f * panel[c];
                as_blended &= std::abs(float(a[c]) - want) <= 2.5f;
            }
            n.panel += as_blended;
        }
    return n;
}

TEST(StreetBar, TextIsNameAndRefOrTheOneThereIs) {
    EXPECT_EQ(gl::streetBarText(kMeritxell), "Avinguda Meritxell \xC2\xB7 CG-1");
    EXPECT_EQ(gl::streetBarText({"Avinguda Meritxell", ""}), "Avinguda Meritxell");
    EXPECT_EQ(gl::streetBarText({"", "CG-2"}), "CG-2");
    EXPECT_EQ(gl::streetBarText({"CG-2", "CG-2"}), "CG-2") << "a ref used as the name is not repeated";
    EXPECT_EQ(gl::streetBarText({}), "");
    EXPECT_TRUE(layoutOf({}, kW, kH).text.empty()) << "no text, no bar";
}

// The layout: centred at the bottom, sized to the text, legible (cap height) at the cluster's size.
TEST(StreetBar, LayoutSitsAtTheBottomCentreSizedToItsText) {
    const StreetBarLayout l = layoutOf(kMeritxell, kW, kH);
    const StreetBarLayout ref_only = layoutOf({"", "CG-1"}, kW, kH);
    EXPECT_FALSE(l.cut);
    EXPECT_NEAR(0.5f * (l.lo.x + l.hi.x), 0.5f * kW, 0.01f);
    EXPECT_GT(l.lo.y, 0.8f * kH);
    EXPECT_LT(l.hi.y, float(kH) - 8.0f) << "above the bottom edge";
    EXPECT_GE(l.text_px, 30.0f) << "legible at a glance on the cluster";
    EXPECT_LT(ref_only.hi.x - ref_only.lo.x, 0.5f * (l.hi.x - l.lo.x)) << "a shorter text, a shorter bar";
    EXPECT_EQ(ref_only.hi.y - ref_only.lo.y, l.hi.y - l.lo.y) << "the same height";
    EXPECT_LE(l.hi.x - l.lo.x, l.max_width_px);
}

// The bar in the cluster: the panel's colour over the map, white text in it, nothing else of
// the frame changed; no bar without a street.
TEST(StreetBar, ClusterShowsADarkPanelWithWhiteTextAtTheBottom) {
    MapFrame f = clusterFrame();
    const Image without = render(f, MapStyle::day(), kW, kH);
    f.street_bar = kMeritxell;
    const Image with = render(f, MapStyle::day(), kW, kH);
    dump(with, "street_bar_cluster");
    const StreetBarLayout l = layoutOf(kMeritxell, kW, kH);
    const BarPixels n = barPixels(with, without, l, MapStyle::day());
    EXPECT_EQ(n.outside, 0u) << "the bar changed pixels outside its panel";
    EXPECT_GE(n.panel_all, 1000u);
    EXPECT_EQ(n.panel, n.panel_all) << "panel pixels not the panel's colour over the map";
    EXPECT_GE(n.text, 1500u) << "too few white text pixels";
    EXPECT_GE(n.text_max, 250) << "the day style's text is white";
    // The text spans the panel but for its padding (the text's right end is its last letter).
    EXPECT_GT(n.text_right, int(l.hi.x - 16.0f * 1.6f - 12.0f));
    // No street: the frame is the frame without the bar.
    f.street_bar = StreetBar{};
    EXPECT_EQ(render(f, MapStyle::day(), kW, kH).rgba, without.rgba) << "an empty street draws no bar";
}

// A name too long for the bar is cut at a character and ends with an ellipsis; the panel stays
// within its widest, and the text reaches its right end (the ellipsis).
TEST(StreetBar, LongNamesAreCutWithAnEllipsisWithinTheBarsWidest) {
    const StreetBar long_name{
        "Carretera General de les Valls del Nord i de la Massana fins a la Frontera amb Fran\xC3\xA7"
        "a i m\xC3\xA9s enll\xC3\xA0",
        "CG-3"};
    const StreetBarLayout l = layoutOf(long_name, kW, kH);
    ASSERT_TRUE(l.cut);
    ASSERT_GE(l.text.size(), 3u);
    EXPECT_EQ(l.text.substr(l.text.size() - 3), "\xE2\x80\xA6");
    EXPECT_EQ(long_name.name.rfind(l.text.substr(0, l.text.size() - 3), 0), 0u) << "a start of the name: " << l.text;
    EXPECT_LE(l.hi.x - l.lo.x, l.max_width_px + 0.01f);
    EXPECT_GT(l.hi.x - l.lo.x, l.max_width_px - 0.05f * kW) << "cut no more than needed";
    EXPECT_NEAR(l.max_width_px, 0.6f * kW, 0.01f);
    // Cut at a character: every non-ASCII letter keeps all its bytes (the text is valid UTF-8).
    for (const std::size_t width : {40u, 60u, 79u, 80u, 81u, 82u, 95u}) {
        const StreetBar accents{std::string(width, 'x') + "\xC3\xA7\xC3\xA7\xC3\xA7\xC3\xA7" + std::string(60, 'y'),
                                ""};
        const std::string t = layoutOf(accents, 800, 240).text;
        std::size_t i = 0;
        while (i < t.size()) {
            const auto c = static_cast<unsigned char>(t[i]);
            const std::size_t len = c < 0x80 ? 1 : c >= 0xE0 ? 3 : 2;
            ASSERT_LE(i + len, t.size()) << width << ": " << t;
            for (std::size_t k = 1; k < len; ++k) ASSERT_EQ(static_cast<unsigned char>(t[i + k]) & 0xC0, 0x80) << t;
            i += len;
        }
    }
    MapFrame f = clusterFrame();
    const Image without = render(f, MapStyle::day(), kW, kH);
    f.street_bar = long_name;
    const Image with = render(f, MapStyle::day(), kW, kH);
    dump(with, "street_bar_long");
    const BarPixels n = barPixels(with, without, l, MapStyle::day());
    EXPECT_EQ(n.outside, 0u) << "nothing drawn beyond the bar's widest";
    EXPECT_EQ(n.panel, n.panel_all);
    EXPECT_GE(n.text, 3000u);
    EXPECT_GT(n.text_right, int(l.hi.x - 16.0f * 1.6f - 12.0f)) << "the ellipsis at the right end";
}

// Colours come from the style, so the day/night fade applies: at night the text is dimmer.
TEST(StreetBar, NightStyleDimsTheText) {
    MapFrame f = clusterFrame();
    const Image without = render(f, MapStyle::night(), kW, kH);
    f.street_bar = kMeritxell;
    const Image with = render(f, MapStyle::night(), kW, kH);
    const BarPixels n = barPixels(with, without, layoutOf(kMeritxell, kW, kH), MapStyle::night());
    EXPECT_EQ(n.outside, 0u);
    EXPECT_EQ(n.panel, n.panel_all);
    EXPECT_GE(n.text, 1500u);
    EXPECT_NEAR(n.text_max, 255.0f * MapStyle::night().street_bar_text.b, 3.0f);
}

// The bar lies under the vehicle marker: where the car comes low in the frame, over the bar, it
// stays visible there. The marker is moved back towards the camera until it stands in the bar.
TEST(StreetBar, TheVehicleMarkerStaysVisibleOverTheBar) {
    MapFrame f = clusterFrame();
    ASSERT_TRUE(f.marker);
    const StreetBarLayout l = layoutOf(kMeritxell, kW, kH);
    const glm::dvec2 back = glm::normalize(glm::dvec2(f.camera.eye - f.camera.target));
    std::optional<glm::dvec3> in_bar;
    for (double d = 0.0; d < 60.0 && !in_bar; d += 0.25) {
        glm::dvec3 p = f.marker->position + glm::dvec3(d * back, 0.0);
        p.z = navmap::test::andorraDrive().view->terrainHeight(p.x, p.y);
        const glm::vec4 c = f.camera.projection(double(kW) / kH) * f.camera.viewRelativeTo(p) * glm::vec4(0, 0, 0, 1);
        if (c.w <= 0.0f) break;
        const float y = (0.5f - 0.5f * c.y / c.w) * float(kH);
        if (y >= 0.5f * (l.lo.y + l.hi.y)) in_bar = p;
    }
    ASSERT_TRUE(in_bar) << "no point behind the car comes down into the bar";
    f.marker->position = *in_bar;
    f.street_bar = kMeritxell;
    const Image with = render(f, MapStyle::day(), kW, kH);
    dump(with, "street_bar_marker");
    const glm::vec4 red = MapStyle::day().marker_color;
    std::size_t marker_px = 0;
    for (int y = int(l.lo.y); y < int(l.hi.y); ++y)
        for (int x = int(l.lo.x); x < int(l.hi.x); ++x) {
            const auto* p = with.pixel(x, y);
            marker_px += std::abs(p[0] - 255.0f * red.r) <= 12 && std::abs(p[1] - 255.0f * red.g) <= 12 &&
                         std::abs(p[2] - 255.0f * red.b) <= 12;
        }
    EXPECT_GE(marker_px, 100u) << "the marker's own colour in the bar";
}

// Labels keep out of the bar (docs/labels.md "Keep-out"): in the center display's bird's-eye view,
// whose bottom has labels without the bar, none of the layout's placed label boxes meets the bar,
// no drawn glyph lies in it, and its pixels are those of the same frame without labels.
TEST(StreetBar, NoLabelIsPlacedOnTheBar) {
    RendererOptions o;
    o.width = kBirdW;
    o.height = kBirdH;
    const StreetBarLayout l = layoutOf(kMeritxell, kBirdW, kBirdH);
    const labels::OrientedBox bar_box{0.5f * (l.lo + l.hi), 0.5f * (l.hi - l.lo), {1.0f, 0.0f}};
    struct Shot {
        Image image{1, 1};
        MapFrameStats stats;
    };
    auto shoot = [&](bool labels_on, bool bar) {
        MapFrame f = navmap::test::settledAndorraFrame(ViewMode::Bird, kBirdW, kBirdH, 1800.0, 0.0);
        f.layers.labels = labels_on;
        f.frame_dt_s = 1.0 / 30.0;
        if (bar) f.street_bar = kMeritxell;
        auto r = Renderer::create(o);
        for (int i = 0; i < (labels_on ? 60 : 1); ++i) r->renderMap(f);
        return Shot{r->readSync(), r->mapStats()};
    };
    auto placedOnBar = [&](const MapFrameStats& s) {
        std::size_t n = 0;
        for (const labels::PlacedLabel& p : s.placed_labels) n += p.alpha > 0.0f && p.box.intersects(bar_box);
        return n;
    };
    auto glyphsOnBar = [&](const MapFrameStats& s) {
        std::size_t n = 0;
        for (const labels::DrawnLabel& d : s.drawn_labels) {
            if (d.opacity <= 0.0f) continue;
            for (const labels::ScreenQuad& q : d.glyph_boxes) {
                glm::vec2 lo(1e9f), hi(-1e9f);
                for (const glm::vec2 c : q) {
                    lo = glm::min(lo, c);
                    hi = glm::max(hi, c);
                }
                n += hi.x > l.lo.x && lo.x < l.hi.x && hi.y > l.lo.y && lo.y < l.hi.y;
            }
        }
        return n;
    };
    auto changedInBar = [&](const Image& a, const Image& b) {
        std::size_t n = 0;
        for (int y = int(l.lo.y); y <= int(l.hi.y); ++y)
            for (int x = int(l.lo.x); x <= int(l.hi.x); ++x) n += maxDiff(a.pixel(x, y), b.pixel(x, y)) > 2;
        return n;
    };
    // Without the bar the labels lie there: the test can fail.
    const Shot bare = shoot(false, false), labelled = shoot(true, false);
    dump(labelled.image, "street_bar_labels_without_bar");
    ASSERT_GT(placedOnBar(labelled.stats), 0u) << "no label where the bar goes: the test shows nothing";
    ASSERT_GT(changedInBar(labelled.image, bare.image), 100u);
    // With it: none there, by the layout's boxes, the drawn glyphs and the pixels.
    const Shot bar_bare = shoot(false, true), bar_labelled = shoot(true, true);
    dump(bar_labelled.image, "street_bar_labels");
    EXPECT_GE(bar_labelled.stats.labels_visible, 5u) << "labels elsewhere";
    EXPECT_EQ(placedOnBar(bar_labelled.stats), 0u);
    EXPECT_EQ(glyphsOnBar(bar_labelled.stats), 0u);
    EXPECT_EQ(changedInBar(bar_labelled.image, bar_bare.image), 0u) << "label pixels in the bar";
}

}  // namespace
