// SPDX-License-Identifier: Apache-2.0
// The orthoimage as the terrain's ground (seed ch. 6, MapStyle::ground): a terrain point in the
// orthoimage's colour with `ground = orthoimage` and in the land cover's with `landcover`, relief
// shading and the night's darkening applied alike, roads on top; an image not ready yet keeps
// the land cover; unusable weights leave the land cover and say so once.

#include <gtest/gtest.h>

#include <sys/stat.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <memory>
#include <string>
#include <thread>

#include "navmap/map/ortho/ortho_network.h"
#include "navmap/map/ortho/tile_sampler.h"
#include "navmap/render/renderer.h"
#include "ortho_test_tile.h"
#include "synthetic_tile.h"
#include "test_paths.h"

namespace {

using namespace navmap;
using namespace navmap::render;
namespace mo = navmap::map::ortho;

constexpr int kW = 320, kH = 240;

std::filesystem::path shippedWeights() { return test::sourceDir() / "data" / "ortho" / "ortho-mlp.nnw"; }

// A flat 1 km tile at 500 m, all water in the OSM land cover (opaque, so the land-cover colour is
// known) and grassland in its ortho layers, with a primary road along y = 500 m.
std::shared_ptr<map::Tile> groundTile(bool with_layers = true) {
    auto tile = test::makeTile([](float, float) { return 500.0f; });
    map::Area water;
    water.cls = map::AreaClass::Water;
    water.polygon.vertices = {{0, 0}, {1000, 0}, {1000, 1000}, {0, 1000}};
    water.polygon.ring_ends = {4};
    water.polygon.indices = {0, 1, 2, 0, 2, 3};
    tile->areas.push_back(water);
    tile->roads.push_back(test::road(map::RoadClass::Primary, {{100, 500}, {900, 500}}));
    if (with_layers) {
        tile->ortho = test::orthoLayers(
            1000.0, [](double, double) { return mo::SuperLandCover::Grass; }, [](double, double) { return 500.0f; });
    }
    return tile;
}

struct Shot {
    std::unique_ptr<Renderer> renderer;
    MapFrame frame;
};

Shot shot(const std::shared_ptr<map::Tile>& tile, const std::string& weights, std::size_t pixels_per_frame = 0) {
    Shot s;
    RendererOptions o;
    o.width = kW;
    o.height = kH;
    o.ortho_weights = weights;
    o.ortho_pixels_per_frame = pixels_per_frame;
    s.renderer = Renderer::create(o);
    const glm::dvec3 origin(tile->origin_x, tile->origin_y, 0.0);
    s.frame.camera.eye = origin + glm::dvec3(500.0, 300.0, 800.0);  // looking down at the centre, a little north
    s.frame.camera.target = origin + glm::dvec3(500.0, 500.0, 500.0);
    s.frame.camera.up = {0.0, 1.0, 0.0};
    s.frame.camera.near_m = 10.0;
    s.frame.camera.far_m = 5000.0;
    s.frame.tiles = {tile};
    s.frame.layers.labels = false;
    return s;
}

Image renderWith(Shot& s, Ground ground, MapStyle style = MapStyle::day()) {
    style.ground = ground;
    s.renderer->setMapStyle(style);
    s.renderer->renderMap(s.frame);
    return s.renderer->readSync();
}

glm::ivec3 pixel(const Image& im, int x, int y) {
    const auto* p = im.pixel(x, y);
    return {p[0], p[1], p[2]};
}

// A channel as the textures store it: RGBA4 for the land cover, RGB565 for the orthoimage.
double stored(double v8, int bits) {
    const int max = (1 << bits) - 1;
    return std::round(v8 * max / 255.0) * 255.0 / max;
}

// The terrain point 150 m south of the centre: away from the road.
constexpr int kGroundX = kW / 2, kGroundY = kH - 30;

TEST(OrthoMap, ATerrainPointHasTheOrthoimagesColourOrTheLandCovers) {
    const auto tile = groundTile();
    Shot s = shot(tile, shippedWeights().string());
    const Image cover = renderWith(s, Ground::LandCover);
    EXPECT_EQ(s.renderer->mapStats().ortho_pending, 0u);
    EXPECT_EQ(s.renderer->mapStats().ortho_generated, 0u);  // not wanted: none made
    const Image ortho = renderWith(s, Ground::Orthoimage);
    EXPECT_EQ(s.renderer->mapStats().ortho_generated, 1u);  // no budget: done in the frame that needs it
    EXPECT_EQ(s.renderer->mapStats().ortho_pending, 0u);
    EXPECT_EQ(s.renderer->mapStats().ortho_problem, "");

    // The network's colour of this ground (uniform over the tile) and the water's.
    const mo::OrthoNetwork net = mo::loadNetwork(shippedWeights());
    const auto c = net.color(mo::encodeInput(mo::OrthoTileSampler(*tile).pixel(500, 350)));
    const glm::dvec3 water(0x8f, 0xb8, 0xde);  // landCoverColor(Water), opaque
    const glm::dvec3 water4(stored(water.x, 4), stored(water.y, 4), stored(water.z, 4));
    const glm::dvec3 ortho565(stored(c[0], 5), stored(c[1], 6), stored(c[2], 5));
    // Both are the ground colour times the same relief shading (no fog this close): the shading
    // is measured on the land-cover frame and applied to the orthoimage's colour.
    const glm::ivec3 pc = pixel(cover, kGroundX, kGroundY), po = pixel(ortho, kGroundX, kGroundY);
    const glm::dvec3 shade = glm::dvec3(pc) / water4;
    EXPECT_NEAR(shade.x, shade.y, 0.03);
    EXPECT_NEAR(shade.y, shade.z, 0.03);
    const double k = (shade.x + shade.y + shade.z) / 3.0;
    // Within one step of the texture's channel (the driver's conversion to 5 or 6 bits may
    // truncate where this rounds) and the framebuffer's rounding.
    for (int ch = 0; ch < 3; ++ch) {
        const double step = 255.0 / (ch == 1 ? 63 : 31);
        EXPECT_NEAR(po[ch], ortho565[ch] * k, step * k + 1.0)
            << "channel " << ch << ": ortho " << int(c[static_cast<std::size_t>(ch)]) << ", shading " << k;
    }
    // The two grounds differ (grassland against water blue).
    EXPECT_GT(std::abs(pc.z - po.z) + std::abs(pc.x - po.x), 40);

    // The road stays on top, in the same colour over either ground.
    const glm::ivec3 rc = pixel(cover, kW / 2, kH / 2), ro = pixel(ortho, kW / 2, kH / 2);
    EXPECT_EQ(rc, ro);
    EXPECT_NE(rc, pc);
}

TEST(OrthoMap, NightDarkensTheOrthoimageLikeTheLandCover) {
    Shot s = shot(groundTile(), shippedWeights().string());
    auto sum = [](glm::ivec3 p) { return double(p.x + p.y + p.z); };
    const double cover_day = sum(pixel(renderWith(s, Ground::LandCover), kGroundX, kGroundY));
    const double cover_night = sum(pixel(renderWith(s, Ground::LandCover, MapStyle::night()), kGroundX, kGroundY));
    const double ortho_day = sum(pixel(renderWith(s, Ground::Orthoimage), kGroundX, kGroundY));
    const double ortho_night = sum(pixel(renderWith(s, Ground::Orthoimage, MapStyle::night()), kGroundX, kGroundY));
    EXPECT_LT(ortho_night, 0.6 * ortho_day);
    EXPECT_NEAR(ortho_night / ortho_day, cover_night / cover_day, 0.05);
}

TEST(OrthoMap, ATileWhoseImageIsNotReadyKeepsTheLandCover) {
    // 512 x 512 pixels in bands of 64 rows: eight frames of the network, then the copy and the
    // roofs in frames of their own, after the worker's input vectors; the land cover until the last.
    Shot s = shot(groundTile(), shippedWeights().string(), 512 * 64);
    const Image cover = renderWith(s, Ground::LandCover);
    int frames = 0;
    Image image;
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(30);
    do {
        image = renderWith(s, Ground::Orthoimage);
        ++frames;
        if (s.renderer->mapStats().ortho_pending > 0) {
            EXPECT_EQ(image.rgba, cover.rgba) << "frame " << frames;
            std::this_thread::sleep_for(std::chrono::milliseconds(2));  // the worker's turn
        }
    } while (s.renderer->mapStats().ortho_pending > 0 && std::chrono::steady_clock::now() < deadline);
    EXPECT_EQ(s.renderer->mapStats().ortho_pending, 0u);
    EXPECT_GE(frames, 10);
    EXPECT_NE(image.rgba, cover.rgba);
    // A tile without ortho layers keeps its land cover.
    Shot plain = shot(groundTile(false), shippedWeights().string());
    const Image plain_ortho = renderWith(plain, Ground::Orthoimage);
    EXPECT_EQ(plain.renderer->mapStats().ortho_problem,
              "1 of 1 drawn tiles have no orthoimage layers (the store was compiled without navmap-compile-ortho "
              "--ortho-data): they show the land cover");
    EXPECT_EQ(plain_ortho.rgba, renderWith(plain, Ground::LandCover).rgba);
    EXPECT_EQ(plain.renderer->mapStats().ortho_pending, 0u);
    EXPECT_EQ(renderWith(plain, Ground::Orthoimage).rgba, plain_ortho.rgba);
    EXPECT_EQ(plain.renderer->mapStats().ortho_problem, "") << "said once";
}

TEST(OrthoMap, UnusableWeightsLeaveTheLandCoverAndSaySoOnce) {
    const auto path =
        std::filesystem::temp_directory_path() / ("navmap-ortho-bad-" + std::to_string(::getpid()) + ".nnw");
    std::filesystem::copy_file(shippedWeights(), path, std::filesystem::copy_options::overwrite_existing);
    std::filesystem::resize_file(path, 1000);
    Shot s = shot(groundTile(), path.string());
    const Image cover = renderWith(s, Ground::LandCover);
    EXPECT_EQ(s.renderer->mapStats().ortho_problem, "");  // not wanted yet
    const Image ortho = renderWith(s, Ground::Orthoimage);
    EXPECT_EQ(s.renderer->mapStats().ortho_problem, "orthoimages off: " + path.string() + ": truncated: 1000 of " +
                                                        std::to_string(std::filesystem::file_size(shippedWeights())) +
                                                        " bytes (the ground shows the land cover)");
    EXPECT_EQ(ortho.rgba, cover.rgba);
    EXPECT_EQ(renderWith(s, Ground::Orthoimage).rgba, cover.rgba);
    EXPECT_EQ(s.renderer->mapStats().ortho_problem, "");  // said once
    std::filesystem::remove(path);

    Shot missing = shot(groundTile(), "/nonexistent/ortho-mlp.nnw");
    EXPECT_EQ(renderWith(missing, Ground::Orthoimage).rgba, cover.rgba);
    EXPECT_EQ(missing.renderer->mapStats().ortho_problem,
              "orthoimages off: open(/nonexistent/ortho-mlp.nnw): No such file or directory (orthoimage weights) "
              "(the ground shows the land cover)");
}

// docs/architecture.md "Untrusted files": the weights are read as the renderer is made, never in a
// frame, and only a regular file of the format's size. A FIFO used to block the render thread for
// ever at the first orthoimage frame (and SIGTERM with it), /dev/zero to grow without bound, and a
// 2 GiB file to take 2.1 GiB and every frame after it.
TEST(OrthoMap, WeightsAreReadWhenTheRendererIsMadeAndOnlyFromARegularFile) {
    const auto dir = std::filesystem::temp_directory_path() / ("navmap-ortho-files-" + std::to_string(::getpid()));
    std::filesystem::remove_all(dir);
    std::filesystem::create_directories(dir);
    Shot plain = shot(groundTile(), "");
    const Image cover = renderWith(plain, Ground::LandCover);

    const auto fifo = dir / "fifo.nnw";
    ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
    Shot f = shot(groundTile(), fifo.string());
    EXPECT_EQ(renderWith(f, Ground::Orthoimage).rgba, cover.rgba);
    EXPECT_EQ(f.renderer->mapStats().ortho_problem,
              "orthoimages off: " + fifo.string() +
                  ": is a FIFO, not a regular file (orthoimage weights) (the ground shows the land cover)");
    Shot z = shot(groundTile(), "/dev/zero");
    EXPECT_EQ(renderWith(z, Ground::Orthoimage).rgba, cover.rgba);
    EXPECT_EQ(z.renderer->mapStats().ortho_problem,
              "orthoimages off: /dev/zero: is a character device, not a regular file (orthoimage weights) (the "
              "ground shows the land cover)");
    const auto big = dir / "big.nnw";
    std::filesystem::copy_file(shippedWeights(), big);
    std::filesystem::resize_file(big, std::uintmax_t{2} << 30);  // sparse: no disk
    Shot b = shot(groundTile(), big.string());
    EXPECT_EQ(renderWith(b, Ground::Orthoimage).rgba, cover.rgba);
    EXPECT_EQ(b.renderer->mapStats().ortho_problem,
              "orthoimages off: " + big.string() +
                  ": 2147483648 bytes, over the limit of 192588 bytes (orthoimage weights) (the ground shows the "
                  "land cover)");

    // Read at creation: the file may go before the first orthoimage frame.
    const auto good = dir / "good.nnw";
    std::filesystem::copy_file(shippedWeights(), good);
    Shot g = shot(groundTile(), good.string());
    std::filesystem::remove(good);
    (void)renderWith(g, Ground::Orthoimage);
    EXPECT_EQ(g.renderer->mapStats().ortho_problem, "");
    EXPECT_GT(g.renderer->mapStats().ortho_generated + g.renderer->mapStats().ortho_pending, 0u);
    std::filesystem::remove_all(dir);
}

}  // namespace
