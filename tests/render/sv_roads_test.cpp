// SPDX-License-Identifier: Apache-2.0
// Shadow-volume roads (seed 3.5, issue #8): instances and technique selection, caps and draping
// on synthetic tiles, the high-resolution terrain case (the store's SRTM tile refined to 10 m)
// where roads draped on the shipped grid leave the surface and SV roads stay on it (the golden
// views are render cases, tests/render/cases/andorra_sv_*). Mesa llvmpipe through EGL.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <memory>
#include <string>

#include "andorra_drive.h"
#include "dem_refine.h"
#include "drive_scene.h"
#include "gl/sv_roads.h"
#include "golden.h"
#include "navmap/render/renderer.h"
#include "navmap/render/road_style.h"
#include "road_draping.h"
#include "synthetic_tile.h"
#include "test_paths.h"

namespace {

using namespace navmap::render;
using navmap::test::kAndorraLaVella;
namespace map = navmap::map;

constexpr int kW = 640, kH = 480;

using navmap::test::makeTile;
using navmap::test::road;

HeightGrid gridOf(const map::Tile& tile) {
    return HeightGrid{tile.dem.size, tile.size_m / (tile.dem.size - 1), tile.dem.heights.data()};
}

glm::ivec3 to8(glm::vec3 c) { return glm::ivec3(glm::round(c * 255.0f)); }

bool near(glm::ivec3 a, glm::ivec3 b, int tol = 6) {
    return std::abs(a.x - b.x) <= tol && std::abs(a.y - b.y) <= tol && std::abs(a.z - b.z) <= tol;
}

// One renderer and camera over a set of tiles; frames rendered with different layers.
struct View {
    std::unique_ptr<Renderer> renderer;
    Camera camera;
    glm::dvec3 origin;  // tile origin: points below are tile-local
    int width = kW, height = kH;

