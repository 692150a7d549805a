// SPDX-License-Identifier: Apache-2.0
// The real Andorra store at fixed poses: layers, outlines, lost contexts and culling (issue: map
// rendering; its golden views are render cases, tests/render/cases/andorra_{bird,snail}_*). The
// store is compiled at build time (build/andorra.navmap).
#include <gtest/gtest.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <utility>

#include "andorra_drive.h"
#include "drive_scene.h"
#include "golden.h"
#include "navmap/render/renderer.h"
#include "test_paths.h"
#include "tile_mesh.h"

namespace {

using namespace navmap::render;

constexpr int kW = 640, kH = 240;

std::unique_ptr<Renderer> rendererOfSize(int w, int h) {
    RendererOptions o;
    o.width = w;
    o.height = h;
    return Renderer::create(o);
}

// Pixels whose colour differs at all.
std::size_t differingPixels(const Image& a, const Image& b) {
    std::size_t n = 0;
    for (std::size_t i = 0; i < a.rgba.size(); i += 4) n += std::memcmp(&a.rgba[i], &b.rgba[i], 3) != 0;
    return n;
}

// Pixels whose colour differs between two frames of one size: in all, and in the bottom quarter
// (in the snail's view the ground next to the car).
struct Difference {
    std::size_t all = 0, near = 0;
};
Difference differenceOf(const Image& a, const Image& b) {
    Difference d;
    for (int y = 0; y < a.height; ++y) {
        for (int x = 0; x < a.width; ++x) {
            if (std::memcmp(a.pixel(x, y), b.pixel(x, y), 3) == 0) continue;
            ++d.all;
            d.near += y >= a.height * 3 / 4;
        }
    }
    return d;
}

Image renderView(ViewMode mode, const MapLayers& layers, MapFrameStats* stats = nullptr) {
    auto renderer = rendererOfSize(kW, kH);
    // The car 1.8 km into the drive (Escaldes), camera settled.
    MapFrame frame = navmap::test::settledAndorraFrame(mode, kW, kH);
    frame.layers = layers;
    renderer->renderMap(frame);
    if (stats) *stats = renderer->mapStats();
    return renderer->readSync();
}

MapLayers layersFor(int step) {
    MapLayers l;
    l.roads = step >= 1;
    l.outlines = step >= 1;
    l.buildings = step >= 2;
    l.route = step >= 3;
    l.marker = step >= 3;
    return l;
}

TEST(AndorraMap, DriveIsPlannedOnTheRoadGraph) {
    const auto& d = navmap::test::andorraDrive().drive;
    ASSERT_GT(d.line.size(), 20u);
    // Andorra la Vella -> Encamp along the CG-2 is about 7-9 km.
    EXPECT_GT(d.line.back().measure_m, 6000.0);
    EXPECT_LT(d.line.back().measure_m, 12000.0);
}

TEST(AndorraMap, RoadsChangeTheImageOnlyWhereRoadsAre) {
    const Image terrain = renderView(ViewMode::Bird, layersFor(0));
    const Image roads = renderView(ViewMode::Bird, layersFor(1));
    std::size_t changed = 0;
    for (std::size_t i = 0; i < terrain.rgba.size(); i += 4) changed += terrain.rgba[i] != roads.rgba[i];
    const double fraction = double(changed) / (kW * kH);
    EXPECT_GT(fraction, 0.01) << "roads are visible";
    EXPECT_LT(fraction, 0.5) << "roads cover only part of the view";
}

// The outline filter runs only on the screen cells near the road and route quads (OutlineCells,
// marked on the CPU): the image equals the full-screen filter's, in both views and at the display
// profiles' sizes, while the filter runs on a fraction of the screen; with the road mask packed
// on the GPU (outline_pack.frag, cells from the quads) and with the edges found on the CPU from the
// mask read back (outlineEdges, cells that hold an edge) alike.
TEST(AndorraMap, OutlinesNearRoadsEqualTheFullScreenFilter) {
    using OutlineMask = MapLayers::OutlineMask;
    for (ViewMode mode : {ViewMode::Bird, ViewMode::Snail}) {
        for (const auto& [w, h] : {std::pair{kW, kH}, std::pair{1280, 480}, std::pair{800, 240}}) {
            auto renderer = rendererOfSize(w, h);
            MapFrame frame = navmap::test::settledAndorraFrame(mode, w, h);
            frame.layers = layersFor(3);
            renderer->renderMap(frame);
            const Image near_roads = renderer->readSync();
            const std::size_t filtered = renderer->mapStats().outline_pixels;
            // Automatic: the edges found on the CPU on a software rasterizer, the GPU packs elsewhere.
            EXPECT_EQ(renderer->mapStats().outline_mask_on_cpu, renderer->device().software);
            EXPECT_GT(filtered, 0u);
            EXPECT_LT(filtered, std::size_t(w * h * 3 / 4)) << "the filter runs near roads only";
            Image by[2];  // the mask packed on the GPU, the edges found on the CPU
            for (const OutlineMask where : {OutlineMask::Gpu, OutlineMask::Cpu}) {
                frame.layers.outline_mask = where;
                renderer->renderMap(frame);
                by[where == OutlineMask::Cpu] = renderer->readSync();
                EXPECT_EQ(renderer->mapStats().outline_mask_on_cpu, where == OutlineMask::Cpu);
                std::printf("[ measure  ] %s %dx%d, %s: outline filter on %.1f %% of the screen\n",
                            mode == ViewMode::Bird ? "bird" : "snail", w, h,
                            where == OutlineMask::Cpu ? "edge cells" : "quad cells",
                            100.0 * double(renderer->mapStats().outline_pixels) / (w * h));
            }
            frame.layers.outline_mask = OutlineMask::Auto;
            frame.layers.outlines_near_roads = false;
            renderer->renderMap(frame);
            const Image full = renderer->readSync();
            EXPECT_EQ(renderer->mapStats().outline_pixels, std::size_t(w * h)) << "the whole screen";
            frame.layers.outlines = false;
            renderer->renderMap(frame);
            const Image none = renderer->readSync();
            const std::size_t differ = differingPixels(full, near_roads), outline = differingPixels(full, none);
            EXPECT_GT(outline, std::size_t(w * h / 100)) << "outlines are drawn";
            EXPECT_EQ(differ, 0u) << (mode == ViewMode::Bird ? "bird " : "snail ") << w << "x" << h;
            EXPECT_EQ(differingPixels(full, by[0]), 0u) << "mask packed on the GPU, " << w << "x" << h;
            EXPECT_EQ(differingPixels(full, by[1]), 0u) << "edges found on the CPU, " << w << "x" << h;
        }
    }
}

// Road pieces and buildings are culled per tile block before the vertex stage: the same image
// (roads, outlines, glow, buildings) from far fewer pieces and triangles.
// A frame as given and again with one of its layer switches off: the stats and image of each.
struct Rendered {
    MapFrameStats stats;
    Image image;
};
// `frame` is a copy on purpose: the second render switches the layer off in it (clang-tidy 14
// misses the write through the member pointer).
std::pair<Rendered, Rendered> renderWithAndWithout(Renderer& renderer,
                                                   MapFrame frame,  // NOLINT(performance-unnecessary-value-param)
                                                   bool MapLayers::*option) {
    std::pair<Rendered, Rendered> out;
    for (Rendered* r : {&out.first, &out.second}) {
        renderer.renderMap(frame);
        r->stats = renderer.mapStats();
        r->image = renderer.readSync();
        frame.layers.*option = false;
    }
    return out;
}

// A culling switch (same image, less drawn) on and off in the settled full scene: both views, at
// the test size and at 1280x480, and with the glow, which draws the terrain before the buildings.
struct CullingCase {
    const char* name;  // the view
    ViewMode mode;
    int w, h;
    bool glow;
    Rendered culled, all;
};
template <typename Check>
void forEachCullingCase(bool MapLayers::*option, Check check) {
    for (ViewMode mode : {ViewMode::Bird, ViewMode::Snail}) {
        for (const auto& [w, h, glow] :
             {std::tuple{kW, kH, false}, std::tuple{1280, 480, false}, std::tuple{kW, kH, true}}) {
            auto renderer = rendererOfSize(w, h);
            MapFrame frame = navmap::test::settledAndorraFrame(mode, w, h);
            frame.layers = layersFor(3);
            frame.layers.glow_roads = glow;
            auto [culled, all] = renderWithAndWithout(*renderer, frame, option);
            const CullingCase c{
                mode == ViewMode::Bird ? "bird" : "snail", mode, w, h, glow, std::move(culled), std::move(all)};
            EXPECT_EQ(differingPixels(c.all.image, c.culled.image), 0u)
                << c.name << " " << w << "x" << h << (glow ? " glow" : "");
            check(c);
        }
    }
}

TEST(AndorraMap, RoadAndBuildingBlocksOutsideTheViewAreNotDrawn) {
    forEachCullingCase(&MapLayers::cull_blocks, [](const CullingCase& c) {
        const MapFrameStats& culled = c.culled.stats;
        const MapFrameStats& all = c.all.stats;
        std::printf("[ measure  ] %s %dx%d%s: %zu of %zu road pieces, %zu of %zu building triangles drawn\n", c.name,
                    c.w, c.h, c.glow ? " glow" : "", culled.road_segments, all.road_segments, culled.building_triangles,
                    all.building_triangles);
        EXPECT_GT(culled.road_segments, 0u);
        EXPECT_LT(culled.road_segments, all.road_segments / 2) << c.name;
        EXPECT_GT(culled.building_triangles, 0u);
        EXPECT_LT(culled.building_triangles, all.building_triangles) << c.name;
    });
}

// Road blocks that the drawn terrain hides (MapLayers::cull_hidden_roads, TerrainHorizon) are
// left out: the same image, pixel for pixel, outlines and glow included, from fewer road pieces
// in snail's view, where ridges hide most distant roads.
TEST(AndorraMap, RoadBlocksHiddenBehindTheTerrainAreNotDrawn) {
    forEachCullingCase(&MapLayers::cull_hidden_roads, [](const CullingCase& c) {
        const MapFrameStats& culled = c.culled.stats;
        const MapFrameStats& all = c.all.stats;
        std::printf("[ measure  ] %s %dx%d%s: %zu of %zu road pieces drawn, %zu road blocks hidden, horizon %.2f ms\n",
                    c.name, c.w, c.h, c.glow ? " glow" : "", culled.road_segments, all.road_segments,
                    culled.road_blocks_hidden, culled.horizon_ms);
        EXPECT_EQ(all.road_blocks_hidden, 0u);
        EXPECT_GT(culled.road_segments, 0u) << c.name;
        if (c.mode == ViewMode::Snail) {
            EXPECT_GT(culled.road_blocks_hidden, 0u) << c.w << "x" << c.h;
            EXPECT_LT(culled.road_segments, all.road_segments * 9 / 10) << "ridges hide distant roads";
        }
    });
}

// The settled 1280x480 frame of the full scene in `mode` with a layer switch on and off: the
// stats and images, and the pixels they differ in (printed with the road pieces drawn).
struct Toggled {
    Rendered on, off;
    Difference differ;
};
Toggled toggled(ViewMode mode, bool MapLayers::*option) {
    const int w = 1280, h = 480;
    auto renderer = rendererOfSize(w, h);
    MapFrame frame = navmap::test::settledAndorraFrame(mode, w, h);
    frame.layers = layersFor(3);
    auto [on, off] = renderWithAndWithout(*renderer, frame, option);
    Toggled t{std::move(on), std::move(off), {}};
    t.differ = differenceOf(t.on.image, t.off.image);
    std::printf(
        "[ measure  ] %s %dx%d: %zu of %zu road pieces drawn, %zu pixels differ (%.2f %%), %zu in the bottom quarter\n",
        mode == ViewMode::Bird ? "bird" : "snail", w, h, t.on.stats.road_segments, t.off.stats.road_segments,
        t.differ.all, 100.0 * double(t.differ.all) / double(w * h), t.differ.near);
    return t;
}

// Road levels of detail (TileMesh, kRoadLodTolerance): blocks far from the camera draw their roads
// simplified, within half a pixel on screen. Far fewer pieces; the picture differs only in a few
// edge pixels of distant roads, and the near part of the frame not at all.
TEST(AndorraMap, DistantRoadsAreDrawnSimplifiedWithinHalfAPixel) {
    for (ViewMode mode : {ViewMode::Bird, ViewMode::Snail}) {
        const Toggled t = toggled(mode, &MapLayers::road_lod);
        const char* name = mode == ViewMode::Bird ? "bird" : "snail";
        EXPECT_LT(t.on.stats.road_segments, t.off.stats.road_segments * 9 / 10) << name;
        EXPECT_LT(t.differ.all, std::size_t(1280 * 480 / 200)) << name << ": at most 0.5 % of the pixels";
        if (mode == ViewMode::Snail) {
            EXPECT_EQ(t.differ.near, 0u) << "the roads next to the car are drawn as draped";
        }
    }
}

// seed 7.3: minor classes leave distant views (RoadClassStyle::select_px). Fewer pieces reach the
// vertex stage; next to the car (the bottom quarter of the snail's view) nothing is left out.
TEST(AndorraMap, MinorRoadsLeaveDistantViews) {
    for (ViewMode mode : {ViewMode::Bird, ViewMode::Snail}) {
        const Toggled t = toggled(mode, &MapLayers::road_selection);
        const char* name = mode == ViewMode::Bird ? "bird" : "snail";
        EXPECT_LT(t.on.stats.road_segments, t.off.stats.road_segments * 9 / 10) << name;
        EXPECT_GT(t.differ.all, 0u) << name << ": nothing left out";
        if (mode == ViewMode::Snail) {
            EXPECT_EQ(t.differ.near, 0u) << "the roads next to the car are all drawn";
        }
    }
}

// Three display targets of different sizes on one renderer (one depth/stencil buffer sized to
// the largest, tiles shared) draw what renderers of their own draw; tiles that any target drew in
// its latest frame are not evicted even with a cache cap far below their number, so taking turns
// re-uploads nothing.
TEST(AndorraMap, TargetsOfDifferentSizesMatchRenderersOfTheirOwnAndKeepTheirTiles) {
    struct View {
        ViewMode mode;
        int w, h;
    };
    const View views[] = {{ViewMode::Snail, 640, 240}, {ViewMode::Snail, 400, 120}, {ViewMode::Bird, 640, 360}};
    RendererOptions o;
    o.width = views[0].w;
    o.height = views[0].h;
    o.tile_resource_cache = 1;
    auto shared = Renderer::create(o);
    const navmap::render::TargetHandle ids[3] = {shared->primaryTarget(), shared->addTarget(views[1].w, views[1].h),
                                                 shared->addTarget(views[2].w, views[2].h)};
    for (int round = 0; round < 2; ++round) {
        for (int k = 0; k < 3; ++k) {
            MapFrame frame = navmap::test::settledAndorraFrame(views[k].mode, views[k].w, views[k].h);
            frame.layers = layersFor(3);
            shared->renderMap(ids[k], frame);
            EXPECT_GT(shared->mapStats().tiles_drawn, 3u);
            if (round == 1) {
                EXPECT_EQ(shared->mapStats().tiles_uploaded, 0u) << "target " << k << " re-uploaded tiles";
            }
            const Image image = shared->readSync(ids[k]);
            if (round == 1) {
                RendererOptions alone_options = o;
                alone_options.width = views[k].w;
                alone_options.height = views[k].h;
                auto alone = Renderer::create(alone_options);
                alone->renderMap(frame);
                // Pixel for pixel, but for the route: a tile keeps the route draped at the finest
                // tolerance a view has needed of it (half a pixel, docs/rendering.md "Route:
                // bounded by what is drawn"), so a target that shares its tiles with a nearer view
                // may draw a route simplified less than a renderer of its own would.
                const navmap::test::GoldenComparison cmp = navmap::test::compareImages(alone->readSync(), image, 0);
                ASSERT_TRUE(cmp.sizes_match) << "target " << k;
                std::printf("target %d: %zu pixels differ (%.4f%%), largest channel difference %d\n", k,
                            cmp.differing_pixels, cmp.differing_fraction * 100.0, cmp.max_channel_difference);
                EXPECT_LE(cmp.differing_fraction, 0.0005) << "target " << k;
            }
        }
    }
}

// A lost GL context is made anew (docs/gles-profile.md "Lost contexts"): the renderer's test hook
// drops the context at the start of the second frame, as a GPU reset would lose it. That frame
// renders on a new context, every target keeps its handle and size, tiles and programs are made
// again, and the pixels are the golden's.
TEST(AndorraMap, ALostContextIsMadeAnewAndTheMapRendersAgain) {
    ::setenv("NAVMAP_TEST_LOSE_CONTEXT_AFTER_FRAMES", "1", 1);
    auto renderer = rendererOfSize(kW, kH);
    ::unsetenv("NAVMAP_TEST_LOSE_CONTEXT_AFTER_FRAMES");
    const TargetHandle second = renderer->addTarget(320, 120);
    std::printf("[ info     ] robust context: %s\n", renderer->device().robust_context ? "yes" : "no");
    MapFrame frame = navmap::test::settledAndorraFrame(ViewMode::Bird, kW, kH);
    frame.layers = layersFor(3);
    renderer->renderMap(frame);
    EXPECT_GOLDEN(renderer->readSync(), "render/cases/andorra_bird_full/expected.png",
                  (navmap::test::GoldenTolerance{10, 0.01}));
    EXPECT_EQ(renderer->device().context_resets, 0);

    renderer->renderMap(frame);  // the hook drops the context first
    EXPECT_EQ(renderer->device().context_resets, 1);
    EXPECT_GT(renderer->mapStats().tiles_uploaded, 3u) << "the tiles were uploaded again";
    EXPECT_GOLDEN(renderer->readSync(), "render/cases/andorra_bird_full/expected.png",
                  (navmap::test::GoldenTolerance{10, 0.01}));
    EXPECT_EQ(renderer->width(second), 320);
    EXPECT_EQ(renderer->height(second), 120);
    MapFrame small = navmap::test::settledAndorraFrame(ViewMode::Bird, 320, 120);
    small.layers = layersFor(3);
    renderer->renderMap(second, small);
    EXPECT_GT(renderer->mapStats().tiles_drawn, 3u);
    auto alone = rendererOfSize(320, 120);
    alone->renderMap(small);
    EXPECT_EQ(renderer->readSync(second).rgba, alone->readSync().rgba) << "the second target after the new context";
    EXPECT_EQ(renderer->device().context_resets, 1) << "once: the hook fires once";
}

// The terrain is drawn in blocks (TileMesh::terrain_blocks); those outside the view frustum are
// skipped (the render cases andorra_{bird,snail}_* show that nothing visible goes missing).
TEST(AndorraMap, TerrainBlocksOutsideTheViewAreNotDrawn) {
    for (ViewMode mode : {ViewMode::Bird, ViewMode::Snail}) {
        MapFrameStats stats;
        renderView(mode, layersFor(0), &stats);
        const MapFrame frame = navmap::test::settledAndorraFrame(mode, kW, kH);
        std::size_t all = 0;
        for (const auto& t : frame.tiles) all += buildTileMesh(*t).terrain_indices.size() / 3;
        std::printf("[ measure  ] %s: %zu of %zu terrain triangles drawn\n", mode == ViewMode::Bird ? "bird" : "snail",
                    stats.terrain_triangles, all);
        EXPECT_GT(stats.terrain_triangles, all / 10);
        EXPECT_LT(stats.terrain_triangles, all * 3 / 4);
    }
}

}  // namespace
