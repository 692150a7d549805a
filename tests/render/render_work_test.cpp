// SPDX-License-Identifier: Apache-2.0
// The renderer's GL work (MapFrameStats::*_work: draw calls, vertices, bytes uploaded, counted
// on every frame) grows with the scene, not faster: twice the roads on a tile cost the road pass
// at most 2.3 times the vertices and the frame at most 2.3 times the draw calls and uploads.
// Counted, not timed: the same on every machine and driver.
#include <gtest/gtest.h>

#include <cstdint>
#include <cstdio>
#include <memory>
#include <random>
#include <vector>

#include "navmap/render/renderer.h"
#include "synthetic_tile.h"

namespace {

using namespace navmap::render;
namespace map = navmap::map;

struct Work {
    PassWork first;  ///< the frame that uploads the tile
    PassWork next;   ///< the frame after it
    PassWork roads;  ///< the road pass of the frame after it
    PassWork uploads;
};

// A frame of `tile` alone, uploaded at once, seen from `eye` towards `target` (tile-local metres).
MapFrame tileFrame(const std::shared_ptr<map::Tile>& tile, glm::dvec3 eye, glm::dvec3 target, glm::dvec3 up) {
    const glm::dvec3 origin(tile->origin_x, tile->origin_y, 0.0);
    MapFrame frame;
    frame.camera.eye = origin + eye;
    frame.camera.target = origin + target;
    frame.camera.up = up;
    frame.camera.near_m = 10.0;
    frame.camera.far_m = 5000.0;
    frame.tiles = {tile};
    frame.upload_all = true;
    return frame;
}

// `n` straight residential roads at random places on a flat 1 km tile, seen from above.
Work renderRoads(int n) {
    auto tile = navmap::test::makeTile([](float, float) { return 500.0F; });
    std::mt19937 rng(17);
    std::uniform_real_distribution<float> pos(50.0F, 950.0F);
    for (int i = 0; i < n; ++i) {
        const map::LocalPoint a{pos(rng), pos(rng)};
        const map::LocalPoint b{a.x + 40.0F, a.y + 25.0F};
        const map::LocalPoint c{b.x + 30.0F, b.y - 20.0F};
        tile->roads.push_back(navmap::test::road(map::RoadClass::Residential, {a, b, c}));
    }
    RendererOptions o;
    o.width = 320;
    o.height = 240;
    auto renderer = Renderer::create(o);
    const MapFrame frame =
        tileFrame(tile, glm::dvec3(500.0, 500.0, 1800.0), glm::dvec3(500.0, 500.0, 500.0), glm::dvec3(0.0, 1.0, 0.0));
    Work w;
    renderer->renderMap(frame);
    w.first = renderer->mapStats().frame_work;
    w.uploads = renderer->mapStats().uploads_work;
    renderer->renderMap(frame);
    w.next = renderer->mapStats().frame_work;
    w.roads = renderer->mapStats().roads_work;
    return w;
}

double ratio(std::uint64_t a, std::uint64_t b) { return static_cast<double>(b) / static_cast<double>(a); }

}  // namespace

TEST(RenderWork, TwiceTheRoadsCostAtMostTwiceTheWork) {
    const Work small = renderRoads(150);
    const Work large = renderRoads(300);
    std::printf(
        "roads pass: %llu -> %llu vertices in %llu -> %llu draw calls; frame: %llu -> %llu draw calls; "
        "first frame uploads %llu -> %llu bytes\n",
        static_cast<unsigned long long>(small.roads.vertices), static_cast<unsigned long long>(large.roads.vertices),
        static_cast<unsigned long long>(small.roads.draw_calls),
        static_cast<unsigned long long>(large.roads.draw_calls), static_cast<unsigned long long>(small.next.draw_calls),
        static_cast<unsigned long long>(large.next.draw_calls),
        static_cast<unsigned long long>(small.first.bytes_uploaded),
        static_cast<unsigned long long>(large.first.bytes_uploaded));
    // The counts are real: the roads are drawn, the tile is uploaded once.
    ASSERT_GT(small.roads.draw_calls, 0U);
    ASSERT_GT(small.roads.vertices, 0U);
    ASSERT_GT(small.uploads.bytes_uploaded, 0U);
    EXPECT_GT(large.roads.vertices, small.roads.vertices) << "more roads, more road vertices";
    EXPECT_LT(small.next.bytes_uploaded, small.first.bytes_uploaded) << "the tile is not uploaded again";
    EXPECT_LE(ratio(small.roads.vertices, large.roads.vertices), 2.3);
    EXPECT_LE(ratio(small.next.draw_calls, large.next.draw_calls), 2.3);
    EXPECT_LE(ratio(small.first.bytes_uploaded, large.first.bytes_uploaded), 2.3);
    EXPECT_LE(ratio(small.first.vertices, large.first.vertices), 2.3);
}

// RendererOptions::warm_up rasterizes a throwaway land-cover triangle at creation (the daemon's
// start-up pays the driver's first code there): it must leave nothing behind that changes a frame.
// A tile with water and forest areas, drawn by a renderer with and one without the warm-up.
TEST(RenderWarmUp, DrawsTheSameFramesAsWithout) {
    auto tile = navmap::test::makeTile([](float x, float y) { return 400.0F + 0.05F * x + 0.02F * y; });
    map::Area water, forest;
    water.cls = map::AreaClass::Water;
    forest.cls = map::AreaClass::Forest;
    water.polygon.vertices = {{100, 100}, {600, 150}, {350, 700}};
    forest.polygon.vertices = {{500, 500}, {950, 520}, {900, 950}, {480, 900}};
    water.polygon.ring_ends = {3};
    water.polygon.indices = {0, 1, 2};
    forest.polygon.ring_ends = {4};
    forest.polygon.indices = {0, 1, 2, 0, 2, 3};
    tile->areas = {water, forest};
    tile->roads.push_back(navmap::test::road(map::RoadClass::Primary, {{50.0F, 500.0F}, {950.0F, 560.0F}}));
    const MapFrame frame =
        tileFrame(tile, glm::dvec3(500.0, -300.0, 1200.0), glm::dvec3(500.0, 500.0, 400.0), glm::dvec3(0.0, 0.0, 1.0));
    std::vector<Image> images[2];
    for (bool warm : {false, true}) {
        RendererOptions o;
        o.width = 320;
        o.height = 240;
        o.warm_up = warm;
        auto renderer = Renderer::create(o);
        for (int i = 0; i < 2; ++i) {
            renderer->renderMap(frame);
            images[warm].push_back(renderer->readSync());
        }
    }
    for (std::size_t i = 0; i < 2; ++i) {
        ASSERT_EQ(images[0][i].rgba.size(), images[1][i].rgba.size());
        std::size_t differing = 0;
        for (std::size_t b = 0; b < images[0][i].rgba.size(); ++b)
            differing += images[0][i].rgba[b] != images[1][i].rgba[b];
        EXPECT_EQ(differing, 0U) << "frame " << i;
    }
    // The areas are drawn: water blue dominates somewhere, so the raster path ran in both.
    std::size_t blue = 0;
    const Image& im = images[1][0];
    for (std::size_t p = 0; p + 3 < im.rgba.size(); p += 4) blue += im.rgba[p + 2] > im.rgba[p] + 40;
    EXPECT_GT(blue, 500U);
}
