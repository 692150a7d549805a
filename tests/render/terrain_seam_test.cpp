// SPDX-License-Identifier: Apache-2.0
// Relief shading is continuous across tile borders: looking straight down on the steepest
// Andorra slope that a leaf tile border crosses, the shading steps across the border no more than
// it does between neighbouring columns inside the tiles (docs/rendering.md "Terrain normals").
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <vector>

#include "andorra_drive.h"
#include "drive_scene.h"
#include "navmap/render/image.h"
#include "navmap/render/renderer.h"
#include "test_paths.h"

namespace {

using namespace navmap::render;
using navmap::map::TileId;

constexpr int kW = 480, kH = 270;

bool haveStore() { return std::filesystem::exists(navmap::test::binaryDir() / "andorra.navmap"); }

// A north-south border between two leaf tiles (x = x_m, y from y0_m to y1_m), with how steep the
// terrain is across it and how far the two tiles' one-sided slopes at the border disagree.
struct Border {
    double x_m = 0, y0_m = 0, y1_m = 0;
    double slope = 0;     ///< mean |dz/dx| across the border (central difference)
    double mismatch = 0;  ///< mean |west tile's backward - east tile's forward dz/dx| at the border
    float top_m = 0;      ///< highest sample along it
};

// Of the leaf tiles within `reach` tiles of `at`, the border on a steep slope (mean slope over
// 0.35) where the tiles' own one-sided differences disagree most: where per-tile normals showed
// their seam. Only the middle half of each border (away from the corners).
Border steepestSeam(const navmap::map::TileSource& source, navmap::map::PlanarPoint at, int reach) {
    const navmap::map::TileScheme& scheme = source.scheme();
    const int leaf = scheme.leafLevel();
    const auto centre = scheme.tileAt(leaf, at);
    Border best;
    if (!centre) return best;
    for (int dy = -reach; dy <= reach; ++dy) {
        for (int dx = -reach; dx < reach; ++dx) {
            const auto x = static_cast<std::uint32_t>(static_cast<int>(centre->x) + dx);
            const auto y = static_cast<std::uint32_t>(static_cast<int>(centre->y) + dy);
            const TileId w{static_cast<std::uint8_t>(leaf), x, y};
            const TileId e{static_cast<std::uint8_t>(leaf), x + 1, y};
            if (!source.contains(w) || !source.contains(e)) continue;
            const auto a = source.load(w).tile, b = source.load(e).tile;
            if (!a || !b || a->dem.size < 8 || a->dem.size != b->dem.size) continue;
            if (std::abs(a->origin_x + a->size_m - b->origin_x) > 0.01) continue;  // not west/east
            const int n = a->dem.size;
            const double s = a->size_m / (n - 1);
            Border c;
            c.x_m = b->origin_x;
            c.y0_m = a->origin_y;
            c.y1_m = a->origin_y + a->size_m;
            int count = 0;
            for (int r = n / 4; r <= 3 * n / 4; ++r) {
                c.slope += std::abs(b->dem.at(r, 1) - a->dem.at(r, n - 2)) / (2 * s);
                c.mismatch +=
                    std::abs((a->dem.at(r, n - 1) - a->dem.at(r, n - 2)) - (b->dem.at(r, 1) - b->dem.at(r, 0))) / s;
                c.top_m = std::max(c.top_m, b->dem.at(r, 0));
                ++count;
            }
            c.slope /= count;
            c.mismatch /= count;
            if (c.slope > 0.35 && c.mismatch > best.mismatch) best = c;
        }
    }
    return best;
}

float luminance(const Image& im, int x, int y) {
    const std::size_t i = (static_cast<std::size_t>(y) * im.width + x) * 4;
    return 0.299f * im.rgba[i] + 0.587f * im.rgba[i + 1] + 0.114f * im.rgba[i + 2];
}

TEST(TerrainSeamGpu, ShadingIsContinuousAcrossATileBorderOnASteepSlope) {
    if (!haveStore())
        GTEST_SKIP() << "no compiled store in " << navmap::test::binaryDir() << " (target navmap_default_store)";
    navmap::test::DriveScene& d = navmap::test::andorraDrive();
    const navmap::map::TileSource& source = d.scene.tiles();
    const auto vella = d.scene.toPlanar(navmap::test::kAndorraLaVella.lat_deg, navmap::test::kAndorraLaVella.lon_deg);
    const Border border = steepestSeam(source, vella, 3);
    ASSERT_GT(border.slope, 0.35) << "no steep leaf tile border near Andorra la Vella";
    std::printf("[ measure  ] border x %.0f m, y %.0f..%.0f m: slope %.2f, one-sided mismatch %.3f\n", border.x_m,
                border.y0_m, border.y1_m, border.slope, border.mismatch);

    // Straight down on the border's middle, north up: the border x = x_m projects onto the line
    // between columns kW / 2 - 1 and kW / 2 at every height.
    MapFrame frame;
    const double y_mid = 0.5 * (border.y0_m + border.y1_m);
    frame.camera.eye = glm::dvec3(border.x_m, y_mid, border.top_m + 700.0);
    frame.camera.target = glm::dvec3(border.x_m, y_mid, border.top_m - 300.0);
    frame.camera.up = glm::dvec3(0.0, 1.0, 0.0);
    frame.layers.land_cover = false;
    frame.layers.roads = frame.layers.outlines = frame.layers.buildings = false;
    frame.layers.route = frame.layers.marker = frame.layers.labels = false;
    const double aspect = double(kW) / kH;
    ASSERT_TRUE(d.view->warmUp(frame.camera, aspect, kH, std::chrono::seconds(20)));
    d.view->select(frame, aspect, kH);
    // Both sides of the border are drawn from leaf tiles (the border is one at the drawn level).
    const int leaf = source.scheme().leafLevel();
    for (const double side : {-10.0, 10.0}) {
        const auto id = source.scheme().tileAt(leaf, {border.x_m + side, y_mid});
        ASSERT_TRUE(id);
        EXPECT_TRUE(std::any_of(frame.tiles.begin(), frame.tiles.end(), [&](const auto& t) { return t->id == *id; }))
            << "leaf tile " << int(id->level) << "/" << id->x << "/" << id->y << " not drawn";
    }

    RendererOptions o;
    o.width = kW;
    o.height = kH;
    auto renderer = Renderer::create(o);
    renderer->renderMap(frame);
    const Image image = renderer->readSync();
    if (const char* dir = std::getenv("NAVMAP_SEAM_PNG")) {
        std::string error;
        EXPECT_TRUE(writePng(std::filesystem::path(dir) / "terrain_seam.png", image, &error)) << error;
    }

    // Per column boundary c (between columns c - 1 and c): the mean |luminance step| over the
    // middle rows. The border's boundary is kW / 2; the others, 4 to 80 columns to either side,
    // lie inside the two tiles (the next north-south borders are a tile, over 700 columns, away).
    auto step = [&](int c) {
        double sum = 0.0;
        int rows = 0;
        for (int y = kH / 8; y < kH - kH / 8; ++y, ++rows)
            sum += std::abs(luminance(image, c, y) - luminance(image, c - 1, y));
        return sum / rows;
    };
    const double at_border = step(kW / 2);
    std::vector<double> inside;
    for (int off = 4; off <= 80; ++off) {
        inside.push_back(step(kW / 2 - off));
        inside.push_back(step(kW / 2 + off));
    }
    std::sort(inside.begin(), inside.end());
    const double typical = inside[inside.size() / 2];
    const double most = inside.back();
    std::printf("[ measure  ] luminance step across the border %.2f; inside the tiles: median %.2f, max %.2f\n",
                at_border, typical, most);
    // Gouraud shading is continuous inside a tile, so a column's step there is the shading's
    // gradient plus rounding to 8 bits. Continuous normals make the border one more such column:
    // within the largest step of the 154 columns inside the tiles. Per-tile one-sided normals
    // put a jump on it (several times the median).
    EXPECT_LE(at_border, std::max(most, 1.5 * typical));
}

}  // namespace
