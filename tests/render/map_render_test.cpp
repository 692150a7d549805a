// SPDX-License-Identifier: Apache-2.0
// Pixel assertions on map frames that do not depend on goldens: rounded caps, crack-free
// joints, casing colours, roads on top of the terrain they lie on (issue: map rendering).
// Synthetic tiles with known geometry; Mesa llvmpipe through EGL.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <memory>
#include <vector>

#include <glm/gtc/matrix_transform.hpp>

#include "navmap/render/renderer.h"
#include "navmap/render/road_style.h"
#include "synthetic_tile.h"
#include "tile_mesh.h"

namespace {

using namespace navmap::render;
namespace map = navmap::map;

constexpr int kW = 640, kH = 480;

using navmap::test::makeTile;
using navmap::test::road;

struct Scene {
    std::unique_ptr<Renderer> renderer;
    Camera camera;
    glm::dvec3 origin;
    Image image;

    glm::vec2 project(glm::dvec3 local) const {
        const glm::mat4 vp = camera.projection(double(kW) / kH) * camera.viewRelativeTo(origin);
        const glm::vec4 c = vp * glm::vec4(glm::vec3(local), 1.0f);
        return {(c.x / c.w * 0.5f + 0.5f) * kW, (1.0f - (c.y / c.w * 0.5f + 0.5f)) * kH};
    }
    glm::ivec3 at(glm::dvec3 local) const {
        const glm::vec2 p = project(local);
        const auto* px = image.pixel(static_cast<int>(p.x), static_cast<int>(p.y));
        return {px[0], px[1], px[2]};
    }
};

glm::ivec3 to8(glm::vec3 c) { return glm::ivec3(glm::round(c * 255.0f)); }

bool near(glm::ivec3 a, glm::ivec3 b, int tol = 6) {
    return std::abs(a.x - b.x) <= tol && std::abs(a.y - b.y) <= tol && std::abs(a.z - b.z) <= tol;
}

// Renders one frame of `tile` with a camera given relative to the tile origin; `extra` may add a
// route or marker to the frame.
Scene renderWith(const std::shared_ptr<map::Tile>& tile, const MapStyle& style, glm::dvec3 eye, glm::dvec3 target,
                 glm::dvec3 up, const MapLayers& layers = {},
                 const std::function<void(MapFrame&, const glm::dvec3& origin)>& extra = {}) {
    Scene s;
    RendererOptions o;
    o.width = kW;
    o.height = kH;
    s.renderer = Renderer::create(o);
    s.renderer->setMapStyle(style);
    s.origin = glm::dvec3(tile->origin_x, tile->origin_y, 0.0);
    s.camera.eye = s.origin + eye;
    s.camera.target = s.origin + target;
    s.camera.up = up;
    s.camera.near_m = 10.0;
    s.camera.far_m = 5000.0;
    MapFrame frame;
    frame.camera = s.camera;
    frame.tiles = {tile};
    frame.layers = layers;
    if (extra) extra(frame, s.origin);
    s.renderer->renderMap(frame);
    s.image = s.renderer->readSync();
    return s;
}

// Looks straight down from `height_m` above the tile centre.
Scene render(const std::shared_ptr<map::Tile>& tile, double height_m, MapStyle style, MapLayers layers = {}) {
    return renderWith(tile, style, {500.0, 500.0, 500.0 + height_m}, {500.0, 500.0, 0.0}, {0.0, 1.0, 0.0}, layers);
}

MapStyle wideRoads() {
    MapStyle style = MapStyle::day();
    for (auto& c : style.roads.classes) c.width_m = 40.0f;
    style.roads.classes[0].casing_m = 8.0f;
    style.roads.scale_threshold_m = 1e6f;  // no width scaling in these close-ups
    return style;
}

TEST(MapRender, DeadEndCapIsRound) {
    auto tile = makeTile([](float, float) { return 500.0f; });
    tile->roads.push_back(road(map::RoadClass::Residential, {{380, 500}, {500, 500}}));
    MapLayers no_outline;
    no_outline.outlines = false;
    const Scene s = render(tile, 300.0, wideRoads(), no_outline);
    const glm::ivec3 fill = to8(wideRoads().roads.classes[static_cast<int>(map::RoadClass::Residential)].fill);
    const double r = 20.0;  // cap radius = width / 2
    // On the arc (inside by a margin): covered.
    for (double a = -80.0; a <= 80.0; a += 20.0) {
        const double rad = glm::radians(a);
        const glm::dvec3 p{500.0 + 0.85 * r * std::cos(rad), 500.0 + 0.85 * r * std::sin(rad), 500.0};
        EXPECT_TRUE(near(s.at(p), fill)) << "arc point at " << a << " deg not covered";
    }
    // The corners of the bounding quad (end + r along, +-r across), pulled in slightly: terrain.
    for (double sy : {-1.0, 1.0}) {
        const glm::dvec3 corner{500.0 + 0.9 * r, 500.0 + sy * 0.9 * r, 500.0};
        EXPECT_FALSE(near(s.at(corner), fill, 30)) << "quad corner covered: the cap is not round";
    }
    // Beyond the cap tip: terrain; just before it: road.
    EXPECT_TRUE(near(s.at({500.0 + 0.9 * r, 500.0, 500.0}), fill));
    EXPECT_FALSE(near(s.at({500.0 + 1.2 * r, 500.0, 500.0}), fill, 30));
}

TEST(MapRender, NoCrackWhereSegmentsMeetAtAnAngle) {
    // Turns at (500, 500) from shallow to sharp: the joined pieces reach beyond the joint only as
    // far as the bend needs (RoadInstance::cap_reach), sin(turn / 2) half widths.
    for (double degrees : {20.0, 45.0, 70.0, 120.0}) {
        auto tile = makeTile([](float, float) { return 500.0f; });
        const double turn = glm::radians(degrees);
        const map::LocalPoint end{static_cast<float>(500.0 + 120.0 * std::cos(turn)),
                                  static_cast<float>(500.0 + 120.0 * std::sin(turn))};
        tile->roads.push_back(road(map::RoadClass::Residential, {{380, 500}, {500, 500}, end}));
        MapLayers no_outline;
        no_outline.outlines = false;
        const Scene s = render(tile, 300.0, wideRoads(), no_outline);
        const glm::ivec3 fill = to8(wideRoads().roads.classes[static_cast<int>(map::RoadClass::Residential)].fill);
        // On the outer side of the joint, along the bisector, inside the road width: a plain quad
        // extrusion leaves a wedge here; the caps fill it.
        const double bisector = (glm::radians(180.0) + turn) / 2.0 + glm::radians(180.0);  // outer side
        for (double f : {0.3, 0.6, 0.85}) {
            const glm::dvec3 p{500.0 + f * 20.0 * std::cos(bisector), 500.0 + f * 20.0 * std::sin(bisector), 500.0};
            EXPECT_TRUE(near(s.at(p), fill))
                << degrees << " deg: crack at the joint, " << f << " of the half width out";
        }
    }
}

// The joined pieces' quads reach beyond a joint only as far as the bend needs; on flat ground at
// one width the road covers what it covers with both whole caps on every quad.
TEST(MapRender, JointsTrimmedToTheBendCoverWhatWholeCapsCover) {
    auto tile = makeTile([](float, float) { return 500.0f; });
    std::vector<map::LocalPoint> wave, zigzag;
    for (int i = 0; i <= 60; ++i) {
        const float x = 220.0f + 10.0f * static_cast<float>(i);
        wave.push_back({x, 560.0f + 70.0f * std::sin(x / 45.0f)});
        zigzag.push_back({x, 380.0f + ((i % 2) ? 25.0f : -25.0f) + 15.0f * std::sin(x / 30.0f)});
    }
    tile->roads.push_back(road(map::RoadClass::Residential, wave));
    tile->roads.push_back(road(map::RoadClass::Primary, zigzag));
    MapStyle style = wideRoads();
    for (auto& c : style.roads.classes) c.width_m = 14.0f;
    style.roads.classes[2].casing_m = 3.0f;
    MapLayers trimmed, whole;
    whole.trim_joint_caps = false;
    const Scene a = render(tile, 700.0, style, trimmed);
    const Scene b = render(tile, 700.0, style, whole);
    const glm::ivec3 fill = to8(style.roads.classes[static_cast<int>(map::RoadClass::Residential)].fill);
    std::size_t differ = 0, road_pixels = 0;
    for (int y = 0; y < kH; ++y) {
        for (int x = 0; x < kW; ++x) {
            const auto* pa = a.image.pixel(x, y);
            const auto* pb = b.image.pixel(x, y);
            differ += pa[0] != pb[0] || pa[1] != pb[1] || pa[2] != pb[2];
            road_pixels += near({pb[0], pb[1], pb[2]}, fill);
        }
    }
    // Pixels whose centre lies on the rim of a round join may flip: the trimmed quads interpolate
    // the cap coordinates from other corners.
    std::printf("[ measure  ] %zu road pixels, %zu pixels differ\n", road_pixels, differ);
    EXPECT_GT(road_pixels, 5000u);
    EXPECT_LE(differ, road_pixels / 2000);
}

// Far roads seen at a grazing angle are foreshortened across to a fraction of a pixel; without
// the least on-screen width (RoadStyle::min_width_px) they break up into dashes. On flat ground,
// and on ground rising away from the camera as a valley side does in the snail's view, where the
// road slanting up the slope crosses the eye's height and is seen edge-on there.
class GrazingRoads : public ::testing::TestWithParam<float> {};

TEST_P(GrazingRoads, FarRoadStaysUnbroken) {
    const float rise = GetParam();  // metres up per metre towards +y
    // 1.1 to 1.5 km ahead of a camera 20 m above the ground, 600 m before the tile, with ground
    // beyond: 6 m of road are 0.04 to 0.07 px high on screen (flat). One road across the view, one
    // slanting away, so that the centre line passes every offset from the pixel centres.
    const std::vector<std::pair<glm::dvec2, glm::dvec2>> roads{{{100, 500}, {900, 500}}, {{100, 350}, {900, 850}}};
    MapStyle style = MapStyle::day();
    style.roads.classes[static_cast<int>(map::RoadClass::Residential)].width_m = 6.0f;
    style.roads.scale_threshold_m = 1e6f;  // only the least width, no distance scaling
    MapLayers no_outline;
    no_outline.outlines = false;
    const glm::ivec3 fill = to8(style.roads.classes[static_cast<int>(map::RoadClass::Residential)].fill);
    // The columns between the road's projected ends (a margin in) with a fill pixel within 3 rows
    // of its projected centre line (straight: the ground is a plane), and the most fill pixels in
    // one such column.
    struct Coverage {
        int columns = 0, covered = 0, thickest = 0;
    };
    auto coverage = [&](const Scene& s, glm::dvec2 a, glm::dvec2 b) {
        Coverage c;
        const glm::vec2 pa = s.project({a, 500.0 + rise * a.y}), pb = s.project({b, 500.0 + rise * b.y});
        for (int x = static_cast<int>(std::min(pa.x, pb.x)) + 4; x < static_cast<int>(std::max(pa.x, pb.x)) - 4; ++x) {
            const float y = pa.y + (pb.y - pa.y) * ((static_cast<float>(x) + 0.5f - pa.x) / (pb.x - pa.x));
            int n = 0;
            for (int row = static_cast<int>(y) - 3; row <= static_cast<int>(y) + 3; ++row) {
                const auto* px = s.image.pixel(x, row);
                n += near({px[0], px[1], px[2]}, fill, 12);
            }
            ++c.columns;
            c.covered += n > 0;
            c.thickest = std::max(c.thickest, n);
        }
        return c;
    };
    for (const auto& [a, b] : roads) {
        auto tile = makeTile([rise](float, float y) { return 500.0f + rise * y; });
        tile->roads.push_back(road(map::RoadClass::Residential, {{static_cast<float>(a.x), static_cast<float>(a.y)},
                                                                 {static_cast<float>(b.x), static_cast<float>(b.y)}}));
        auto scene = [&](float min_width_px) {
            MapStyle st = style;
            st.roads.min_width_px = min_width_px;
            return renderWith(tile, st, {500.0, -600.0, 520.0}, {500.0, 1000.0, 490.0}, {0.0, 0.0, 1.0}, no_outline);
        };
        const Scene widened = scene(style.roads.min_width_px), plain = scene(0.0f);
        const Coverage w = coverage(widened, a, b), p = coverage(plain, a, b);
        std::printf(
            "[ measure  ] rise %g, road (%g, %g)-(%g, %g): %d columns, %d covered at the least width "
            "(at most %d px thick), %d without\n",
            rise, a.x, a.y, b.x, b.y, w.columns, w.covered, w.thickest, p.covered);
        EXPECT_GT(w.columns, 100);
        EXPECT_EQ(w.covered, w.columns) << "the far road breaks up on screen";
        EXPECT_LE(w.thickest, 2) << "widened beyond the least width";
        EXPECT_LT(p.covered, w.columns / 2) << "the scene does not foreshorten the road below a pixel";
        if (::testing::Test::HasFailure()) (void)writePng("map_render_grazing.png", widened.image, nullptr);
    }
}

INSTANTIATE_TEST_SUITE_P(MapRender, GrazingRoads, ::testing::Values(0.0f, 0.04f));

// seed 7.3: a class left out of distant views fades out by narrowing, its drawn width the
// fraction selectionFade() gives of its true one, until nothing is left; with the selection
// off it is drawn whole. Straight down from 300 m on a path made 8 m wide (about 15 px), with
// the class's threshold moved through the fade band instead of the camera.
TEST(MapRender, SelectedClassNarrowsToNothingBelowItsThreshold) {
    auto tile = makeTile([](float, float) { return 500.0f; });
    tile->roads.push_back(road(map::RoadClass::Path, {{470, 500}, {530, 500}}));
    constexpr auto kPath = static_cast<std::size_t>(map::RoadClass::Path);
    MapStyle style = wideRoads();
    style.roads.classes[kPath].width_m = 8.0f;
    const glm::ivec3 fill = to8(style.roads.classes[kPath].fill);
    const float focal_px = 0.5f * kH / static_cast<float>(std::tan(glm::radians(Camera{}.fov_y_deg) / 2.0));
    const float distance = 300.0f, true_px = 8.0f * focal_px / distance;
    // Fill pixels down the column through the road's middle.
    auto drawn_px = [&](float select_px, bool selection) {
        MapStyle st = style;
        st.roads.classes[kPath].select_px = select_px;
        MapLayers layers;
        layers.outlines = false;
        layers.road_selection = selection;
        const Scene sc = render(tile, distance, st, layers);
        const glm::vec2 mid = sc.project({500.0, 500.0, 500.0});
        int n = 0;
        for (int y = 0; y < kH; ++y) {
            const auto* px = sc.image.pixel(static_cast<int>(mid.x), y);
            n += near({px[0], px[1], px[2]}, fill);
        }
        return n;
    };
    for (const float select_px : {5.0f, 11.0f, 13.0f, 14.5f, 16.0f}) {
        const float expected = true_px * selectionFade(8.0f, select_px, focal_px).at(distance);
        const int n = drawn_px(select_px, true);
        std::printf("[ measure  ] threshold %.1f px, true width %.2f px: %d px drawn, %.2f expected\n", select_px,
                    true_px, n, expected);
        EXPECT_NEAR(n, expected, 1.5) << "threshold " << select_px;
        EXPECT_NEAR(drawn_px(select_px, false), true_px, 1.5) << "selection off, threshold " << select_px;
    }
    EXPECT_EQ(drawn_px(16.0f, true), 0) << "left out below its threshold";
}

TEST(MapRender, MotorwayHasItsClassColourWithCasingAtTheEdge) {
    auto tile = makeTile([](float, float) { return 500.0f; });
    tile->roads.push_back(road(map::RoadClass::Motorway, {{300, 500}, {700, 500}}));
    tile->roads.push_back(road(map::RoadClass::Residential, {{500, 300}, {500, 480}}));
    const MapStyle style = wideRoads();
    const Scene s = render(tile, 300.0, style);
    const auto& mw = style.roads.classes[0];
    EXPECT_TRUE(near(s.at({560.0, 500.0, 500.0}), to8(mw.fill))) << "motorway centre";
    // Casing band: between the fill edge (20 m) and fill + casing (28 m) from the axis.
    EXPECT_TRUE(near(s.at({560.0, 524.0, 500.0}), to8(mw.casing))) << "casing above";
    EXPECT_TRUE(near(s.at({560.0, 476.0, 500.0}), to8(mw.casing))) << "casing below";
    // Junction: the residential road ends under the motorway; the motorway is drawn over it
    // (least important first, seed 3.6.3).
    EXPECT_TRUE(near(s.at({500.0, 492.0, 500.0}), to8(mw.fill))) << "junction must show the motorway";
    // Dark outline just outside the casing (seed 3.6.3 outlines).
    // Dark outline just outside the casing (seed 3.6.3, 3x3 max filter: about one pixel).
    const glm::ivec3 terrain = s.at({560.0, 560.0, 500.0});
    int darkest = 3 * 255;
    for (double y = 528.0; y <= 529.5; y += 0.1) {
        const glm::ivec3 c = s.at({560.0, y, 500.0});
        darkest = std::min(darkest, c.x + c.y + c.z);
    }
    EXPECT_LT(darkest, terrain.x + terrain.y + terrain.z - 60) << "no outline next to the road";
    if (::testing::Test::HasFailure()) (void)writePng("map_render_motorway.png", s.image, nullptr);
}

TEST(MapRender, DrapedRoadsAreNeverHiddenByTheirTerrain) {
    // Rolling hills (60 m amplitude, ~150 m wavelength) under a road that crosses them.
    auto hills = [](float x, float y) { return 500.0f + 60.0f * std::sin(x / 48.0f) * std::cos(y / 61.0f); };
    auto tile = makeTile(hills, 65);
    tile->roads.push_back(road(map::RoadClass::Primary, {{100, 450}, {900, 560}}));
    MapStyle style = MapStyle::day();
    style.roads.classes[2].width_m = 14.0f;
    style.roads.classes[2].casing_m = 0.0f;
    // Oblique view from the south at ~45 degrees.
    const Scene s = renderWith(tile, style, {500.0, -150.0, 1250.0}, {500.0, 500.0, 500.0}, {0.0, 0.0, 1.0});
    const glm::ivec3 fill = to8(style.roads.classes[2].fill);
    const TileMesh mesh = buildTileMesh(*tile);
    const HeightGrid grid = mesh.grid();
    int samples = 0, visible = 0;
    for (double t = 0.05; t <= 0.95; t += 0.01) {
        const double x = 100.0 + 800.0 * t, y = 450.0 + 110.0 * t;
        const glm::dvec3 p{x, y, grid.heightAt(x, y)};
        ++samples;
        if (near(s.at(p), fill, 20)) ++visible;
    }
    EXPECT_EQ(visible, samples) << "road centreline pixels hidden by the terrain they lie on";
}

TEST(MapRender, NightPaletteIsDarkerThanDay) {
    auto tile = makeTile([](float x, float y) { return 500.0f + 0.1f * x + 0.05f * y; });
    tile->roads.push_back(road(map::RoadClass::Primary, {{300, 500}, {700, 500}}));
    const Scene day = render(tile, 300.0, MapStyle::day());
    const Scene night = render(tile, 300.0, MapStyle::night());
    auto luminance = [](const Image& im) {
        double sum = 0;
        for (std::size_t i = 0; i < im.rgba.size(); i += 4) sum += im.rgba[i] + im.rgba[i + 1] + im.rgba[i + 2];
        return sum / (im.rgba.size() / 4);
    };
    EXPECT_LT(luminance(night.image), 0.6 * luminance(day.image));
    // Roads stay brighter than the terrain at night.
    const glm::ivec3 r = night.at({500.0, 500.0, 500.0}), t = night.at({500.0, 600.0, 500.0});
    EXPECT_GT(r.x + r.y + r.z, t.x + t.y + t.z + 60);
}

TEST(MapRender, TileWithoutElevationRendersFlatWithAWarning) {
    auto tile = makeTile([](float, float) { return 0.0f; });
    tile->dem.coverage = 0.25f;  // the compiler had DEM for a quarter of it
    const Scene s = render(tile, 300.0, MapStyle::day());
    EXPECT_EQ(s.renderer->mapStats().flat_tiles, 1u);
    ASSERT_EQ(s.renderer->mapStats().new_flat_tiles.size(), 1u) << "reported once, for the caller's warning";
    EXPECT_EQ(s.renderer->mapStats().new_flat_tiles[0].id.toString(), "10/5/7");
    EXPECT_FLOAT_EQ(s.renderer->mapStats().new_flat_tiles[0].coverage, 0.25f);
    EXPECT_EQ(s.renderer->mapStats().tiles_drawn, 1u);
}

TEST(MapRender, TerrainOnlyLayerShowsNoRoads) {
    auto tile = makeTile([](float, float) { return 500.0f; });
    tile->roads.push_back(road(map::RoadClass::Residential, {{300, 500}, {700, 500}}));
    MapLayers terrain_only;
    terrain_only.roads = false;
    const Scene s = render(tile, 300.0, wideRoads(), terrain_only);
    EXPECT_EQ(s.at({500.0, 500.0, 500.0}), s.at({500.0, 560.0, 500.0}));
    EXPECT_EQ(s.renderer->mapStats().road_segments, 0u);
    EXPECT_EQ(s.renderer->mapStats().tiles_drawn, 1u);
}

TEST(MapRender, RouteIsDrawnAboveRoadsAndDimmedBehindTheCar) {
    auto tile = makeTile([](float, float) { return 500.0f; });
    tile->roads.push_back(road(map::RoadClass::Residential, {{300, 500}, {700, 500}}));
    RouteGeometry route;
    for (int i = 0; i <= 8; ++i) {
        route.points.push_back({tile->origin_x + 300.0 + 50.0 * i, tile->origin_y + 500.0, 500.0});
        route.measure_m.push_back(50.0 * i);
    }
    MapStyle style = wideRoads();
    style.route_width_m = 24.0f;
    const Scene s = renderWith(tile, style, {500.0, 500.0, 800.0}, {500.0, 500.0, 0.0}, {0.0, 1.0, 0.0}, {},
                               [&](MapFrame& frame, const glm::dvec3& origin) {
                                   frame.route = &route;
                                   frame.route_progress_m = 200.0;  // driven up to x = 500
                                   frame.marker = MarkerState{origin + glm::dvec3(500.0, 500.0, 500.0), 90.0, false};
                               });
    const glm::ivec3 ahead = s.at({620.0, 500.0, 500.0});
    const glm::ivec3 behind = s.at({380.0, 500.0, 500.0});
    EXPECT_TRUE(near(ahead, to8(style.route_color))) << "route colour ahead of the car";
    EXPECT_FALSE(near(behind, to8(style.route_color), 20)) << "the driven part is dimmed";
    EXPECT_GT(behind.x, to8(style.route_color).x) << "dimmed towards grey";
    // The marker: its colour at the projected vehicle position, constant screen size.
    const glm::vec2 c = s.project({500.0, 500.0, 500.0});
    const auto* px = s.image.pixel(static_cast<int>(c.x), static_cast<int>(c.y));
    EXPECT_TRUE(near({px[0], px[1], px[2]}, to8(glm::vec3(style.marker_color)), 10));
}

TEST(MapRender, StaleMarkerIsGrey) {
    auto tile = makeTile([](float, float) { return 500.0f; });
    const Scene s = renderWith(tile, MapStyle::day(), {500.0, 500.0, 800.0}, {500.0, 500.0, 0.0}, {0.0, 1.0, 0.0}, {},
                               [](MapFrame& frame, const glm::dvec3& origin) {
                                   frame.marker = MarkerState{origin + glm::dvec3(500.0, 500.0, 500.0), 0.0, true};
                               });
    EXPECT_TRUE(near(s.at({500.0, 500.0, 500.0}), to8(glm::vec3(MapStyle::day().marker_stale_color)), 10));
}

TEST(MapRender, BuildingsStandOnTheTerrainAndHideWhatIsBehind) {
    auto tile = makeTile([](float, float) { return 500.0f; });
    map::Building b;
    b.footprint.vertices = {{480, 480}, {520, 480}, {520, 520}, {480, 520}};
    b.footprint.ring_ends = {4};
    b.footprint.indices = {0, 1, 2, 0, 2, 3};
    b.height_m = 30.0f;
    tile->buildings.push_back(b);
    tile->roads.push_back(road(map::RoadClass::Residential, {{300, 500}, {700, 500}}));
    const TileMesh mesh = buildTileMesh(*tile);
    EXPECT_EQ(mesh.buildings.size(), 4u + 4u * 4u) << "roof + four walls";
    EXPECT_EQ(mesh.building_indices.size(), 6u + 4u * 6u);
    const Scene s = render(tile, 300.0, wideRoads());
    // Seen from straight above the roof covers the road under it.
    const glm::ivec3 roof = s.at({500.0, 500.0, 530.0});
    const glm::ivec3 fill = to8(wideRoads().roads.classes[static_cast<int>(map::RoadClass::Residential)].fill);
    EXPECT_FALSE(near(roof, fill, 10)) << "road drawn over the building roof";
    EXPECT_TRUE(near(s.at({400.0, 500.0, 500.0}), fill));
}

}  // namespace
