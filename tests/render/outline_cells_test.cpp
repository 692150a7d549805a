// SPDX-License-Identifier: Apache-2.0
// Unit tests of the screen cells where the outline filter runs (seed 3.6.3 outlines, OutlineCells):
// every pixel that can read a road pixel in its 3x3 neighbourhood lies in a marked cell, also for
// quads that reach behind the camera, and the rectangles cover exactly the marked cells.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <stdexcept>
#include <utility>
#include <vector>

#include <glm/gtc/matrix_transform.hpp>

#include "navmap/render/road_style.h"
#include "outline_cells.h"

namespace {

using namespace navmap::render;

constexpr int kW = 320, kH = 120, kCell = 8;
constexpr float kReach = 2.0f;

struct Camera {
    glm::mat4 view, projection;
};

// A low camera looking along +y over flat ground, like the snail's view.
Camera lowCamera() {
    return {glm::lookAt(glm::vec3(0.0f, -40.0f, 12.0f), glm::vec3(0.0f, 60.0f, 0.0f), glm::vec3(0.0f, 0.0f, 1.0f)),
            glm::perspective(glm::radians(45.0f), float(kW) / kH, 1.0f, 5000.0f)};
}

const QuadShape kShape{10.0f, 300.0f, 4.0f, 0.02f};

// The pixel an in-front point projects to, or false.
bool pixelOf(const Camera& c, glm::vec3 p, float alpha, glm::ivec2& out) {
    glm::vec4 v = c.view * glm::vec4(p, 1.0f);
    v = glm::vec4(glm::vec3(v) * (1.0f - alpha), 1.0f);
    const glm::vec4 clip = c.projection * v;
    if (clip.z < -clip.w) return false;  // behind the near plane
    const float x = (clip.x / clip.w * 0.5f + 0.5f) * kW, y = (clip.y / clip.w * 0.5f + 0.5f) * kH;
    if (x < 0.0f || y < 0.0f || x >= kW || y >= kH) return false;
    out = {int(std::floor(x)), int(std::floor(y))};
    return true;
}

// Samples the quad roads_geo.vert draws for p0-p1 densely on the ground and checks that each
// sample's pixel and its 8 neighbours (the pixels whose 3x3 filter reads it) are marked.
int checkQuadCovered(const OutlineCells& cells, const Camera& c, glm::vec3 p0, glm::vec3 p1, const QuadShape& s) {
    const glm::vec3 mid = 0.5f * (p0 + p1);
    const float dist = glm::length(glm::vec3(c.view * glm::vec4(mid, 1.0f)));
    const float w = s.width_m * distanceWidthScale(dist, s.scale_threshold_m, s.max_scale);
    const glm::vec2 d = glm::vec2(p1 - p0);
    const glm::vec2 t = glm::length(d) > 1e-6f ? glm::normalize(d) : glm::vec2(1.0f, 0.0f), n(-t.y, t.x);
    int samples = 0;
    for (int i = 0; i <= 200; ++i) {
        for (int j = 0; j <= 20; ++j) {
            const float a = i / 200.0f, b = j / 20.0f * 2.0f - 1.0f;
            // Along from p0 - t w/2 to p1 + t w/2, across from -w/2 to w/2.
            glm::vec3 p = glm::mix(p0, p1, a);
            p += glm::vec3((glm::mix(-0.5f, 0.5f, a) * w) * t + (0.5f * w * b) * n, 0.0f);
            glm::ivec2 px;
            if (!pixelOf(c, p, s.z_offset_alpha, px)) continue;
            ++samples;
            for (int dy = -1; dy <= 1; ++dy) {
                for (int dx = -1; dx <= 1; ++dx) {
                    const int x = px.x + dx, y = px.y + dy;
                    if (x < 0 || y < 0 || x >= kW || y >= kH) continue;
                    EXPECT_TRUE(cells.covers(x, y)) << "pixel " << x << "," << y << " next to the quad of (" << p0.x
                                                    << "," << p0.y << ")-(" << p1.x << "," << p1.y << ")";
                    if (!cells.covers(x, y)) return samples;
                }
            }
        }
    }
    return samples;
}

std::size_t coveredPixels(const OutlineCells& cells) {
    std::size_t n = 0;
    for (int y = 0; y < kH; ++y)
        for (int x = 0; x < kW; ++x) n += cells.covers(x, y);
    return n;
}

TEST(OutlineCells, EveryPixelTheFilterCanDarkenIsMarked) {
    const Camera c = lowCamera();
    std::mt19937 rng(11);
    std::uniform_real_distribution<float> x(-300.0f, 300.0f), y(-30.0f, 900.0f), len(0.5f, 80.0f), angle(0.0f, 6.2832f),
        z(-2.0f, 2.0f);
    int samples = 0;
    for (int i = 0; i < 300; ++i) {
        OutlineCells cells;
        cells.reset(kW, kH, kCell, kReach);
        cells.setView(c.view, c.projection);
        const glm::vec3 p0(x(rng), y(rng), z(rng));
        const float a = angle(rng), l = len(rng);
        const glm::vec3 p1 = p0 + glm::vec3(l * std::cos(a), l * std::sin(a), z(rng));
        cells.markQuad(p0, p1, kShape);
        samples += checkQuadCovered(cells, c, p0, p1, kShape);
        if (HasFailure()) return;
    }
    EXPECT_GT(samples, 100000) << "the pieces were seen";
}

TEST(OutlineCells, QuadsReachingBehindTheCameraAreClippedAtTheNearPlane) {
    const Camera c = lowCamera();
    // Under the camera and behind it, out to the front: the visible part reaches the bottom edge.
    const glm::vec3 p0(0.0f, -80.0f, 0.0f), p1(5.0f, 200.0f, 0.0f);
    OutlineCells cells;
    cells.reset(kW, kH, kCell, kReach);
    cells.setView(c.view, c.projection);
    cells.markQuad(p0, p1, kShape);
    EXPECT_GT(checkQuadCovered(cells, c, p0, p1, kShape), 1000);
    EXPECT_TRUE(cells.covers(kW / 2, 0)) << "the road runs off the bottom of the screen";
    // A road entirely behind the camera marks nothing.
    OutlineCells behind;
    behind.reset(kW, kH, kCell, kReach);
    behind.setView(c.view, c.projection);
    behind.markQuad({-20.0f, -200.0f, 0.0f}, {20.0f, -120.0f, 0.0f}, kShape);
    EXPECT_EQ(coveredPixels(behind), 0u);
}

TEST(OutlineCells, MarksLittleMoreThanTheRoad) {
    const Camera c = lowCamera();
    OutlineCells cells;
    cells.reset(kW, kH, kCell, kReach);
    cells.setView(c.view, c.projection);
    // A far road across the view: a thin band on screen, marked a few cells high at most.
    cells.markQuad({-400.0f, 800.0f, 0.0f}, {400.0f, 800.0f, 0.0f}, kShape);
    int rows = 0;
    for (int y = 0; y < kH; y += kCell) rows += cells.covers(kW / 2, y);
    EXPECT_GE(rows, 1);
    EXPECT_LE(rows, 2);
    EXPECT_LT(coveredPixels(cells), std::size_t(kW * kH / 10));
}

// roads_geo.vert moves the upper side of a quad whose fill is narrower on screen than
// QuadShape::min_width_px up by as much as min_width_px * width / fill width: the cells reach
// that far above such a quad, and no further around quads that are wide enough.
TEST(OutlineCells, WidenedFarRoadsAreMarkedUpToTheirLeastWidth) {
    const Camera c = lowCamera();
    QuadShape widened = kShape;
    widened.min_width_px = 12.0f;  // more than a cell, so that too short a reach shows
    widened.fill_width_m = 8.0f;   // 10 m with the casing: the casing grows by 10 / 8
    const float most = widened.min_width_px * widened.width_m / widened.fill_width_m;
    // A far road across the view, a few pixels high on screen: every pixel up to `most` above
    // its centre line, and the filter's pixel beyond, is marked.
    const glm::vec3 p0(-150.0f, 700.0f, 0.0f), p1(150.0f, 700.0f, 0.0f);
    OutlineCells cells;
    cells.reset(kW, kH, kCell, kReach);
    cells.setView(c.view, c.projection);
    cells.markQuad(p0, p1, widened);
    int checked = 0;
    for (float a = 0.0f; a <= 1.0f; a += 0.01f) {
        glm::ivec2 px;
        if (!pixelOf(c, glm::mix(p0, p1, a), widened.z_offset_alpha, px)) continue;
        for (int up = 0; up <= static_cast<int>(std::ceil(most)) + 1 && px.y + up < kH; ++up) {
            ++checked;
            EXPECT_TRUE(cells.covers(px.x, px.y + up))
                << "pixel " << px.x << "," << px.y + up << ": " << up << " px above the road";
        }
    }
    EXPECT_GT(checked, 500);
    // A near road, its fill 20-odd pixels wide on screen, is not widened: the least width adds
    // nothing to its cells.
    OutlineCells near_plain, near_widened;
    for (const auto& [cells_of, shape] :
         {std::pair<OutlineCells*, const QuadShape*>{&near_plain, &kShape}, {&near_widened, &widened}}) {
        cells_of->reset(kW, kH, kCell, kReach);
        cells_of->setView(c.view, c.projection);
        cells_of->markQuad({-10.0f, -22.0f, 0.0f}, {10.0f, -18.0f, 0.0f}, *shape);
    }
    EXPECT_GT(coveredPixels(near_plain), 0u);
    EXPECT_EQ(coveredPixels(near_widened), coveredPixels(near_plain));
}

TEST(OutlineCells, RectanglesCoverExactlyTheMarkedCells) {
    const Camera c = lowCamera();
    OutlineCells cells;
    cells.reset(kW, kH, kCell, kReach);
    cells.setView(c.view, c.projection);
    std::mt19937 rng(5);
    std::uniform_real_distribution<float> x(-200.0f, 200.0f), y(0.0f, 600.0f);
    for (int i = 0; i < 40; ++i) cells.markQuad({x(rng), y(rng), 0.0f}, {x(rng), y(rng), 0.0f}, kShape);
    std::vector<int> hits(kW * kH, 0);
    for (const CellRect& r : cells.rects()) {
        ASSERT_LT(r.x0, r.x1);
        ASSERT_LT(r.y0, r.y1);
        ASSERT_GE(r.x0, 0);
        ASSERT_GE(r.y0, 0);
        ASSERT_LE(r.x1, kW);
        ASSERT_LE(r.y1, kH);
        for (int py = r.y0; py < r.y1; ++py)
            for (int px = r.x0; px < r.x1; ++px) ++hits[py * kW + px];
    }
    std::size_t marked = 0;
    for (int py = 0; py < kH; ++py) {
        for (int px = 0; px < kW; ++px) {
            ASSERT_EQ(hits[py * kW + px], cells.covers(px, py) ? 1 : 0) << px << "," << py;
            marked += cells.covers(px, py);
        }
    }
    EXPECT_GT(marked, 0u);
    // In groups of four cells along a row: each cell of a group with a marked cell, no other.
    const int group = 4 * kCell;
    std::fill(hits.begin(), hits.end(), 0);
    for (const CellRect& r : cells.rects(4)) {
        ASSERT_EQ(r.x0 % group, 0);
        ASSERT_TRUE(r.x1 % group == 0 || r.x1 == kW) << r.x1;
        ASSERT_LE(r.x1, kW);
        for (int py = r.y0; py < r.y1; ++py)
            for (int px = r.x0; px < r.x1; ++px) ++hits[py * kW + px];
    }
    for (int py = 0; py < kH; ++py) {
        for (int gx = 0; gx < kW; gx += group) {
            bool any = false;
            for (int px = gx; px < std::min(gx + group, kW); px += kCell) any = any || cells.covers(px, py);
            for (int px = gx; px < std::min(gx + group, kW); ++px)
                ASSERT_EQ(hits[py * kW + px], any ? 1 : 0) << px << "," << py;
        }
    }
    // A straight vertical road on screen is one rectangle, not one per row of cells.
    OutlineCells column;
    column.reset(kW, kH, kCell, kReach);
    column.setView(glm::mat4(1.0f), glm::ortho(0.0f, float(kW), 0.0f, float(kH), -1.0f, 1.0f));
    column.markQuad({100.0f, 20.0f, 0.0f}, {100.0f, 100.0f, 0.0f}, {4.0f, 1e9f, 1.0f, 0.0f});
    const auto rects = column.rects();
    ASSERT_EQ(rects.size(), 1u);
    EXPECT_EQ(rects[0].x0, 96);   // 100 - 2 (half width) - 2 (reach) = 96, a cell edge
    EXPECT_EQ(rects[0].x1, 112);  // 100 + 2 + 2 = 104 touches the cell from 104 to 112
    EXPECT_EQ(rects[0].y0, 16);   // 20 - 2 (cap) - 2
    EXPECT_EQ(rects[0].y1, 112);  // 100 + 2 + 2
}

TEST(OutlineCells, BrokenInputMarksNothing) {
    const Camera c = lowCamera();
    OutlineCells cells;
    cells.reset(kW, kH, kCell, kReach);
    cells.setView(c.view, c.projection);
    const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
    cells.markQuad({nan, 10.0f, 0.0f}, {0.0f, 50.0f, 0.0f}, kShape);
    cells.markQuad({0.0f, inf, 0.0f}, {0.0f, 50.0f, 0.0f}, kShape);
    EXPECT_EQ(coveredPixels(cells), 0u);
    OutlineCells empty;
    empty.reset(0, 0, kCell, kReach);
    empty.setView(c.view, c.projection);
    empty.markQuad({0.0f, 10.0f, 0.0f}, {0.0f, 50.0f, 0.0f}, kShape);
    EXPECT_TRUE(empty.rects().empty());
}

// outlineEdges against seed 3.6.3's filter on a binary mask, pixel by pixel: an edge pixel is not a
// road pixel and has one in its 3x3 neighbourhood (clamped at the borders, as the shader's fetches
// are). Widths that are and are not multiples of 8 and 64, down to one pixel; bytes of every value,
// a byte above 127 counting as road. markEdges then marks exactly the cells that hold an edge pixel.
TEST(OutlineEdges, AreTheNonRoadPixelsNextToARoadPixel) {
    std::mt19937 rng(11);
    for (const auto& size : {std::pair{1, 1}, std::pair{1, 9}, std::pair{13, 5}, std::pair{64, 40}, std::pair{131, 17},
                             std::pair{800, 24}}) {
        const int w = size.first, h = size.second;
        // Sparse road pixels in the lower left quarter only, so that many cells hold no edge.
        std::vector<std::uint8_t> mask(static_cast<std::size_t>(w * h), 0);
        for (int y = 0; y < (h + 1) / 2; ++y)
            for (int x = 0; x < (w + 1) / 2; ++x)
                mask[static_cast<std::size_t>(y * w + x)] = rng() % 5 == 0 ? static_cast<std::uint8_t>(rng()) : 0;
        if (w == 1 && h == 1) mask[0] = 0;  // a lone pixel without roads: no edge
        const auto road = [&](int x, int y) {
            return mask[static_cast<std::size_t>(std::clamp(y, 0, h - 1) * w + std::clamp(x, 0, w - 1))] > 127;
        };
        const int groups = packedMaskWidth(w);
        ASSERT_EQ(groups, (w + 7) / 8);
        std::vector<std::uint16_t> edges(static_cast<std::size_t>(groups * h), 0xFFFF);
        outlineEdges(mask.data(), w, h, edges.data());
        const auto edge = [&](int x, int y) {
            return (edges[static_cast<std::size_t>(y * groups + x / 8)] >> (x % 8)) & 1u;
        };
        int wrong = 0, edge_pixels = 0;
        for (int y = 0; y < h; ++y) {
            for (int g = 0; g < groups; ++g) {
                // Bits beyond the row's end and above bit 7 stay clear.
                EXPECT_EQ(edges[static_cast<std::size_t>(y * groups + g)] >> std::min(8, w - 8 * g), 0u)
                    << w << "x" << h;
            }
            for (int x = 0; x < w; ++x) {
                bool near = false;
                for (int dy = -1; dy <= 1; ++dy)
                    for (int dx = -1; dx <= 1; ++dx) near = near || road(x + dx, y + dy);
                const bool expected = near && !road(x, y);
                wrong += expected != (edge(x, y) != 0);
                edge_pixels += expected;
            }
        }
        EXPECT_EQ(wrong, 0) << w << "x" << h;
        if (w * h >= 64) {
            EXPECT_GT(edge_pixels, w * h / 16) << "the test mask has edges";
        }

        OutlineCells cells;
        cells.reset(w, h, kCell, 0.0f);
        cells.markEdges(edges.data(), groups);
        int marked = 0, cells_total = 0;
        for (int cy = 0; cy < (h + kCell - 1) / kCell; ++cy) {
            for (int cx = 0; cx < (w + kCell - 1) / kCell; ++cx) {
                bool holds_edge = false;
                for (int y = cy * kCell; y < std::min(h, (cy + 1) * kCell); ++y)
                    for (int x = cx * kCell; x < std::min(w, (cx + 1) * kCell); ++x)
                        holds_edge = holds_edge || edge(x, y);
                EXPECT_EQ(cells.covers(cx * kCell, cy * kCell), holds_edge) << "cell " << cx << "," << cy;
                marked += holds_edge;
                ++cells_total;
            }
        }
        if (w >= 64) {
            EXPECT_LT(marked, cells_total) << "cells without edges stay unmarked";
        }
    }
}

// A texel of the edge mask is one row of one cell: other cell sizes are refused, not misread.
TEST(OutlineEdges, MarkEdgesRefusesCellsOfAnotherSize) {
    const std::vector<std::uint16_t> edges(static_cast<std::size_t>(packedMaskWidth(64) * 16), 1);
    OutlineCells cells;
    cells.reset(64, 16, 4, 0.0f);
    EXPECT_THROW(cells.markEdges(edges.data(), packedMaskWidth(64)), std::logic_error);
    cells.reset(64, 16, kPackedMaskPixels, 0.0f);
    cells.markEdges(edges.data(), packedMaskWidth(64));
    EXPECT_TRUE(cells.covers(0, 0));
    EXPECT_TRUE(cells.covers(63, 15));
}

}  // namespace
