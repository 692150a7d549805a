// SPDX-License-Identifier: Apache-2.0
// Route guidance in rendered frames of the Andorra store: the manoeuvre arrow of a real left turn
// of the drive lies on the outgoing road to the left of the junction, not on the right; a frame
// without the arrow shows none of it; the HUD style shows the guidance overlay's distance text;
// the render cases of the arrow in both views and of the HUD (tests/render/cases/andorra_arrow_*,
// andorra_hud) stand where this drive's left turn is.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "andorra_drive.h"
#include "drive_scene.h"
#include "gl/guidance_overlay_pass.h"
#include "navmap/map/turn_lanes.h"
#include "navmap/render/maneuver_arrow.h"
#include "navmap/render/renderer.h"
#include "render_case.h"
#include "test_paths.h"

namespace {

using namespace navmap::render;
using navmap::test::routeAt;

constexpr int kW = 640, kH = 240;
// The bird's-eye view at the center display's size: at 240 px high an arrow is a few pixels.
constexpr int kBirdW = 1280, kBirdH = 720;
constexpr int kHudW = 800, kHudH = 240;
const glm::vec3 kMagenta{1.0f, 0.0f, 1.0f};  // nowhere else in the map

// NAVMAP_GUIDANCE_DUMP=<dir> writes the images a test looks at.
void dump(const Image& image, const std::string& name) {
    if (const char* dir = std::getenv("NAVMAP_GUIDANCE_DUMP"))
        (void)writePng(std::string(dir) + "/" + name + ".png", image, nullptr);
}

// A left turn of the drive: the first route vertex past 300 m where the direction 25 m before
// and 25 m after differ by 60 to 120 degrees counter-clockwise.
struct Turn {
    double measure = 0.0;
    glm::dvec3 junction{0.0};
    glm::dvec2 in{0.0}, out{0.0};  // unit directions
};
std::optional<Turn> firstLeftTurn(const RouteGeometry& r) {
    for (std::size_t i = 1; i + 1 < r.points.size(); ++i) {
        const double m = r.measure_m[i];
        if (m < 300.0 || m + 30.0 > r.measure_m.back()) continue;
        const glm::dvec2 a(routeAt(r, m - 25.0)), j(r.points[i]), b(routeAt(r, m + 25.0));
        const glm::dvec2 in = glm::normalize(j - a), out = glm::normalize(b - j);
        const double turn = std::atan2(in.x * out.y - in.y * out.x, glm::dot(in, out));
        if (turn > glm::radians(60.0) && turn < glm::radians(120.0)) return Turn{m, r.points[i], in, out};
    }
    return std::nullopt;
}

const Turn& leftTurn() {
    static const std::optional<Turn> kTurn = firstLeftTurn(navmap::test::andorraDrive().drive.geometry);
    if (!kTurn) ADD_FAILURE() << "the Andorra drive has no left turn";
    static const Turn kNone{};
    return kTurn ? *kTurn : kNone;
}

// The car this far before the junction, per view: the junction then lies in the view's middle.
// The bird's-eye view at standstill: its closest zoom.
double leadM(ViewMode mode) { return mode == ViewMode::Bird ? 50.0 : 45.0; }

glm::ivec2 viewSize(ViewMode mode) { return mode == ViewMode::Bird ? glm::ivec2(kBirdW, kBirdH) : glm::ivec2(kW, kH); }

MapFrame turnFrame(ViewMode mode, glm::ivec2 size) {
    return navmap::test::settledAndorraFrame(mode, size.x, size.y, leftTurn().measure - leadM(mode),
                                             mode == ViewMode::Bird ? 0.0 : 8.0);
}
MapFrame turnFrame(ViewMode mode) { return turnFrame(mode, viewSize(mode)); }

ManeuverArrow turnArrow(const MapFrame& f) { return cutManeuverArrow(*f.route, leftTurn().measure, 40.0, 25.0); }

Image render(const MapFrame& frame, const MapStyle& style, int w, int h) {
    RendererOptions o;
    o.width = w;
    o.height = h;
    auto r = Renderer::create(o);
    r->setMapStyle(style);
    r->renderMap(frame);
    return r->readSync();
}

MapStyle magentaArrows() {
    MapStyle s = MapStyle::day();
    s.arrow_fill = kMagenta;
    return s;
}

bool isMagenta(const Image& im, int x, int y) {
    const auto* p = im.pixel(x, y);
    return p[0] >= 235 && p[1] <= 20 && p[2] >= 235;
}
std::size_t magentaIn(const Image& im, glm::ivec2 c, int r) {
    std::size_t n = 0;
    for (int y = std::max(c.y - r, 0); y <= std::min(c.y + r, im.height - 1); ++y)
        for (int x = std::max(c.x - r, 0); x <= std::min(c.x + r, im.width - 1); ++x) n += isMagenta(im, x, y);
    return n;
}
std::size_t magentaPixels(const Image& im) {
    return magentaIn(im, {im.width / 2, im.height / 2}, std::max(im.width, im.height));
}

// Screen pixel (y down) of a store-frame point; none behind the camera.
std::optional<glm::ivec2> project(const MapFrame& f, glm::dvec3 p, glm::ivec2 size) {
    const int w = size.x, h = size.y;
    p.z = navmap::test::andorraDrive().view->terrainHeight(p.x, p.y);
    const glm::mat4 vp = f.camera.projection(double(w) / h) * f.camera.viewRelativeTo(p);
    const glm::vec4 c = vp * glm::vec4(0.0f, 0.0f, 0.0f, 1.0f);
    if (c.w <= 0.0f) return std::nullopt;
    return glm::ivec2(int((c.x / c.w * 0.5f + 0.5f) * float(w)), int((0.5f - c.y / c.w * 0.5f) * float(h)));
}

const char* viewName(ViewMode m) { return m == ViewMode::Bird ? "bird" : "snail"; }

class ArrowView : public ::testing::TestWithParam<ViewMode> {};

// The arrow of the left turn covers the outgoing road left of the junction (its head lies there)
// and nothing at the mirror point on the right of the incoming road.
TEST_P(ArrowView, LeftTurnArrowCoversTheOutgoingRoadOnTheLeftOnly) {
    const Turn& t = leftTurn();
    MapFrame f = turnFrame(GetParam());
    f.layers.buildings = false;  // nothing may hide the junction here
    f.layers.marker = false;
    f.arrows = {turnArrow(f)};
    ASSERT_GE(f.arrows[0].points.size(), 2u);
    const glm::ivec2 size = viewSize(GetParam());
    const Image im = render(f, magentaArrows(), size.x, size.y);
    dump(im, std::string("arrow_left_") + viewName(GetParam()));
    // Into the outgoing road, and its mirror image across the incoming road's line.
    const bool bird = GetParam() == ViewMode::Bird;
    const glm::dvec3 left = routeAt(*f.route, t.measure + (bird ? 15.0 : 12.0));
    const int window = bird ? 2 : 3;
    const glm::dvec2 v = glm::dvec2(left) - glm::dvec2(t.junction);
    const glm::dvec2 mirrored = glm::dvec2(t.junction) + 2.0 * glm::dot(v, t.in) * t.in - v;
    const glm::dvec3 right(mirrored, t.junction.z);
    const auto pl = project(f, left, size), pr = project(f, right, size), pj = project(f, t.junction, size);
    ASSERT_TRUE(pl && pr && pj) << "junction behind the camera";
    EXPECT_LT(pl->x, pr->x) << "the left point is not left of the right one on screen";
    const std::size_t on_left = magentaIn(im, *pl, window), on_right = magentaIn(im, *pr, window);
    EXPECT_GE(on_left, bird ? 12u : 20u) << "arrow missing on the outgoing road at " << pl->x << "," << pl->y;
    EXPECT_EQ(on_right, 0u) << "arrow on the right of the junction at " << pr->x << "," << pr->y;
    EXPECT_GE(magentaIn(im, *pj, window), bird ? 12u : 20u) << "arrow missing at the junction";
}

// Removing the arrow from the frame removes it from the pixels: the next frame of the same
// renderer without it has no arrow colour where it was, and equals a frame never given one.
TEST_P(ArrowView, AFrameWithoutTheArrowShowsNoneOfIt) {
    MapFrame with = turnFrame(GetParam());
    with.layers.buildings = false;
    with.layers.marker = false;
    with.arrows = {turnArrow(with)};
    MapFrame without = with;
    without.arrows.clear();
    const glm::ivec2 size = viewSize(GetParam());
    RendererOptions o;
    o.width = size.x;
    o.height = size.y;
    auto r = Renderer::create(o);
    r->setMapStyle(magentaArrows());
    r->renderMap(with);
    const Image a = r->readSync();
    r->renderMap(without);
    const Image b = r->readSync();
    const Image baseline = render(without, magentaArrows(), size.x, size.y);
    const auto pj = project(with, leftTurn().junction, size);
    ASSERT_TRUE(pj);
    EXPECT_GE(magentaIn(a, *pj, 6), 40u) << "the arrow was not drawn";
    EXPECT_GE(magentaPixels(a), 150u);
    EXPECT_EQ(magentaIn(b, *pj, 6), 0u);
    EXPECT_EQ(magentaPixels(b), 0u);
    EXPECT_EQ(b.rgba, baseline.rgba) << "the frame after the arrow differs from one never given it";
}

// A later manoeuvre's arrow (emphasis below 1) is drawn fainter: its fill lies between the
// route's colour and the arrow's.
TEST_P(ArrowView, LowerEmphasisDrawsFainter) {
    MapFrame f = turnFrame(GetParam());
    f.layers.buildings = false;
    f.arrows = {turnArrow(f)};
    f.arrows[0].emphasis = 0.5f;
    f.layers.marker = false;
    const glm::ivec2 size = viewSize(GetParam());
    const Image im = render(f, magentaArrows(), size.x, size.y);
    const auto pj = project(f, leftTurn().junction, size);
    ASSERT_TRUE(pj);
    EXPECT_EQ(magentaPixels(im), 0u);
    const glm::vec3 half = glm::mix(MapStyle::day().route_color, kMagenta, 0.5f) * 255.0f;
    std::size_t faint = 0;
    for (int y = pj->y - 4; y <= pj->y + 4; ++y) {
        for (int x = pj->x - 4; x <= pj->x + 4; ++x) {
            const auto* p = im.pixel(x, y);
            faint += std::abs(p[0] - half.r) <= 6 && std::abs(p[1] - half.g) <= 6 && std::abs(p[2] - half.b) <= 6;
        }
    }
    EXPECT_GE(faint, 20u);
}

// Labels keep out of the manoeuvre arrows (docs/labels.md "Keep-out"): with labels on, no
// visible label's drawn glyph box (outline and halo included) covers a pixel of the arrow's fill
// as drawn without labels. The arrow is a long one (the 350 m after the turn, past labelled
// streets and POIs beside the route: without the keep-out, 273 of its pixels lie under labels),
// in the center display's bird's-eye view (the snail's view there shows one label, far away).
TEST(ArrowLabels, NoLabelIsDrawnOverTheArrow) {
    const glm::ivec2 size = viewSize(ViewMode::Bird);
    MapFrame f = turnFrame(ViewMode::Bird, size);
    f.arrows = {cutManeuverArrow(*f.route, leftTurn().measure + 350.0, 345.0, 25.0)};
    RendererOptions o;
    o.width = size.x;
    o.height = size.y;
    auto r = Renderer::create(o);
    r->setMapStyle(magentaArrows());
    r->renderMap(f);
    const Image bare = r->readSync();
    ASSERT_GE(magentaPixels(bare), 200u);
    f.layers.labels = true;
    f.frame_dt_s = 1.0 / 30.0;
    for (int i = 0; i < 60; ++i) r->renderMap(f);
    const MapFrameStats stats = r->mapStats();
    dump(r->readSync(), "arrow_labels_bird");
    // Pixel centres inside a convex quad (corners in order, either winding).
    auto inside = [](const labels::ScreenQuad& q, glm::vec2 p) {
        int sign = 0;
        for (std::size_t i = 0; i < 4; ++i) {
            const glm::vec2 a = q[i], b = q[(i + 1) % 4];
            const float c = (b.x - a.x) * (p.y - a.y) - (b.y - a.y) * (p.x - a.x);
            if (c == 0.0f) continue;
            const int s = c > 0.0f ? 1 : -1;
            if (sign != 0 && s != sign) return false;
            sign = s;
        }
        return true;
    };
    std::size_t visible = 0, covered = 0;
    std::string over;
    for (const labels::DrawnLabel& l : stats.drawn_labels) {
        if (l.opacity < 0.5f) continue;
        ++visible;
        std::size_t mine = 0;
        for (const labels::ScreenQuad& q : l.glyph_boxes) {
            glm::vec2 lo(1e9f), hi(-1e9f);
            for (const glm::vec2 c : q) {
                lo = glm::min(lo, c);
                hi = glm::max(hi, c);
            }
            for (int y = std::max(int(lo.y), 0); y <= std::min(int(hi.y), bare.height - 1); ++y)
                for (int x = std::max(int(lo.x), 0); x <= std::min(int(hi.x), bare.width - 1); ++x)
                    mine += isMagenta(bare, x, y) && inside(q, glm::vec2(x + 0.5f, y + 0.5f));
        }
        if (mine > 0) over += " \"" + l.text + "\" (" + std::to_string(mine) + " px)";
        covered += mine;
    }
    EXPECT_GE(visible, 3u);
    EXPECT_EQ(covered, 0u) << "labels drawn over the arrow:" << over;
}

// The render cases hold the turn's measure as a number: they show this turn while the drive finds
// it there (a changed store or route planner fails here, not as a changed image).
TEST_P(ArrowView, TheRenderCasesStandBeforeTheLeftTurn) {
    std::vector<std::string> names = {std::string("andorra_arrow_") + viewName(GetParam())};
    if (GetParam() == ViewMode::Snail) names.emplace_back("andorra_hud");  // the HUD's frame is a snail's view
    for (const std::string& name : names) {
        std::string error;
        const auto c = navmap::test::loadRenderCase(navmap::test::sourceDir() / "tests/render/cases" / name, &error);
        ASSERT_TRUE(c) << error;
        ASSERT_TRUE(c->guidance) << name;
        EXPECT_EQ(c->view, GetParam()) << name;
        EXPECT_EQ(c->guidance->junction_m, leftTurn().measure) << name;
        EXPECT_EQ(c->measure_m, leftTurn().measure - leadM(GetParam())) << name;
        EXPECT_EQ(c->speed_mps, GetParam() == ViewMode::Bird ? 0.0 : 8.0) << name;
    }
}

INSTANTIATE_TEST_SUITE_P(Views, ArrowView, ::testing::Values(ViewMode::Bird, ViewMode::Snail),
                         [](const auto& p) { return std::string(viewName(p.param)); });

// The HUD's frame: its style and layers, the roads at the junction, the arrow and the overlay.
MapFrame hudFrame(const std::string& distance) {
    MapFrame f = turnFrame(ViewMode::Snail, {kHudW, kHudH});
    f.layers = MapLayers::hud();
    f.arrows = {turnArrow(f)};
    f.guidance_roads = junctionRoads(f.tiles, glm::dvec2(leftTurn().junction), 60.0);
    GuidanceOverlay g;
    g.symbol = ManeuverSymbol::TurnLeft;
    g.distance = distance;
    g.street = "Avinguda Carlemany";
    g.remaining_distance = "12.4 km";
    g.remaining_time = "18 min";
    f.guidance = g;
    return f;
}

// The distance text is drawn where the layout puts it: the overlay with "300 m" differs from the
// one without a distance only in the distance text's box, by bright text pixels. Elsewhere a
// channel may move by a level or two: the distance's glyphs take atlas space, the other glyphs
// are packed elsewhere, and the text shader's float filter (shaders/text_sdf.frag) sees their
// texel fractions rounded a little differently.
TEST(HudGuidance, ShowsTheDistanceText) {
    const Image with = render(hudFrame("300 m"), MapStyle::hud(), kHudW, kHudH);
    const Image without = render(hudFrame(""), MapStyle::hud(), kHudW, kHudH);
    dump(with, "hud_300m");
    const navmap::render::gl::GuidanceLayout l = navmap::render::gl::guidanceLayout(kHudW, kHudH);
    const float em = l.distance_px;
    std::size_t inside = 0, outside = 0, bright = 0;
    for (int y = 0; y < kHudH; ++y) {
        for (int x = 0; x < kHudW; ++x) {
            const auto* a = with.pixel(x, y);
            const auto* b = without.pixel(x, y);
            const int step = std::max({std::abs(a[0] - b[0]), std::abs(a[1] - b[1]), std::abs(a[2] - b[2])});
            if (step <= 2) continue;
            const bool in_box = x >= l.distance_at.x - 8 && x <= l.distance_at.x + 4.0f * em &&
                                y >= l.distance_at.y - 1.1f * em && y <= l.distance_at.y + 0.4f * em;
            (in_box ? inside : outside) += 1;
            bright += in_box && a[0] > 230 && a[1] > 230 && a[2] > 230;
        }
    }
    EXPECT_EQ(outside, 0u) << "the distance text changed pixels outside its box";
    EXPECT_GE(bright, 400u) << "too few white text pixels: the distance is not legible";
    EXPECT_GE(inside, bright);
}

// The HUD style: black wherever nothing is drawn (transparent on the combiner), no buildings,
// terrain or map roads (the render case andorra_hud holds the golden of this frame).
TEST(HudGuidance, BlackBackground) {
    const MapFrame f = hudFrame("300 m");
    const Image im = render(f, MapStyle::hud(), kHudW, kHudH);
    dump(im, "hud");
    std::size_t black = 0;
    for (int y = 0; y < kHudH; ++y)
        for (int x = 0; x < kHudW; ++x) {
            const auto* p = im.pixel(x, y);
            black += p[0] == 0 && p[1] == 0 && p[2] == 0;
        }
    EXPECT_GT(black, std::size_t(kHudW * kHudH) * 6 / 10) << "the HUD is not mostly black";
}

// The speed limit sign (MapFrame::speed_limit): a red ring, a white disc and black digits where
// speedLimitSignLayout puts it; nothing of it without a limit.
bool isSignRed(const Image& im, glm::vec2 at) {
    const auto* p = im.pixel(int(at.x), int(at.y));
    return p[0] >= 170 && p[1] <= 60 && p[2] <= 60;
}

struct SignPixels {
    int ring_red = 0, outside_red = 0, disc_white = 0, digits_dark = 0;
};

SignPixels signPixels(const Image& im, const navmap::render::gl::SpeedLimitSignLayout& l) {
    SignPixels n;
    constexpr int kAngles = 48;
    for (int k = 0; k < kAngles; ++k) {
        const float a = 6.2831853f * float(k) / kAngles;
        const glm::vec2 dir(std::cos(a), std::sin(a));
        n.ring_red += isSignRed(im, l.centre + 0.5f * (l.radius + l.inner_radius) * dir);
        n.outside_red += isSignRed(im, l.centre + (l.radius + 4.0f) * dir);
        // Between the digits and the ring (above and below the number): white.
        const auto* w = im.pixel(int(l.centre.x + 0.88f * l.inner_radius * dir.x),
                                 int(l.centre.y + 0.88f * l.inner_radius * dir.y));
        n.disc_white += w[0] >= 235 && w[1] >= 235 && w[2] >= 235;
    }
    const int half = int(0.55f * l.inner_radius);
    for (int y = int(l.centre.y) - half; y <= int(l.centre.y) + half; ++y)
        for (int x = int(l.centre.x) - half; x <= int(l.centre.x) + half; ++x) {
            const auto* p = im.pixel(x, y);
            n.digits_dark += p[0] <= 60 && p[1] <= 60 && p[2] <= 60;
        }
    return n;
}

TEST(SpeedLimitSign, HudPanelShowsTheLimitAsARedRingWithBlackDigits) {
    MapFrame f = hudFrame("300 m");
    f.speed_limit = SpeedLimitSign{50, SignCorner::TopRight};
    const Image with = render(f, MapStyle::hud(), kHudW, kHudH);
    f.speed_limit.reset();
    const Image without = render(f, MapStyle::hud(), kHudW, kHudH);
    dump(with, "hud_speed_limit");
    const auto l = navmap::render::gl::speedLimitSignLayout(kHudW, kHudH, SignCorner::TopRight, 2);
    EXPECT_GT(l.centre.x, 0.8f * kHudW) << "top right";
    EXPECT_LT(l.centre.y, 0.4f * kHudH);
    const SignPixels s = signPixels(with, l);
    EXPECT_EQ(s.ring_red, 48) << "the ring is red all round";
    EXPECT_EQ(s.outside_red, 0) << "nothing red outside the ring";
    EXPECT_GE(s.disc_white, 40) << "a white disc inside the ring";
    EXPECT_GE(s.digits_dark, 80) << "black digits in the middle";
    const SignPixels none = signPixels(without, l);
    EXPECT_EQ(none.ring_red, 0) << "no sign without a limit";
    EXPECT_EQ(none.disc_white, 0);
    // The sign changes nothing outside its square.
    std::size_t outside = 0;
    for (int y = 0; y < kHudH; ++y)
        for (int x = 0; x < kHudW; ++x) {
            if (std::abs(x - l.centre.x) <= l.radius + 2 && std::abs(y - l.centre.y) <= l.radius + 2) continue;
            const auto* a = with.pixel(x, y);
            const auto* b = without.pixel(x, y);
            outside += a[0] != b[0] || a[1] != b[1] || a[2] != b[2];
        }
    EXPECT_EQ(outside, 0u);
}

TEST(SpeedLimitSign, UnknownLimitDrawsNoSign) {
    MapFrame f = hudFrame("300 m");
    const Image without = render(f, MapStyle::hud(), kHudW, kHudH);
    f.speed_limit = SpeedLimitSign{0, SignCorner::TopRight};  // unknown: what the daemon never sends
    const Image unknown = render(f, MapStyle::hud(), kHudW, kHudH);
    EXPECT_EQ(unknown.rgba, without.rgba);
    const auto l = navmap::render::gl::speedLimitSignLayout(kHudW, kHudH, SignCorner::TopRight, 2);
    EXPECT_EQ(signPixels(unknown, l).ring_red, 0);
}

TEST(SpeedLimitSign, ClusterCornerShowsThreeDigits) {
    MapFrame f = turnFrame(ViewMode::Snail);
    f.speed_limit = SpeedLimitSign{110, SignCorner::TopLeft};
    const Image with = render(f, MapStyle::day(), kW, kH);
    f.speed_limit.reset();
    const Image without = render(f, MapStyle::day(), kW, kH);
    dump(with, "cluster_speed_limit");
    const auto l = navmap::render::gl::speedLimitSignLayout(kW, kH, SignCorner::TopLeft, 3);
    EXPECT_LT(l.centre.x, 0.2f * kW);
    EXPECT_LT(l.centre.y, 0.4f * kH);
    const SignPixels s = signPixels(with, l);
    EXPECT_EQ(s.ring_red, 48);
    EXPECT_GE(s.disc_white, 40);
    EXPECT_GE(s.digits_dark, 40);
    EXPECT_EQ(signPixels(without, l).ring_red, 0) << "the map itself has no red there";
}

// Labels keep out of the sign's corner: in the center display's bird's-eye view with labels, the
// corner where labels lie most without the sign has none of their glyphs under the sign with it.
TEST(SpeedLimitSign, NoLabelIsDrawnUnderTheSign) {
    const glm::ivec2 size = viewSize(ViewMode::Bird);
    RendererOptions o;
    o.width = size.x;
    o.height = size.y;
    auto drawnLabels = [&](const std::optional<SpeedLimitSign>& sign) {
        MapFrame f = turnFrame(ViewMode::Bird, size);
        f.layers.labels = true;
        f.frame_dt_s = 1.0 / 30.0;
        f.speed_limit = sign;
        auto r = Renderer::create(o);
        for (int i = 0; i < 60; ++i) r->renderMap(f);
        return r->mapStats().drawn_labels;
    };
    auto glyphsUnder = [&](const std::vector<labels::DrawnLabel>& drawn, SignCorner corner) {
        const auto l = navmap::render::gl::speedLimitSignLayout(size.x, size.y, corner, 2);
        std::size_t n = 0;
        for (const labels::DrawnLabel& label : drawn) {
            if (label.opacity < 0.5f) continue;
            for (const labels::ScreenQuad& q : label.glyph_boxes) {
                glm::vec2 lo(1e9f), hi(-1e9f);
                for (const glm::vec2 c : q) {
                    lo = glm::min(lo, c);
                    hi = glm::max(hi, c);
                }
                n += hi.x > l.centre.x - l.radius && lo.x < l.centre.x + l.radius && hi.y > l.centre.y - l.radius &&
                     lo.y < l.centre.y + l.radius;
            }
        }
        return n;
    };
    const auto without = drawnLabels(std::nullopt);
    SignCorner busiest = SignCorner::TopLeft;
    std::size_t most = 0;
    for (const SignCorner c :
         {SignCorner::TopLeft, SignCorner::TopRight, SignCorner::BottomLeft, SignCorner::BottomRight}) {
        if (const std::size_t n = glyphsUnder(without, c); n > most) {
            most = n;
            busiest = c;
        }
    }
    ASSERT_GT(most, 0u) << "no corner has labels: the test shows nothing";
    EXPECT_EQ(glyphsUnder(drawnLabels(SpeedLimitSign{50, busiest}), busiest), 0u)
        << most << " glyphs lie there without the sign (corner " << int(busiest) << ")";
}

// The lane row (GuidanceOverlay::lanes in the HUD's panel, MapFrame::lanes on its own in the
// cluster): each lane's box in the bright colour where the route takes it, dark where not; its
// arrows in the symbol's colour or dimmed; nothing of it without lanes.
namespace lanes_test {

namespace la = navmap::map::lane_arrow;
using navmap::render::gl::LaneRowLayout;

bool near(const std::uint8_t* p, glm::ivec3 c, int tolerance = 6) {
    return std::abs(p[0] - c.r) <= tolerance && std::abs(p[1] - c.g) <= tolerance && std::abs(p[2] - c.b) <= tolerance;
}
const glm::ivec3 kBoxOn{56, 107, 191}, kBoxOff{41, 43, 51};  // guidance_overlay_pass.cpp's box colours

struct LaneBox {
    glm::vec2 lo{0.0f}, hi{0.0f};
};
LaneBox box(const LaneRowLayout& l, int i) {
    const glm::vec2 lo = l.origin + glm::vec2(float(i) * (l.box.x + l.gap), 0.0f);
    return {lo, lo + l.box};
}

struct BoxPixels {
    bool fill_on = false, fill_off = false;  // the box's corner
    int bright = 0, dim = 0;                 // arrow pixels in the symbol's colours
};
BoxPixels boxPixels(const Image& im, const LaneBox& b, const MapStyle& style) {
    BoxPixels n;
    const auto* corner = im.pixel(int(b.lo.x) + 2, int(b.lo.y) + 2);
    n.fill_on = near(corner, kBoxOn);
    n.fill_off = near(corner, kBoxOff);
    const glm::ivec3 bright(glm::round(style.guidance_symbol * 255.0f));
    const glm::ivec3 dim(glm::round(style.guidance_symbol_dim * 255.0f));
    for (int y = int(b.lo.y) + 1; y < int(b.hi.y) - 1; ++y)
        for (int x = int(b.lo.x) + 1; x < int(b.hi.x) - 1; ++x) {
            n.bright += near(im.pixel(x, y), bright, 10);
            n.dim += near(im.pixel(x, y), dim, 10);
        }
    return n;
}

// Pixels that differ between two images outside the box lo..hi (grown by `grow`).
std::size_t changedOutside(const Image& a, const Image& b, glm::vec2 lo, glm::vec2 hi, float grow = 2.0f) {
    std::size_t n = 0;
    for (int y = 0; y < a.height; ++y)
        for (int x = 0; x < a.width; ++x) {
            if (x >= lo.x - grow && x <= hi.x + grow && y >= lo.y - grow && y <= hi.y + grow) continue;
            const auto* p = a.pixel(x, y);
            const auto* q = b.pixel(x, y);
            n += p[0] != q[0] || p[1] != q[1] || p[2] != q[2];
        }
    return n;
}

TEST(LaneGuidanceRender, HudPanelShowsTheLanesToTakeBright) {
    MapFrame f = hudFrame("300 m");
    f.guidance->lanes = LaneRow{{la::kLeft, la::kThrough, la::kThrough | la::kRight}, 0b001};
    const Image with = render(f, MapStyle::hud(), kHudW, kHudH);
    f.guidance->lanes.reset();
    const Image without = render(f, MapStyle::hud(), kHudW, kHudH);
    dump(with, "hud_lanes");
    const LaneRowLayout l = navmap::render::gl::laneRowInPanel(navmap::render::gl::guidanceLayout(kHudW, kHudH));
    const MapStyle style = MapStyle::hud();
    const BoxPixels left = boxPixels(with, box(l, 0), style);
    EXPECT_TRUE(left.fill_on) << "the left-turn lane is the one to take";
    EXPECT_GE(left.bright, 20) << "its arrow in the symbol's colour";
    EXPECT_EQ(left.dim, 0);
    for (const int i : {1, 2}) {
        const BoxPixels other = boxPixels(with, box(l, i), style);
        EXPECT_TRUE(other.fill_off) << "lane " << i << " is dark";
        EXPECT_EQ(other.bright, 0) << "lane " << i;
        EXPECT_GE(other.dim, 20) << "lane " << i << "'s arrows dimmed";
    }
    // Lane 2 has two arrows (through and right): more of it than of lane 1.
    EXPECT_GT(boxPixels(with, box(l, 2), style).dim, boxPixels(with, box(l, 1), style).dim);
    for (int i = 0; i < 3; ++i) {
        const BoxPixels none = boxPixels(without, box(l, i), style);
        EXPECT_FALSE(none.fill_on || none.fill_off) << "no box " << i << " without lanes";
    }
    // The row is all that changes: the street and distance keep the panel as wide as it was.
    EXPECT_EQ(changedOutside(with, without, box(l, 0).lo, box(l, 2).hi), 0u);
}

TEST(LaneGuidanceRender, NoLanesDrawNothing) {
    MapFrame f = hudFrame("300 m");
    const Image without = render(f, MapStyle::hud(), kHudW, kHudH);
    f.guidance->lanes = LaneRow{};  // known to have no lanes: what the daemon never sends
    EXPECT_EQ(render(f, MapStyle::hud(), kHudW, kHudH).rgba, without.rgba);
    MapFrame c = turnFrame(ViewMode::Snail);
    const Image cluster = render(c, MapStyle::day(), kW, kH);
    c.lanes = LaneRow{};
    EXPECT_EQ(render(c, MapStyle::day(), kW, kH).rgba, cluster.rgba);
}

TEST(LaneGuidanceRender, ClusterRowAtTheTopCentre) {
    MapFrame f = turnFrame(ViewMode::Snail);
    // The CG-2's climbing lane ending (Andorra, way 456350884): go on in the first lane.
    f.lanes = LaneRow{{0, la::kMergeToRight}, 0b01};
    const Image with = render(f, MapStyle::day(), kW, kH);
    f.lanes.reset();
    const Image without = render(f, MapStyle::day(), kW, kH);
    dump(with, "cluster_lanes");
    const LaneRowLayout l = navmap::render::gl::laneRowAtTop(kW, kH, 2);
    EXPECT_NEAR(0.5f * (box(l, 0).lo.x + box(l, 1).hi.x), 0.5f * kW, 1.0f) << "centred";
    EXPECT_LT(box(l, 0).hi.y, 0.4f * kH) << "at the top";
    const MapStyle style = MapStyle::day();
    const BoxPixels on = boxPixels(with, box(l, 0), style);
    EXPECT_TRUE(on.fill_on);
    EXPECT_EQ(on.bright, 0) << "an unmarked lane has no arrow";
    const BoxPixels merging = boxPixels(with, box(l, 1), style);
    EXPECT_TRUE(merging.fill_off);
    EXPECT_GE(merging.dim, 20) << "the merge arrow, dimmed";
    EXPECT_FALSE(boxPixels(without, box(l, 0), style).fill_on) << "the map has no box colour there";
    const auto [lo, hi] = navmap::render::gl::laneRowPanel(l, 2);
    EXPECT_EQ(changedOutside(with, without, lo, hi), 0u);
}

// Labels keep out of the cluster's lane row: at the first place along the drive where labels lie
// at the top centre without the row, none of their glyphs is under it with the row.
TEST(LaneGuidanceRender, NoLabelIsDrawnUnderTheLaneRow) {
    const glm::ivec2 size = viewSize(ViewMode::Bird);
    RendererOptions o;
    o.width = size.x;
    o.height = size.y;
    const LaneRow row{std::vector<std::uint16_t>(8, la::kThrough), 0b00011000};
    const LaneRowLayout l = navmap::render::gl::laneRowAtTop(size.x, size.y, row.lanes.size());
    const auto [lo, hi] = navmap::render::gl::laneRowPanel(l, row.lanes.size());
    auto glyphsUnder = [&](double measure, const std::optional<LaneRow>& lanes) {
        MapFrame f = navmap::test::settledAndorraFrame(ViewMode::Bird, size.x, size.y, measure, 0.0);
        f.layers.labels = true;
        f.frame_dt_s = 1.0 / 30.0;
        f.lanes = lanes;
        auto r = Renderer::create(o);
        for (int i = 0; i < 60; ++i) r->renderMap(f);
        std::size_t n = 0;
        for (const labels::DrawnLabel& label : r->mapStats().drawn_labels) {
            if (label.opacity < 0.5f) continue;
            for (const labels::ScreenQuad& q : label.glyph_boxes) {
                glm::vec2 qlo(1e9f), qhi(-1e9f);
                for (const glm::vec2 c : q) {
                    qlo = glm::min(qlo, c);
                    qhi = glm::max(qhi, c);
                }
                n += qhi.x > lo.x && qlo.x < hi.x && qhi.y > lo.y && qlo.y < hi.y;
            }
        }
        return n;
    };
    for (double measure = 300.0; measure < 6000.0; measure += 700.0) {
        const std::size_t without = glyphsUnder(measure, std::nullopt);
        if (without == 0) continue;
        EXPECT_EQ(glyphsUnder(measure, row), 0u) << without << " glyphs lie there without the row, at " << measure;
        return;
    }
    FAIL() << "no place of the drive has labels at the top centre: the test shows nothing";
}

}  // namespace lanes_test

}  // namespace
