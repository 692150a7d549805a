// SPDX-License-Identifier: Apache-2.0
// Glowing roads (seed 5.3.5, 5.5.2) and the transparency label aura (seed 5.3.3, 5.5.1) in
// rendered map frames of the Andorra store: which pixels glow, that a world-space label behind
// a building becomes readable with its road visible around it (the golden views of both
// techniques are render cases, tests/render/cases/andorra_{glow_single,glow_road,aura}_*).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <string>
#include <vector>

#include "andorra_drive.h"
#include "drive_scene.h"
#include "navmap/render/renderer.h"
#include "test_paths.h"

namespace {

using namespace navmap::render;
using GlowMode = MapLayers::GlowMode;

constexpr int kW = 640, kH = 240;
// The aura tests render at the cluster's size: at 640 x 240 no world-space label of the drive
// stands behind a building (the view holds few, small labels).
constexpr int kAuraW = 1280, kAuraH = 480;
// A pose found by OcclusionSearch.FindAuraPose (below): in snail's view this far along the drive,
// a world-space road label stands behind buildings of Andorra la Vella.
constexpr double kAuraMeasure = 1800.0;
// Road and route parts pass behind buildings at these poses (OcclusionSearch.FindGlowPose): in
// bird's-eye only close by (at standstill), since from higher up the roads' view-space offset
// (seed 3.6.2) lifts them over the low buildings of the valley.
struct GlowPose {
    double measure, speed_mps;
};
GlowPose glowPose(ViewMode mode) { return mode == ViewMode::Bird ? GlowPose{300.0, 0.0} : GlowPose{1800.0, 13.0}; }
constexpr int kSettleFrames = 30;  // labels fade in and settle

MapFrame frameAt(ViewMode mode, double measure, double speed_mps = 13.0, int w = kW, int h = kH) {
    MapFrame frame = navmap::test::settledAndorraFrame(mode, w, h, measure, speed_mps);
    frame.frame_dt_s = 1.0 / 30.0;
    return frame;
}

MapFrame glowFrame(ViewMode mode) { return frameAt(mode, glowPose(mode).measure, glowPose(mode).speed_mps); }

std::unique_ptr<Renderer> makeRenderer(const MapStyle& style = MapStyle::day(), int w = kW, int h = kH) {
    RendererOptions o;
    o.width = w;
    o.height = h;
    auto r = Renderer::create(o);
    r->setMapStyle(style);
    return r;
}

Image render(const MapFrame& frame, int frames = 1, const MapStyle& style = MapStyle::day(),
             MapFrameStats* stats = nullptr, int w = kW, int h = kH) {
    auto r = makeRenderer(style, w, h);
    for (int i = 0; i < frames; ++i) r->renderMap(frame);
    if (stats) *stats = r->mapStats();
    return r->readSync();
}

struct Rgb {
    int r, g, b;
};
Rgb at(const Image& im, int x, int y) {
    const auto i = (static_cast<std::size_t>(y) * static_cast<std::size_t>(im.width) + static_cast<std::size_t>(x)) * 4;
    return {im.rgba[i], im.rgba[i + 1], im.rgba[i + 2]};
}
int dist(Rgb a, Rgb b) { return std::max({std::abs(a.r - b.r), std::abs(a.g - b.g), std::abs(a.b - b.b)}); }
Rgb toRgb(glm::vec3 c) {
    auto q = [](float v) { return static_cast<int>(std::lround(std::clamp(v, 0.0f, 1.0f) * 255.0f)); };
    return {q(c.r), q(c.g), q(c.b)};
}

const char* viewName(ViewMode m) { return m == ViewMode::Bird ? "bird" : "snail"; }

// NAVMAP_OCCLUSION_DUMP=<dir> writes the images a test compares, for looking at them.
void dump(const Image& image, const std::string& name) {
    if (const char* dir = std::getenv("NAVMAP_OCCLUSION_DUMP")) {
        std::string error;
        if (!writePng(std::string(dir) + "/" + name + ".png", image, &error)) std::printf("dump: %s\n", error.c_str());
    }
}

// ---------------------------------------------------------------------------------------------
// Glowing roads.

TEST(GlowRoads, OffByDefault) {
    const MapLayers l;
    EXPECT_FALSE(l.glow_roads);
    EXPECT_FALSE(l.label_aura);
    EXPECT_FALSE(l.glow_blur);
    EXPECT_EQ(l.glow_mode, GlowMode::SingleColor);
}

class GlowRoadsView : public ::testing::TestWithParam<ViewMode> {};

// Full-strength single colour: every pixel the glow changes is exactly the glow colour and lies
// where a building covers the scene; roads not hidden by buildings do not change.
TEST_P(GlowRoadsView, HiddenRoadPixelsGetTheGlowColourOnlyWithGlowOn) {
    MapStyle style = MapStyle::day();
    style.glow_strength = 1.0f;
    style.glow_color = {1.0f, 0.0f, 1.0f};  // magenta: nowhere else in the map
    const MapFrame base = glowFrame(GetParam());
    MapFrame glow = base;
    glow.layers.glow_roads = true;
    MapFrame open = base;
    open.layers.buildings = false;
    // Compared with the glow at zero strength: the glow keeps the terrain's depth, so the
    // buildings are drawn after the terrain, not before as without the glow. Apart from depth
    // ties where walls meet the ground that order changes nothing.
    MapStyle invisible = style;
    invisible.glow_strength = 0.0f;
    const Image off = render(base, 1, style);
    const Image without = render(glow, 1, invisible);
    const Image with = render(glow, 1, style);
    const Image no_buildings = render(open, 1, style);
    std::size_t order_differs = 0;
    for (int y = 0; y < kH; ++y) {
        for (int x = 0; x < kW; ++x) order_differs += dist(at(off, x, y), at(without, x, y)) > 0;
    }
    EXPECT_LE(order_differs, std::size_t(kW * kH / 5000)) << "glow off and at zero strength draw the same";
    dump(off, std::string("glow_off_") + viewName(GetParam()));
    dump(without, std::string("glow_base_") + viewName(GetParam()));
    dump(with, std::string("glow_on_") + viewName(GetParam()));
    dump(no_buildings, std::string("glow_open_") + viewName(GetParam()));
    const Rgb magenta{255, 0, 255};
    std::size_t changed = 0, glow_coloured = 0, under_building = 0, magenta_before = 0;
    for (int y = 0; y < kH; ++y) {
        for (int x = 0; x < kW; ++x) {
            magenta_before += dist(at(without, x, y), magenta) <= 2;
            if (dist(at(with, x, y), at(without, x, y)) == 0) continue;
            ++changed;
            glow_coloured += dist(at(with, x, y), magenta) <= 2;
            under_building += dist(at(without, x, y), at(no_buildings, x, y)) > 0;
        }
    }
    std::printf("%s: %zu glowing pixels, %zu magenta, %zu under buildings\n", viewName(GetParam()), changed,
                glow_coloured, under_building);
    EXPECT_EQ(magenta_before, 0u) << "without glow no pixel has the glow colour";
    EXPECT_GT(changed, 80u) << "roads pass behind buildings at this pose";
    EXPECT_EQ(glow_coloured, changed) << "changed pixels are the glow colour";
    // A few building pixels may look like the scene behind them.
    EXPECT_GE(double(under_building), 0.99 * double(changed)) << "only pixels where a building hides the scene glow";
}

// Road-colour mode: glowing pixels carry a road class fill or the route colour.
TEST_P(GlowRoadsView, RoadColourModeUsesTheRoadsOwnColours) {
    MapStyle style = MapStyle::day();
    style.glow_strength = 1.0f;
    std::vector<Rgb> palette;
    for (const auto& c : style.roads.classes) palette.push_back(toRgb(c.fill));
    palette.push_back(toRgb(style.route_color));
    const MapFrame base = glowFrame(GetParam());
    MapFrame glow = base;
    glow.layers.glow_roads = true;
    glow.layers.glow_mode = GlowMode::RoadColor;
    MapStyle invisible = style;
    invisible.glow_strength = 0.0f;  // the same pass order (see above)
    const Image without = render(glow, 1, invisible);
    const Image with = render(glow, 1, style);
    std::size_t changed = 0, road_coloured = 0;
    for (int y = 0; y < kH; ++y) {
        for (int x = 0; x < kW; ++x) {
            if (dist(at(with, x, y), at(without, x, y)) == 0) continue;
            ++changed;
            const Rgb c = at(with, x, y);
            road_coloured += std::any_of(palette.begin(), palette.end(), [&](Rgb p) { return dist(c, p) <= 2; });
        }
    }
    EXPECT_GT(changed, 80u);
    EXPECT_EQ(road_coloured, changed);
}

// Blur spreads the glow beyond the hidden road pixels, and reports its pass time when profiled.
TEST_P(GlowRoadsView, BlurSoftensAndIsProfiled) {
    const MapFrame base = glowFrame(GetParam());
    MapFrame sharp = base, soft = base;
    sharp.layers.glow_roads = soft.layers.glow_roads = true;
    soft.layers.glow_blur = true;
    const Image without = render(base);
    const Image a = render(sharp);
    RendererOptions o;
    o.width = kW;
    o.height = kH;
    o.profile_passes = true;
    auto r = Renderer::create(o);
    r->renderMap(soft);
    EXPECT_GT(r->mapStats().glow_ms, 0.0);
    EXPECT_EQ(r->mapStats().aura_ms, 0.0);
    const Image b = r->readSync();
    std::size_t changed_sharp = 0, changed_soft = 0;
    for (int y = 0; y < kH; ++y) {
        for (int x = 0; x < kW; ++x) {
            changed_sharp += dist(at(a, x, y), at(without, x, y)) > 0;
            changed_soft += dist(at(b, x, y), at(without, x, y)) > 0;
        }
    }
    EXPECT_GT(changed_soft, changed_sharp * 5 / 4) << "the blurred halo reaches around the glowing roads";
}

// The glow draws no road again: one screen pass over the stencil marks, three vertices, whatever
// the roads in view (their fill pass marked where a building hides it as they were drawn).
TEST_P(GlowRoadsView, TheGlowIsOneScreenPassWithoutTheRoadsDrawnAgain) {
    MapFrame glow = glowFrame(GetParam());
    glow.layers.glow_roads = true;
    for (const bool blur : {false, true}) {
        glow.layers.glow_blur = blur;
        MapFrameStats stats;
        (void)render(glow, 1, MapStyle::day(), &stats);
        EXPECT_GT(stats.road_segments, 100u);
        // Without blur the screen pass; with it also the two blur passes and the composite.
        EXPECT_EQ(stats.glow_work.draw_calls, blur ? 4u : 1u);
        EXPECT_EQ(stats.glow_work.vertices, blur ? 12u : 3u);
    }
}

INSTANTIATE_TEST_SUITE_P(Views, GlowRoadsView, ::testing::Values(ViewMode::Bird, ViewMode::Snail),
                         [](const auto& p) { return std::string(viewName(p.param)); });

// ---------------------------------------------------------------------------------------------
// Transparency label aura.

// Pixels of one label: its text (labels on vs off, no buildings) inside its layout box.
struct LabelPixels {
    labels::PlacedLabel label;
    std::vector<std::pair<int, int>> text;
    std::size_t hidden = 0;  // text pixels that show the building instead (aura off)
};

struct AuraScene {
    MapFrame frame;
    Image labels_open, plain_open, labels_built, plain_built, no_roads_open;
    std::vector<labels::PlacedLabel> placed;
};

AuraScene auraScene(const MapFrame& frame) {
    AuraScene s;
    s.frame = frame;
    MapFrame f = s.frame;
    f.layers.labels = true;
    MapFrameStats stats;
    s.labels_built = render(f, kSettleFrames, MapStyle::day(), &stats, kAuraW, kAuraH);
    s.placed = stats.placed_labels;
    f.layers.buildings = false;
    s.labels_open = render(f, kSettleFrames, MapStyle::day(), nullptr, kAuraW, kAuraH);
    f.layers.labels = false;
    s.plain_open = render(f, 1, MapStyle::day(), nullptr, kAuraW, kAuraH);
    f.layers.roads = f.layers.route = false;
    s.no_roads_open = render(f, 1, MapStyle::day(), nullptr, kAuraW, kAuraH);
    f = s.frame;
    s.plain_built = render(f, 1, MapStyle::day(), nullptr, kAuraW, kAuraH);
    dump(s.labels_built, "aura_scene_labels_built");
    dump(s.labels_open, "aura_scene_labels_open");
    dump(s.plain_built, "aura_scene_plain_built");
    dump(s.plain_open, "aura_scene_plain_open");
    return s;
}

std::vector<LabelPixels> labelPixels(const AuraScene& s) {
    std::vector<LabelPixels> out;
    for (const auto& p : s.placed) {
        if (p.state != labels::LabelState::Visible) continue;
        LabelPixels lp{p, {}, 0};
        const glm::vec2 h = p.box.aabbHalfExtents();
        const int x0 = std::max(0, int(p.box.center.x - h.x)), x1 = std::min(kAuraW - 1, int(p.box.center.x + h.x));
        const int y0 = std::max(0, int(p.box.center.y - h.y)), y1 = std::min(kAuraH - 1, int(p.box.center.y + h.y));
        for (int y = y0; y <= y1; ++y) {
            for (int x = x0; x <= x1; ++x) {
                if (dist(at(s.labels_open, x, y), at(s.plain_open, x, y)) <= 24) continue;  // not text
                lp.text.emplace_back(x, y);
                lp.hidden += dist(at(s.labels_built, x, y), at(s.plain_built, x, y)) <= 4 &&
                             dist(at(s.plain_built, x, y), at(s.plain_open, x, y)) > 4;
            }
        }
        if (!lp.text.empty()) out.push_back(std::move(lp));
    }
    return out;
}

// The label of the scene most hidden by buildings (at least 40 text pixels).
const LabelPixels* mostHidden(const std::vector<LabelPixels>& labels) {
    const LabelPixels* best = nullptr;
    for (const auto& l : labels) {
        if (l.text.size() < 40) continue;
        if (!best || l.hidden * best->text.size() > best->hidden * l.text.size()) best = &l;
    }
    return best;
}

// The snail's view at kAuraMeasure with a building stood in front of its largest label: the drive
// itself has no world-space label behind a building (OcclusionSearch.FindAuraPose finds at most
// 8 % hidden between 600 and 4500 m), so the case is constructed on the real scene.
MapFrame labelBehindBuilding() {
    MapFrame f = frameAt(ViewMode::Snail, kAuraMeasure, 13.0, kAuraW, kAuraH);
    MapFrame probe = f;
    probe.layers.labels = true;
    MapFrameStats stats;
    (void)render(probe, kSettleFrames, MapStyle::day(), &stats, kAuraW, kAuraH);
    const labels::PlacedLabel* largest = nullptr;
    for (const auto& p : stats.placed_labels) {
        if (p.state != labels::LabelState::Visible) continue;
        if (!largest || p.box.half_extents.x > largest->box.half_extents.x) largest = &p;
    }
    EXPECT_NE(largest, nullptr) << "no label at this pose";
    if (!largest) return f;
    const glm::vec2 h = largest->box.aabbHalfExtents();
    EXPECT_TRUE(navmap::test::standBuildingInFront(f, largest->box.center, 2.0f * std::max(h.x, h.y) + 12.0f, kAuraW,
                                                   kAuraH, 60.0));
    return f;
}

TEST(LabelAura, WorldSpaceLabelBehindABuildingBecomesReadable) {
    const AuraScene s = auraScene(labelBehindBuilding());
    dump(s.plain_built, "aura_constructed_plain");
    const auto labels = labelPixels(s);
    const LabelPixels* l = mostHidden(labels);
    ASSERT_NE(l, nullptr) << "no labelled text at this pose";
    const double hidden = double(l->hidden) / double(l->text.size());
    std::printf("label %llu: %zu text pixels, %.0f%% hidden by buildings without the aura\n",
                static_cast<unsigned long long>(l->label.id), l->text.size(), 100.0 * hidden);
    ASSERT_GE(hidden, 0.3) << "the building stood in front of the label hides it";

    MapFrame f = s.frame;
    f.layers.labels = true;
    f.layers.label_aura = true;
    MapFrameStats stats;
    const Image aura = render(f, kSettleFrames, MapStyle::day(), &stats, kAuraW, kAuraH);
    EXPECT_EQ(stats.label_world_weight, 1.0f) << "world-space labels in snail's view";
    // Readable: the text pixels that the building hid differ from the building colour now.
    std::size_t hidden_px = 0, readable = 0;
    for (auto [x, y] : l->text) {
        const bool was_hidden = dist(at(s.labels_built, x, y), at(s.plain_built, x, y)) <= 4 &&
                                dist(at(s.plain_built, x, y), at(s.plain_open, x, y)) > 4;
        if (!was_hidden) continue;
        ++hidden_px;
        readable += dist(at(aura, x, y), at(s.plain_built, x, y)) > 24;
    }
    std::printf("aura: %zu of %zu hidden text pixels readable\n", readable, hidden_px);
    EXPECT_GE(double(readable), 0.8 * double(hidden_px));
    // The referenced road shows around the label: in the enlarged box, road pixels that a building
    // covered without the aura now look like the scene without buildings.
    const glm::vec2 h = l->label.box.aabbHalfExtents() + glm::vec2(MapStyle::day().aura_margin_px);
    const glm::vec2 c = l->label.box.center;
    std::size_t road_shown = 0, road_covered = 0;
    for (int y = std::max(0, int(c.y - h.y)); y <= std::min(kAuraH - 1, int(c.y + h.y)); ++y) {
        for (int x = std::max(0, int(c.x - h.x)); x <= std::min(kAuraW - 1, int(c.x + h.x)); ++x) {
            const bool road = dist(at(s.plain_open, x, y), at(s.no_roads_open, x, y)) > 8;
            const bool covered = dist(at(s.plain_built, x, y), at(s.plain_open, x, y)) > 8;
            if (!road || !covered) continue;
            ++road_covered;
            const bool text = dist(at(s.labels_open, x, y), at(s.plain_open, x, y)) > 24;
            const int before = dist(at(s.plain_built, x, y), at(s.plain_open, x, y));
            road_shown += !text && dist(at(aura, x, y), at(s.plain_open, x, y)) * 2 < before;
        }
    }
    std::printf("aura: %zu of %zu covered road pixels around the label visible\n", road_shown, road_covered);
    EXPECT_GE(road_shown, 10u) << "the referenced road is partly visible around the label";
}

TEST(LabelAura, ChangesOnlyThePixelsWhereABuildingIsSeen) {
    // Bird's-eye over the town: the aura fades the buildings around the labels and leaves the
    // rest of the scene, the roads' outlines and the terrain between the buildings, as it was.
    const AuraScene s = auraScene(frameAt(ViewMode::Bird, kAuraMeasure, 0.0, kAuraW, kAuraH));
    MapFrame f = s.frame;
    f.layers.labels = true;
    f.layers.label_aura = true;
    const Image aura = render(f, kSettleFrames, MapStyle::day(), nullptr, kAuraW, kAuraH);
    dump(aura, "aura_town_bird");
    // Where a building is seen: the frames with and without buildings differ there. Without the
    // screen-space outlines, which lie over buildings beside the roads and are faded with them.
    f = s.frame;
    f.layers.outlines = false;
    const Image built = render(f, 1, MapStyle::day(), nullptr, kAuraW, kAuraH);
    f.layers.buildings = false;
    const Image open = render(f, 1, MapStyle::day(), nullptr, kAuraW, kAuraH);
    std::size_t changed = 0, outside_buildings = 0;
    for (int y = 0; y < kAuraH; ++y) {
        for (int x = 0; x < kAuraW; ++x) {
            if (dist(at(aura, x, y), at(s.labels_built, x, y)) <= 8) continue;
            ++changed;
            outside_buildings += dist(at(built, x, y), at(open, x, y)) <= 4;
        }
    }
    std::printf("aura: %zu pixels changed, %zu of them where no building is seen\n", changed, outside_buildings);
    EXPECT_GT(changed, 500u) << "buildings around the labels fade";
    EXPECT_LE(double(outside_buildings), 0.01 * double(changed));
}

TEST(LabelAura, BuildingsAwayFromLabelsStayOpaque) {
    // Without labels the aura has no region: the frame equals the plain one.
    MapFrame f = frameAt(ViewMode::Bird, kAuraMeasure);
    const Image plain = render(f);
    f.layers.label_aura = true;
    const Image aura = render(f);
    dump(plain, "opaque_plain");
    dump(aura, "opaque_aura");
    std::size_t differ = 0;
    for (int y = 0; y < kH; ++y) {
        for (int x = 0; x < kW; ++x) differ += dist(at(plain, x, y), at(aura, x, y)) > 8;
    }
    EXPECT_EQ(differ, 0u);
}

// Pose search tools (NAVMAP_OCCLUSION_SEARCH=1), for when the data change: for measures along
// the drive, how much of the most hidden world-space label the buildings hide in snail's view.
bool searchRequested() { return std::getenv("NAVMAP_OCCLUSION_SEARCH") != nullptr; }

TEST(OcclusionSearch, FindAuraPose) {
    if (!searchRequested()) GTEST_SKIP() << "pose search tool, not a test: set NAVMAP_OCCLUSION_SEARCH=1 to run it";
    for (double v : {13.0, 0.0}) {
        for (double m = 600.0; m <= 4500.0; m += 150.0) {
            const AuraScene s = auraScene(frameAt(ViewMode::Snail, m, v, kAuraW, kAuraH));
            const auto labels = labelPixels(s);
            const LabelPixels* l = mostHidden(labels);
            if (!l) continue;
            std::printf("measure %.0f speed %.0f: label %llu, %zu text px, %.0f%% hidden\n", m, v,
                        static_cast<unsigned long long>(l->label.id), l->text.size(),
                        100.0 * double(l->hidden) / double(l->text.size()));
            std::fflush(stdout);
        }
    }
}

// Pose search for the glow (by hand): glowing pixels per measure in bird's-eye at standstill.
TEST(OcclusionSearch, FindGlowPose) {
    if (!searchRequested()) GTEST_SKIP() << "pose search tool, not a test: set NAVMAP_OCCLUSION_SEARCH=1 to run it";
    for (double m = 300.0; m <= 4000.0; m += 300.0) {
        for (double v : {0.0, 13.0}) {
            MapFrame f = frameAt(ViewMode::Bird, m, v);
            const Image without = render(f);
            f.layers.glow_roads = true;
            const Image with = render(f);
            std::size_t changed = 0;
            for (int y = 0; y < kH; ++y) {
                for (int x = 0; x < kW; ++x) changed += dist(at(with, x, y), at(without, x, y)) > 0;
            }
            std::printf("measure %.0f speed %.0f: %zu glowing pixels\n", m, v, changed);
        }
    }
}

}  // namespace