    View(const map::Tile& tile, glm::dvec3 eye, glm::dvec3 target, glm::dvec3 up, const MapStyle& style,
         int msaa = -1) {
        RendererOptions o;
        o.width = width;
        o.height = height;
        o.msaa_samples = msaa;
        renderer = Renderer::create(o);
        renderer->setMapStyle(style);
        origin = glm::dvec3(tile.origin_x, tile.origin_y, 0.0);
        camera.eye = origin + eye;
        camera.target = origin + target;
        camera.up = up;
        camera.near_m = 5.0;
        camera.far_m = 8000.0;
    }
    Image render(const std::vector<std::shared_ptr<const map::Tile>>& tiles, const MapLayers& layers,
                 MapFrameStats* stats = nullptr) {
        MapFrame frame;
        frame.camera = camera;
        frame.tiles = tiles;
        frame.layers = layers;
        renderer->renderMap(frame);
        if (stats) *stats = renderer->mapStats();
        return renderer->readSync();
    }
    // Pixel of a tile-local point; false when off screen or behind the camera.
    bool project(glm::dvec3 local, glm::ivec2& px) const {
        const glm::mat4 vp = camera.projection(double(width) / height) * camera.viewRelativeTo(origin);
        const glm::vec4 c = vp * glm::vec4(glm::vec3(local), 1.0f);
        if (c.w <= 0.0f) return false;
        px = glm::ivec2(static_cast<int>((c.x / c.w * 0.5f + 0.5f) * width),
                        static_cast<int>((1.0f - (c.y / c.w * 0.5f + 0.5f)) * height));
        return px.x >= 1 && px.y >= 1 && px.x < width - 1 && px.y < height - 1;
    }
};

// NAVMAP_SV_DUMP=<dir> writes the frames a test compares, to look at them.
void dump(const Image& image, const std::string& name) {
    const char* dir = std::getenv("NAVMAP_SV_DUMP");
    if (!dir) return;
    std::string error;
    if (!writePng(std::filesystem::path(dir) / (name + ".png"), image, &error)) ADD_FAILURE() << error;
}

glm::ivec3 pixel(const Image& image, glm::ivec2 p) {
    const auto* px = image.pixel(p.x, p.y);
    return {px[0], px[1], px[2]};
}

MapLayers layers(RoadTechnique technique, bool roads = true) {
    MapLayers l;
    l.roads = roads;
    l.outlines = false;  // the dark outline would count as road next to the road edge
    l.buildings = false;
    l.route = false;
    l.marker = false;
    l.road_technique = technique;
    return l;
}

MapStyle wideRoads(float width = 40.0f) {
    MapStyle style = MapStyle::day();
    for (auto& c : style.roads.classes) {
        c.width_m = width;
        c.casing_m = 0.0f;
    }
    style.roads.scale_threshold_m = 1e6f;  // no width scaling in these close-ups
    return style;
}

// ---------------------------------------------------------------------------------------------
// CPU side

TEST(SvRoads, InstancesRunLeastImportantFirstAndBoundTheTerrain) {
    auto tile = makeTile([](float x, float y) { return 500.0f + 0.3f * x + 20.0f * std::sin(y / 50.0f); });
    tile->roads.push_back(road(map::RoadClass::Motorway, {{100, 100}, {300, 120}}));
    tile->roads.push_back(road(map::RoadClass::Residential, {{400, 400}, {450, 500}, {520, 560}}));
    map::Road tunnel = road(map::RoadClass::Primary, {{10, 10}, {900, 900}});
    tunnel.flags = map::road_flags::kTunnel;
    tile->roads.push_back(tunnel);
    const auto sv = gl::buildSvTileRoads(*tile, RoadStyle::day());
    // Segments of 201, 112 and 92 m in pieces of at most 40 m (no draping pre-process); tunnels hidden.
    ASSERT_EQ(sv.instances.size(), 6u + 3u + 3u);
    EXPECT_EQ(static_cast<map::RoadClass>(sv.instances[0].road_class), map::RoadClass::Residential);
    EXPECT_EQ(static_cast<map::RoadClass>(sv.instances.back().road_class), map::RoadClass::Motorway);
    EXPECT_EQ(sv.class_first[static_cast<int>(map::RoadClass::Motorway)], 6u);
    EXPECT_EQ(sv.instances[0].segment.x, 400.0f);
    EXPECT_EQ(sv.instances[5].segment.z, 520.0f);
    EXPECT_GT(sv.max_slope, 0.3f) << "slope bound below the terrain's x gradient";
    // The z range holds the surface along and around each segment (within the reach).
    const HeightGrid grid = gridOf(*tile);
    for (const auto& inst : sv.instances) {
        const glm::vec2 a(inst.segment.x, inst.segment.y), b(inst.segment.z, inst.segment.w);
        const glm::vec2 n = glm::normalize(glm::vec2(-(b - a).y, (b - a).x));
        for (float f = 0.0f; f <= 1.0f; f += 0.1f) {
            for (float off : {-inst.reach, 0.0f, inst.reach}) {
                const glm::vec2 p = glm::mix(a, b, f) + off * n;
                const double z = grid.heightAt(p.x, p.y) - inst.planeAt(p);
                EXPECT_GE(z, inst.z_range.x - 1e-3);
                EXPECT_LE(z, inst.z_range.y + 1e-3);
            }
        }
        EXPECT_LT(inst.z_range.y - inst.z_range.x, 12.0f)
            << "a thin volume along the terrain, not the tile's height range";
        const RoadStyle day = RoadStyle::day();
        const auto& cs = day.classes[static_cast<std::size_t>(inst.road_class)];
        EXPECT_FLOAT_EQ(inst.reach, 0.5f * cs.width_m + cs.casing_m + 1.0f);
    }
}

TEST(SvRoads, AutoPicksShadowVolumesOnFineDems) {
    MapFrame frame;
    frame.tiles = {makeTile([](float, float) { return 0.0f; }, 17)};  // 62.5 m: the shipped store
    frame.layers.road_technique = RoadTechnique::Auto;
    EXPECT_EQ(gl::resolveRoadTechnique(frame), RoadTechnique::Geometric);
    frame.tiles.push_back(makeTile([](float, float) { return 0.0f; }, 101));  // 10 m
    EXPECT_EQ(gl::resolveRoadTechnique(frame), RoadTechnique::ShadowVolume);
    frame.layers.road_technique = RoadTechnique::Geometric;
    EXPECT_EQ(gl::resolveRoadTechnique(frame), RoadTechnique::Geometric) << "an explicit choice wins";
    frame.layers.road_technique = RoadTechnique::ShadowVolume;
    frame.tiles.resize(1);
    EXPECT_EQ(gl::resolveRoadTechnique(frame), RoadTechnique::ShadowVolume);
}

TEST(DemRefine, BicubicKeepsTheSamplesAndAddsBoundedDetail) {
    auto tile = makeTile([](float x, float y) { return 1000.0f + 0.2f * x - 0.1f * y; });
    DemRefineOptions flat;
    flat.detail_amplitude_m = 0.0f;
    const map::TileDem smooth = refineDem(tile->dem, tile->size_m, tile->origin_x, tile->origin_y, flat);
    ASSERT_EQ(smooth.size, 101);  // 1000 m at 10 m
    EXPECT_FLOAT_EQ(smooth.spacing_m, 10.0f);
    // Catmull-Rom reproduces a plane exactly, at and between the coarse samples.
    for (int r = 0; r < smooth.size; r += 7)
        for (int c = 0; c < smooth.size; c += 5)
            EXPECT_NEAR(smooth.at(r, c), 1000.0f + 0.2f * c * 10.0f - 0.1f * r * 10.0f, 0.01f);
    const map::TileDem rough = refineDem(tile->dem, tile->size_m, tile->origin_x, tile->origin_y);
    double max_dev = 0.0, sum_sq = 0.0;
    for (std::size_t i = 0; i < rough.heights.size(); ++i) {
        const double d = rough.heights[i] - smooth.heights[i];
        max_dev = std::max(max_dev, std::abs(d));
        sum_sq += d * d;
    }
    EXPECT_LT(max_dev, 8.0) << "detail amplitude: 4 + 2 + 1 + 0.5 m at most";
    EXPECT_GT(std::sqrt(sum_sq / rough.heights.size()), 0.5) << "a few metres of relief added";
    // Deterministic.
    EXPECT_EQ(rough.heights, refineDem(tile->dem, tile->size_m, tile->origin_x, tile->origin_y).heights);
}

// ---------------------------------------------------------------------------------------------
// Synthetic scenes

TEST(SvRoads, DeadEndCapIsRoundAndMatchesGeometricOnFlatTerrain) {
    auto tile = makeTile([](float, float) { return 500.0f; });
    tile->roads.push_back(road(map::RoadClass::Residential, {{380, 500}, {500, 500}}));
    View v(*tile, {500.0, 500.0, 800.0}, {500.0, 500.0, 0.0}, {0.0, 1.0, 0.0}, wideRoads());
    MapFrameStats stats;
    const Image sv = v.render({tile}, layers(RoadTechnique::ShadowVolume), &stats);
    EXPECT_TRUE(stats.sv_roads);
    EXPECT_EQ(stats.road_segments, 3u) << "120 m in pieces of at most 40 m";
    const glm::ivec3 fill = to8(wideRoads().roads.classes[static_cast<int>(map::RoadClass::Residential)].fill);
    auto at = [&](const Image& img, glm::dvec3 p) {
        glm::ivec2 px;
        EXPECT_TRUE(v.project(p, px));
        return pixel(img, px);
    };
    const double r = 20.0;
    for (double a = -80.0; a <= 80.0; a += 20.0) {  // seed 3.5.1: the ray-cylinder cap
        const double rad = glm::radians(a);
        EXPECT_TRUE(near(at(sv, {500.0 + 0.85 * r * std::cos(rad), 500.0 + 0.85 * r * std::sin(rad), 500.0}), fill))
            << "arc point at " << a << " deg not covered";
    }
    for (double sy : {-1.0, 1.0}) {
        EXPECT_FALSE(near(at(sv, {500.0 + 0.9 * r, 500.0 + sy * 0.9 * r, 500.0}), fill, 30)) << "the cap is not round";
    }
    EXPECT_FALSE(near(at(sv, {500.0 + 1.2 * r, 500.0, 500.0}), fill, 30));
    // Same pixels as the geometric approach (flat ground: both are exact).
    const Image geo = v.render({tile}, layers(RoadTechnique::Geometric), &stats);
    EXPECT_FALSE(stats.sv_roads);
    const auto cmp = navmap::test::compareImages(geo, sv, 24);
    EXPECT_LT(cmp.differing_fraction, 0.002) << cmp.differing_pixels << " pixels differ from GEO";
}

// seed 7.3 in the shadow-volume approach: a class left out of distant views narrows per pixel to
// the fraction selectionFade() gives, as wide as the geometric roads draw it, and its boxes are
// clipped only where nothing is left. Straight down from 300 m on a path made 8 m wide (about
// 15 px), the class's threshold moved through the fade band.
TEST(SvRoads, SelectedClassNarrowsAsTheGeometricRoads) {
    auto tile = makeTile([](float, float) { return 500.0f; });
    tile->roads.push_back(road(map::RoadClass::Path, {{470, 500}, {530, 500}}));
    constexpr auto kPath = static_cast<std::size_t>(map::RoadClass::Path);
    const float distance = 300.0f;
    const float focal_px = 0.5f * kH / static_cast<float>(std::tan(glm::radians(Camera{}.fov_y_deg) / 2.0));
    const float true_px = 8.0f * focal_px / distance;
    const glm::ivec3 fill = to8(wideRoads().roads.classes[kPath].fill);
    // Fill pixels down the column through the road's middle.
    auto drawn_px = [&](float select_px, RoadTechnique technique, bool selection) {
        MapStyle style = wideRoads(8.0f);
        style.roads.classes[kPath].select_px = select_px;
        View v(*tile, {500.0, 500.0, 500.0 + distance}, {500.0, 500.0, 0.0}, {0.0, 1.0, 0.0}, style);
        MapLayers l = layers(technique);
        l.road_selection = selection;
        const Image image = v.render({tile}, l);
        glm::ivec2 mid;
        EXPECT_TRUE(v.project({500.0, 500.0, 500.0}, mid));
        int n = 0;
        for (int y = 0; y < kH; ++y) n += near(pixel(image, {mid.x, y}), fill);
        return n;
    };
    for (const float select_px : {5.0f, 11.0f, 13.0f, 14.5f, 16.0f}) {
        const float expected = true_px * selectionFade(8.0f, select_px, focal_px).at(distance);
        const int sv = drawn_px(select_px, RoadTechnique::ShadowVolume, true);
        const int geo = drawn_px(select_px, RoadTechnique::Geometric, true);
        std::printf("[ measure  ] threshold %.1f px, true width %.2f px: %d px drawn (geometric %d), %.2f expected\n",
                    select_px, true_px, sv, geo, expected);
        EXPECT_NEAR(sv, expected, 1.5) << "threshold " << select_px;
        EXPECT_NEAR(sv, geo, 1.0) << "threshold " << select_px;
        EXPECT_NEAR(drawn_px(select_px, RoadTechnique::ShadowVolume, false), true_px, 1.5)
            << "selection off, threshold " << select_px;
    }
}

TEST(SvRoads, CameraInsideTheRoadVolumeStillSeesTheRoad) {
    // seed 3.5.2: only back faces are drawn, so a camera inside a box (here 0.6 m above a flat
    // road whose volume reaches 1 m up) still gets every pixel of the road ahead of it.
    auto tile = makeTile([](float, float) { return 500.0f; });
    tile->roads.push_back(road(map::RoadClass::Residential, {{100, 500}, {900, 500}}));
    View v(*tile, {300.0, 500.0, 500.6}, {600.0, 500.0, 490.0}, {0.0, 0.0, 1.0}, wideRoads());
    v.camera.near_m = 0.1;
    MapFrameStats stats;
    const Image sv = v.render({tile}, layers(RoadTechnique::ShadowVolume), &stats);
    dump(sv, "inside_sv");
    EXPECT_TRUE(stats.sv_roads);
    const glm::ivec3 fill = to8(wideRoads().roads.classes[static_cast<int>(map::RoadClass::Residential)].fill);
    for (double x : {310.0, 320.0, 360.0, 450.0}) {
        for (double y : {497.0, 500.0, 503.0}) {
            glm::ivec2 px;
            ASSERT_TRUE(v.project({x, y, 500.0}, px));
            EXPECT_TRUE(near(pixel(sv, px), fill)) << "no road at " << x << ", " << y;
        }
    }
}

TEST(SvRoads, MultisampledTargetsResolveTheTerrainDepth) {
    // The terrain depth is drawn multisampled and resolved into the texture the SV pass reads
    // (GPUs use 4x MSAA by default; forced here on llvmpipe).
    auto tile = makeTile([](float x, float) { return 500.0f + 0.2f * x; });
    tile->roads.push_back(road(map::RoadClass::Residential, {{300, 500}, {700, 480}}));
    View v(*tile, {500.0, 200.0, 900.0}, {500.0, 500.0, 600.0}, {0.0, 0.0, 1.0}, wideRoads(), 4);
    const DeviceInfo& device = v.renderer->device();
    if (device.msaa_samples < 2) GTEST_SKIP() << "no multisampling on " << device.renderer;
    MapFrameStats stats;
    const Image sv = v.render({tile}, layers(RoadTechnique::ShadowVolume), &stats);
    EXPECT_TRUE(stats.sv_roads);
    const Image geo = v.render({tile}, layers(RoadTechnique::Geometric));
    dump(sv, "msaa_sv");
    const auto cmp = navmap::test::compareImages(geo, sv, 24);
    // SV decides per pixel (one resolved terrain depth per pixel), so only its edges lack the
    // multisampled smoothing GEO's edges get: a thin line of pixels along both road borders.
    EXPECT_LT(cmp.differing_fraction, 0.01) << cmp.differing_pixels << " pixels differ from GEO on a plane";
    const auto with_roads =
        navmap::test::compareImages(v.render({tile}, layers(RoadTechnique::ShadowVolume, false)), sv, 24);
    EXPECT_GT(with_roads.differing_fraction, 0.02) << "no SV road drawn";
}

TEST(SvRoads, DrapeOnSteepHillsAndBuildingsStillHideThem) {
    // Ridges across the road: the road climbs and falls 60 m every 200 m.
    auto tile = makeTile([](float x, float) { return 600.0f + 30.0f * std::sin(x / 32.0f); }, 65);
    tile->roads.push_back(road(map::RoadClass::Secondary, {{150, 500}, {850, 500}}));
    map::Building b;
    b.footprint.vertices = {{640, 380}, {700, 380}, {700, 440}, {640, 440}};
    b.footprint.ring_ends = {4};
    b.footprint.indices = {0, 1, 2, 0, 2, 3};
    b.height_m = 150.0f;  // a tower between the camera and the road's east part
    tile->buildings.push_back(b);
    const MapStyle style = wideRoads(24.0f);
    // Oblique from the south, looking along the ridges (no terrain hides the road).
    View v(*tile, {500.0, 100.0, 1100.0}, {500.0, 500.0, 600.0}, {0.0, 0.0, 1.0}, style);
    const Image terrain = v.render({tile}, layers(RoadTechnique::ShadowVolume, false));
    const Image sv = v.render({tile}, layers(RoadTechnique::ShadowVolume));
    dump(terrain, "hills_terrain");
    dump(sv, "hills_sv");
    dump(v.render({tile}, layers(RoadTechnique::Geometric)), "hills_geo");
    const HeightGrid grid = gridOf(*tile);
    int on = 0, on_total = 0, off = 0, off_total = 0;
    for (double x = 200.0; x <= 600.0; x += 5.0) {
        for (double y : {492.0, 500.0, 508.0}) {  // inside the 24 m road
            glm::ivec2 px;
            if (!v.project({x, y, grid.heightAt(x, y)}, px)) continue;
            ++on_total;
            on += !near(pixel(sv, px), pixel(terrain, px), 20);
        }
        for (double y : {470.0, 530.0}) {  // 18 m off the centreline: terrain
            glm::ivec2 px;
            if (!v.project({x, y, grid.heightAt(x, y)}, px)) continue;
            ++off_total;
            off += !near(pixel(sv, px), pixel(terrain, px), 20);
        }
    }
    ASSERT_GT(on_total, 150);
    EXPECT_GE(on, on_total * 97 / 100) << "road pixels missing on the surface";
    EXPECT_LE(off, off_total / 100) << "road pixels off the road";
    // Buildings in front hide the SV road (gl_FragDepth is the terrain point's depth).
    MapLayers with_buildings = layers(RoadTechnique::ShadowVolume);
    with_buildings.buildings = true;
    const Image hidden = v.render({tile}, with_buildings);
    MapLayers buildings_only = with_buildings;
    buildings_only.roads = false;
    const Image no_roads = v.render({tile}, buildings_only);
    dump(hidden, "hills_sv_buildings");
    // The roof's centre lies on the road's line of sight (the roof sits on the footprint's lowest point).
    double base = 1e9;
    for (const auto& p : b.footprint.vertices) base = std::min(base, grid.heightAt(p.x, p.y));
    glm::ivec2 roof;
    ASSERT_TRUE(v.project({670.0, 410.0, base + 150.0}, roof));
    glm::ivec2 road_behind;
    ASSERT_TRUE(v.project({670.0, 500.0, grid.heightAt(670.0, 500.0)}, road_behind));
    EXPECT_LT(roof.y, road_behind.y + 60) << "the roof is not in front of the road";
    EXPECT_TRUE(near(pixel(hidden, roof), pixel(no_roads, roof), 4)) << "road drawn over the building";
    int covered = 0;
    for (int y = roof.y - 3; y <= roof.y + 3; ++y)
        covered += near(pixel(hidden, {roof.x, y}), pixel(no_roads, {roof.x, y}), 4);
    EXPECT_EQ(covered, 7);
}

// ---------------------------------------------------------------------------------------------
// High-resolution terrain (issue #8): the store's SRTM tile under Andorra la Vella refined to
// 10 m with a few metres of fractal detail.

struct HighRes {
    std::shared_ptr<map::TileStore> store;
    std::shared_ptr<const map::Tile> coarse;
    std::shared_ptr<map::Tile> fine;
};

HighRes* highRes() {
    static std::unique_ptr<HighRes> h;
    if (h) return h.get();
    const auto path = navmap::test::binaryDir() / "andorra.navmap";
    if (!std::filesystem::exists(path)) return nullptr;
    auto out = std::make_unique<HighRes>();
    out->store = map::TileStore::open(path);
    const auto& scheme = out->store->scheme();
    const auto p = out->store->projection().forward(kAndorraLaVella.lat_deg, kAndorraLaVella.lon_deg);
    const auto id = scheme.tileAt(scheme.leafLevel(), p);
    if (!id) return nullptr;
    out->coarse = out->store->load(*id).tile;
    if (!out->coarse) return nullptr;
    out->fine = refineTile(*out->coarse);
    h = std::move(out);
    return h.get();
}

// Long straight road segments (not tunnels or bridges) well inside the tile.
struct Segment {
    glm::dvec2 a, b;
    map::RoadClass cls{};
};
std::vector<Segment> straightSegments(const map::Tile& tile) {
    std::vector<Segment> out;
    for (const auto& r : tile.roads) {
        if (r.flags & (map::road_flags::kTunnel | map::road_flags::kBridge)) continue;
        for (std::size_t i = 0; i + 1 < r.points.size(); ++i) {
            const glm::dvec2 p(r.points[i].x, r.points[i].y), q(r.points[i + 1].x, r.points[i + 1].y);
            auto inside = [&](glm::dvec2 v) {
                return v.x > 250 && v.y > 250 && v.x < tile.size_m - 250 && v.y < tile.size_m - 250;
            };
            if (glm::length(q - p) > 80.0 && inside(p) && inside(q)) out.push_back({p, q, r.cls});
        }
    }
    return out;
}

/// Where a flat quad across the road (half width `half_w`, at its centreline's height on the
/// `fine` surface) floats over ground that falls away on its left: seen from its right at
/// `pitch`, the quad then covers ground `beyond` metres past its edge. Counts such places along
/// the segment every 2 m (the flat pieces of the geometric draping leave the surface, seed 3.7).
int overhangs(const HeightGrid& fine, const Segment& s, double half_w, double beyond, double pitch) {
    const glm::dvec2 d = glm::normalize(s.b - s.a), side(-d.y, d.x);
    const double len = glm::length(s.b - s.a);
    int n = 0;
    for (double t = 0.1 * len; t <= 0.9 * len; t += 2.0) {
        const glm::dvec2 c = s.a + t * d, e = c + (half_w + beyond) * side;
        n += fine.heightAt(c.x, c.y) - fine.heightAt(e.x, e.y) > beyond * std::tan(pitch);
    }
    return n;
}

TEST(SvRoadsHighRes, GeometricDrapingOnTheShippedGridLeavesTheSurfaceShadowVolumesDoNot) {
    HighRes* h = highRes();
    if (!h) GTEST_SKIP() << "build/andorra.navmap missing (target navmap_default_store)";
    ASSERT_EQ(h->fine->dem.size, std::lround(h->coarse->size_m / 10.0) + 1) << "a leaf tile at 10 m";
    const HeightGrid coarse = gridOf(*h->coarse), fine = gridOf(*h->fine);
    // The segment, in the direction, whose flat pieces overhang the refined slope most where the
    // camera below looks (a road along a hillside, the valley on its left).
    std::vector<Segment> segments = straightSegments(*h->coarse);
    ASSERT_FALSE(segments.empty());
    for (std::size_t i = 0, n = segments.size(); i < n; ++i)
        segments.push_back({segments[i].b, segments[i].a, segments[i].cls});
    const Segment& seg = *std::max_element(segments.begin(), segments.end(), [&](const Segment& x, const Segment& y) {
        return overhangs(fine, x, 7.0, 2.8, glm::radians(50.0)) < overhangs(fine, y, 7.0, 2.8, glm::radians(50.0));
    });
    const glm::dvec2 a = seg.a, b = seg.b;
    const map::RoadClass cls = seg.cls;
    std::printf("[ high-res ] %zu straight segments; the chosen one overhangs its slope at %d places\n",
                segments.size() / 2, overhangs(fine, seg, 7.0, 2.8, glm::radians(50.0)));

    // GEO as shipped: the centreline draped on the store's 62.5 m grid (seed 3.6.1) is off the
    // 10 m surface by metres: roads sink into bumps and float over hollows.
    const std::vector<glm::dvec2> line = {a, b};
    const auto draped = drapePolyline(coarse, line);
    double max_off = 0.0, sum_off = 0.0;
    int n = 0;
    for (std::size_t i = 0; i + 1 < draped.size(); ++i) {
        for (double f = 0.0; f < 1.0; f += 0.1) {
            const glm::dvec3 p = glm::mix(draped[i], draped[i + 1], f);
            const double off = p.z - fine.heightAt(p.x, p.y);
            max_off = std::max(max_off, std::abs(off));
            sum_off += std::abs(off);
            ++n;
        }
    }
    std::printf(
        "[ high-res ] road class %d, %.0f m: GEO on the shipped grid is off the 10 m surface by %.2f m mean, %.2f m "
        "max\n",
        static_cast<int>(cls), glm::length(b - a), sum_off / n, max_off);
    EXPECT_GT(max_off, 1.5);

    // Render: look across the road from 400 m, 50 degrees down.
    const glm::dvec2 mid = 0.5 * (a + b);
    const glm::dvec2 dir = glm::normalize(b - a);
    const glm::dvec2 side(-dir.y, dir.x);
    const glm::dvec3 target(mid, fine.heightAt(mid.x, mid.y));
    const double pitch = glm::radians(50.0);
    const glm::dvec3 eye = target + 400.0 * glm::dvec3(-side * std::cos(pitch), std::sin(pitch));
    const float width = 14.0f;
    const MapStyle style = wideRoads(width);
    View v(*h->fine, eye, target, {0.0, 0.0, 1.0}, style);
    const std::vector<std::shared_ptr<const map::Tile>> tiles = {h->fine};
    const Image terrain = v.render(tiles, layers(RoadTechnique::ShadowVolume, false));
    MapFrameStats stats;
    const Image sv = v.render(tiles, layers(RoadTechnique::Auto), &stats);
    dump(terrain, "highres_terrain");
    dump(sv, "highres_sv");
    EXPECT_TRUE(stats.sv_roads) << "Auto picks SV on the 10 m DEM";

    // Road pixels on the terrain surface along the road; none floating beside it. Points next to
    // another road of the tile (a parallel carriageway, a side street) are left out of the
    // "beside" and "outside" sets.
    auto near_other_road = [&](glm::dvec2 p) {
        for (const auto& r : h->coarse->roads) {
            for (std::size_t i = 0; i + 1 < r.points.size(); ++i) {
                const glm::dvec2 s0(r.points[i].x, r.points[i].y), s1(r.points[i + 1].x, r.points[i + 1].y);
                if ((s0 == a && s1 == b) || (s0 == b && s1 == a)) continue;  // the road looked at
                const glm::dvec2 d = s1 - s0;
                const double t = std::clamp(glm::dot(p - s0, d) / std::max(glm::dot(d, d), 1e-9), 0.0, 1.0);
                if (glm::length(p - (s0 + t * d)) < width) return true;
            }
        }
        return false;
    };
    int on = 0, on_total = 0, beside = 0, beside_total = 0;
    const double len = glm::length(b - a);
    for (double s = 0.1 * len; s <= 0.9 * len; s += 2.0) {
        for (double off : {-0.3 * width, 0.0, 0.3 * width}) {
            const glm::dvec2 p = a + s * dir + off * side;
            glm::ivec2 px;
            if (!v.project({p, fine.heightAt(p.x, p.y)}, px)) continue;
            ++on_total;
            on += !near(pixel(sv, px), pixel(terrain, px), 20);
        }
        for (double off : {-1.5 * width, 1.5 * width}) {
            const glm::dvec2 p = a + s * dir + off * side;
            if (near_other_road(p)) continue;
            glm::ivec2 px;
            if (!v.project({p, fine.heightAt(p.x, p.y)}, px)) continue;
            ++beside_total;
            beside += !near(pixel(sv, px), pixel(terrain, px), 20);
        }
    }
    std::printf("[ high-res ] SV: %d/%d road samples covered, %d/%d samples beside the road touched\n", on, on_total,
                beside, beside_total);
    ASSERT_GT(on_total, 60);
    ASSERT_GT(beside_total, 20);
    EXPECT_GE(on, on_total * 98 / 100) << "SV road pixels missing on the surface";
    EXPECT_EQ(beside, 0) << "SV road pixels off the road";

    // Where the GEO road (draped on the shipped grid) would be drawn: its points project away from
    // the surface points they belong to, by pixels.
    double max_px = 0.0;
    for (std::size_t i = 0; i + 1 < draped.size(); ++i) {
        for (double f = 0.0; f < 1.0; f += 0.1) {
            const glm::dvec3 p = glm::mix(draped[i], draped[i + 1], f);
            glm::ivec2 q0, q1;
            if (!v.project(p, q0) || !v.project({p.x, p.y, fine.heightAt(p.x, p.y)}, q1)) continue;
            max_px = std::max(max_px, glm::length(glm::dvec2(q0 - q1)));
        }
    }
    std::printf("[ high-res ] GEO (shipped grid) road drawn up to %.1f px off its place on the surface\n", max_px);
    EXPECT_GT(max_px, 2.0);
    // GEO draped at runtime on the 10 m grid: the centreline is on the surface, but each piece is
    // a flat quad across the road; on the refined slopes its edges float over (or sink into) the
    // surface, so the road is drawn where the terrain beside it is (seed 3.7, Fig. 3.15).
    const Image geo = v.render(tiles, layers(RoadTechnique::Geometric));
    dump(geo, "highres_geo");
    int geo_outside = 0, sv_outside = 0, outside_total = 0;
    for (double s = 0.1 * len; s <= 0.9 * len; s += 1.0) {
        for (double sign : {-1.0, 1.0}) {
            const glm::dvec2 p = a + s * dir + sign * 0.7 * width * side;  // 2.8 m beyond the edge
            if (near_other_road(p)) continue;
            glm::ivec2 px;
            if (!v.project({p, fine.heightAt(p.x, p.y)}, px)) continue;
            ++outside_total;
            geo_outside += !near(pixel(geo, px), pixel(terrain, px), 20);
            sv_outside += !near(pixel(sv, px), pixel(terrain, px), 20);
        }
    }
    std::printf("[ high-res ] 0.7 w from the centreline on the surface: GEO road at %d/%d samples, SV at %d\n",
                geo_outside, outside_total, sv_outside);
    ASSERT_GT(outside_total, 100);
    EXPECT_GT(geo_outside, outside_total / 4) << "GEO was expected to spill beyond the road on the 10 m slopes";
    EXPECT_EQ(sv_outside, 0);
    const auto cmp = navmap::test::compareImages(geo, sv, 24);
    std::printf("[ high-res ] GEO vs SV: %zu pixels differ (%.2f%%)\n", cmp.differing_pixels,
                100.0 * cmp.differing_fraction);
}

}  // namespace
