// SPDX-License-Identifier: Apache-2.0
// The orthoimage network on the GPU (seed 6.6.2): the shader's forward pass against the CPU
// reference (OrthoNetwork::color) for the shipped weights and for a network of another hidden
// width, a tile's image generated in bands within a pixel budget, and the procedural detail (seed
// 6.7): fields drawn over the whole farmland and nowhere else, the detail keeping the mean colour.

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <map>
#include <memory>
#include <string>
#include <thread>
#include <utility>

#include "gl/egl_context.h"
#include "gl/ortho_detail.h"
#include "gl/ortho_generator.h"
#include "navmap/map/ortho/color_difference.h"
#include "navmap/map/ortho/ortho_network.h"
#include "navmap/map/ortho/rng.h"
#include "navmap/map/ortho/tile_sampler.h"
#include "ortho/field_grid.h"
#include "ortho/vegetation.h"
#include "ortho_test_tile.h"
#include "test_paths.h"

namespace {

using namespace navmap;
using namespace navmap::render;
namespace mo = navmap::map::ortho;

// A request for the whole 2 km test tile at `size` pixels.
gl::OrthoGenerator::Request request(std::shared_ptr<const map::Tile> tile, int size, bool vegetation = false) {
    gl::OrthoGenerator::Request req;
    req.tile = std::move(tile);
    req.extent = 2000.0f;
    req.size = size;
    req.vegetation = vegetation;
    return req;
}

std::filesystem::path shippedWeights() { return test::sourceDir() / "data" / "ortho" / "ortho-mlp.nnw"; }

class OrthoGpu : public ::testing::Test {
protected:
    static void SetUpTestSuite() { s_context = std::make_unique<gl::EglContext>(Platform::Auto); }
    static void TearDownTestSuite() { s_context.reset(); }
    void SetUp() override { s_context->makeCurrent(); }
    static std::unique_ptr<gl::EglContext> s_context;
};
std::unique_ptr<gl::EglContext> OrthoGpu::s_context;

mo::OrthoInput randomInput(mo::Rng& r) {
    mo::OrthoInput in;
    for (std::size_t k = 0; k < std::size_t{mo::kOrthoActive}; ++k) {
        in.pairs[2 * k] = static_cast<std::uint8_t>(r.below(mo::kOrthoInputs));
        in.pairs[2 * k + 1] = static_cast<std::uint8_t>(r.below(256));
    }
    return in;
}

// A fixed set of 64 x 64 input vectors: random ones (any node, any value) and encoded pixels of
// every land-cover and climate class over a range of elevations and climates.
std::vector<mo::OrthoInput> fixedInputs() {
    mo::Rng r(2024);
    std::vector<mo::OrthoInput> v;
    v.reserve(64 * 64);
    for (int i = 0; i < 64 * 48; ++i) v.push_back(randomInput(r));
    for (int i = 0; i < 64 * 16; ++i) {
        mo::OrthoPixel p;
        p.cover = {static_cast<std::uint8_t>(i % mo::kGlobalCoverCount), 1, 0.8f, 0.2f};
        p.climate = {static_cast<std::uint8_t>(i % mo::kClimateClassCount), 14, 0.7f, 0.3f};
        p.elevation_m = static_cast<float>(i % 3000);
        p.temp_dec_c = -10.0f + static_cast<float>(i % 25);
        p.temp_jul_c = 10.0f + static_cast<float>(i % 20);
        p.precip_dec_mm = static_cast<float>(i % 200);
        p.precip_jul_mm = static_cast<float>(i % 150);
        p.lights = static_cast<float>(i % 7) / 7.0f;
        v.push_back(mo::encodeInput(p));
    }
    return v;
}

void expectGpuEqualsCpu(const mo::OrthoNetwork& net, const std::string& what) {
    gl::OrthoGenerator gen(net);
    const auto inputs = fixedInputs();
    const auto gpu = gen.runNetwork(inputs, 64);
    ASSERT_EQ(gpu.size(), inputs.size() * 4);
    int worst = 0, off = 0, distinct = 0;
    for (std::size_t i = 0; i < inputs.size(); ++i) {
        const auto cpu = net.color(inputs[i]);
        for (std::size_t c = 0; c < 3; ++c) {
            const int d = std::abs(int(gpu[i * 4 + c]) - int(cpu[c]));
            worst = std::max(worst, d);
            off += d > 1;
        }
        distinct += i > 0 && std::memcmp(&gpu[i * 4], &gpu[(i - 1) * 4], 3) != 0;
    }
    EXPECT_LE(worst, 1) << what << ": " << off << " channels differ by more than 1/255";
    EXPECT_GT(distinct, static_cast<int>(inputs.size()) / 2) << what << ": the outputs hardly vary";
}

TEST_F(OrthoGpu, TheShaderComputesTheCpuReferenceWithinOneStep) {
    ASSERT_TRUE(std::filesystem::exists(shippedWeights())) << shippedWeights();
    const mo::OrthoNetwork shipped = mo::loadNetwork(shippedWeights());
    ASSERT_EQ(shipped.hidden % 4, 3);  // 43: the last group of four is padded
    expectGpuEqualsCpu(shipped, "shipped weights");
    // A network of another width (13 hidden units, padded to 16 on the GPU) with large weights.
    mo::OrthoNetwork net = mo::OrthoNetwork::zeros(mo::kOrthoInputs, 13);
    mo::Rng r(77);
    for (auto* v : {&net.w0, &net.b0, &net.w1}) {
        for (float& w : *v) w = static_cast<float>(r.uniform(-2, 2));
    }
    net.b1 = {0.3f, 0.4f, 0.2f};
    expectGpuEqualsCpu(net, "random 43-13-3 network");
}

// RGB565 as the tile's texture stores a colour, read back as 8 bits.
int quantized(int v, int bits) {
    const int max = (1 << bits) - 1;
    const int q = (v * max + 127) / 255;
    return (q * 255 + max / 2) / max;
}

TEST_F(OrthoGpu, ATilesImageIsMadeInBandsWithinThePixelBudget) {
    const mo::OrthoNetwork net = mo::loadNetwork(shippedWeights());
    gl::OrthoGenerator gen(net);
    const auto tile = test::orthoTile(
        [](double x, double y) {
            return x < 700 ? mo::SuperLandCover::Forest
                           : (y < 1000 ? mo::SuperLandCover::Residential : mo::SuperLandCover::Lake);
        },
        [](double x, double y) { return static_cast<float>(300.0 + 0.4 * x + 0.2 * y); });
    const gl::OrthoGenerator::Request req = request(tile, 128);
    std::string problem;
    const GLuint tex = gen.start(req, problem);
    ASSERT_NE(tex, 0u) << problem;
    EXPECT_FALSE(gen.ready(tex));
    // 32 rows per frame: four frames of the network. The image is ready after the last unless its
    // detail, made on the worker thread meanwhile, is not: then a later frame finishes it.
    int frames = 0, band_frames = 0;
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(10);
    while (!gen.ready(tex) && std::chrono::steady_clock::now() < deadline) {
        const std::size_t before = gen.timings().pixels;
        gen.step(128 * 32);
        EXPECT_LE(gen.timings().pixels - before, 128u * 32u);
        band_frames += gen.timings().pixels > before;
        if (++frames > 4 && !gen.ready(tex)) std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
    EXPECT_EQ(band_frames, 4);
    EXPECT_EQ(gen.timings().pixels, 128u * 128u);
    EXPECT_EQ(gen.pending(), 0u);
    EXPECT_EQ(gen.timings().images, 1u);
    const auto px = gen.read(tex, 128);
    glDeleteTextures(1, &tex);
    // Every pixel is the CPU reference of the sampler's input at its centre, as RGB565 holds it.
    const mo::OrthoTileSampler sampler(*tile);
    std::vector<mo::OrthoInput> inputs(128 * 128);
    sampler.encodeRows(0, 0, 2000, 128, 0, 128, inputs.data());
    int worst = 0;
    for (std::size_t i = 0; i < inputs.size(); ++i) {
        const auto cpu = net.color(inputs[i]);
        for (std::size_t c = 0; c < 3; ++c) {
            const int expected = quantized(cpu[c], c == 1 ? 6 : 5);
            worst = std::max(worst, std::abs(int(px[i * 4 + c]) - expected));
        }
    }
    EXPECT_LE(worst, 9) << "one 5-bit step and the shader's 1/255";
    // Forest, town and lake differ (row 0 is south: pixel (row 20, column 20) is forest).
    auto at = [&](int row, int col) { return &px[static_cast<std::size_t>(row * 128 + col) * 4]; };
    EXPECT_NE(std::memcmp(at(20, 20), at(20, 100), 3), 0);
    EXPECT_NE(std::memcmp(at(20, 100), at(110, 100), 3), 0);
}

TEST_F(OrthoGpu, ATileWithoutUsableLayersIsRefusedByName) {
    gl::OrthoGenerator gen(mo::loadNetwork(shippedWeights()));
    auto tile =
        test::orthoTile([](double, double) { return mo::SuperLandCover::Grass; }, [](double, double) { return 0.0f; });
    tile->ortho.lights.resize(7);
    gl::OrthoGenerator::Request req = request(tile, 256);
    std::string problem;
    EXPECT_EQ(gen.start(req, problem), 0u);
    EXPECT_EQ(problem, "tile 6/33/17: ortho layer lights has 7 samples, expected 1089 (33x33)");
    tile->ortho.lights.resize(33 * 33);
    req.size = 300;
    EXPECT_EQ(gen.start(req, problem), 0u);
    EXPECT_EQ(problem, "tile 6/33/17: orthoimage size 300 is not a power of two in 1..4096");
    EXPECT_EQ(gen.pending(), 0u);
}

std::shared_ptr<map::Tile> farmTile() {
    return test::orthoTile(
        [](double x, double y) {
            const double dx = x - 900, dy = y - 1000;
            return dx * dx + 2.0 * dy * dy < 600.0 * 600.0 || (y > 1500 && x < 400) ? mo::SuperLandCover::Farmland
                                                                                    : mo::SuperLandCover::Grass;
        },
        [](double, double) { return 300.0f; });
}

TEST_F(OrthoGpu, FieldsAreDrawnOverTheWholeFarmlandAndNowhereElse) {
    gl::OrthoGenerator gen(mo::loadNetwork(shippedWeights()));
    gen.setFieldMaskOnly(true);
    const auto tile = farmTile();
    for (const float angle_deg : {0.0f, 30.0f}) {
        // The second time along a primary road at 30 degrees: the grid turns with it.
        if (angle_deg > 0.0f) {
            map::Road road;
            road.cls = map::RoadClass::Primary;
            const float a = angle_deg * 3.14159265f / 180.0f;
            road.points = {{100, 100}, {100 + 1500 * std::cos(a), 100 + 1500 * std::sin(a)}};
            tile->roads.push_back(road);
        }
        const gl::OrthoGenerator::Request req = request(tile, 512);
        std::string problem;
        const GLuint tex = gen.start(req, problem);
        ASSERT_NE(tex, 0u) << problem;
        gen.step(0);
        ASSERT_TRUE(gen.ready(tex));
        const auto px = gen.read(tex, 512);
        glDeleteTextures(1, &tex);
        int outside = 0, missed = 0, farm = 0;
        for (int r = 0; r < 512; ++r) {
            for (int c = 0; c < 512; ++c) {
                const bool field = px[static_cast<std::size_t>(r * 512 + c) * 4] > 127;
                const bool farmland =
                    tile->ortho.cover[static_cast<std::size_t>(r / 2) * 256 + static_cast<std::size_t>(c / 2)] ==
                    static_cast<std::uint8_t>(mo::SuperLandCover::Farmland);
                farm += farmland;
                outside += field && !farmland;
                missed += farmland && !field;
            }
        }
        EXPECT_GT(farm, 50000);
        EXPECT_EQ(outside, 0) << "field pixels outside the farmland, grid at " << angle_deg << " degrees";
        EXPECT_EQ(missed, 0) << "farmland pixels without a field, grid at " << angle_deg << " degrees";
    }
    EXPECT_GT(gen.detailTimings().parcels, 40u);
}

// Mean colour of the pixels of one land-cover class in a 512 x 512 image of a 256-texel cover.
std::array<float, 3> meanOf(const std::vector<std::uint8_t>& px, const map::Tile& t, mo::SuperLandCover cls) {
    std::array<double, 3> sum{};
    int n = 0;
    for (int r = 0; r < 512; ++r) {
        for (int c = 0; c < 512; ++c) {
            if (t.ortho.cover[static_cast<std::size_t>(r / 2) * 256 + static_cast<std::size_t>(c / 2)] !=
                static_cast<std::uint8_t>(cls)) {
                continue;
            }
            for (std::size_t k = 0; k < 3; ++k) sum[k] += px[static_cast<std::size_t>(r * 512 + c) * 4 + k] / 255.0;
            ++n;
        }
    }
    return {float(sum[0] / n), float(sum[1] / n), float(sum[2] / n)};
}

// Farmland in the west, forest in the east with a village of 40 houses; the elevation rises by
// 1000 m from south to north.
std::shared_ptr<map::Tile> villageTile() {
    auto tile = test::orthoTile(
        [](double x, double) { return x < 1000 ? mo::SuperLandCover::Farmland : mo::SuperLandCover::Forest; },
        [](double, double y) { return static_cast<float>(200 + 0.5 * y); });
    for (int i = 0; i < 40; ++i) {
        map::Building b;
        const int column = i % 8, row = i / 8;  // rows of 8 houses
        const float x = 1300.0f + 40.0f * static_cast<float>(column), y = 300.0f + 40.0f * static_cast<float>(row);
        const float w = 12.0f + static_cast<float>(i % 5) * 3.0f;
        b.footprint.vertices = {{x, y}, {x + w, y}, {x + w, y + 12}, {x, y + 12}};
        b.footprint.ring_ends = {4};
        b.footprint.indices = {0, 1, 2, 0, 2, 3};
        b.height_m = 8.0f + static_cast<float>(i % 3) * 4.0f;
        tile->buildings.push_back(b);
    }
    return tile;
}

TEST_F(OrthoGpu, TheDetailKeepsTheNetworksMeanColour) {
    // seed 6.7.5: fields, plants and roofs take their colour from the basic layer and vary it in
    // pairs.
    gl::OrthoGenerator gen(mo::loadNetwork(shippedWeights()));
    const auto tile = villageTile();
    gl::OrthoGenerator::Request req = request(tile, 512);
    req.details = false;
    std::string problem;
    using Clock = std::chrono::steady_clock;
    auto generate = [&](bool detail) {
        req.details = req.vegetation = detail;
        const GLuint tex = gen.start(req, problem);
        EXPECT_NE(tex, 0u) << problem;
        const auto t0 = Clock::now();
        gen.step(0);
        glFinish();
        const double ms = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
        auto px = gen.read(tex, 512);
        glDeleteTextures(1, &tex);
        return std::pair{px, ms};
    };
    const auto [plain, plain_ms] = generate(false);
    const auto [detailed, detailed_ms] = generate(true);
    const auto& t = gen.detailTimings();
    // The cost of the detail on this tile (docs/benchmarks): printed, not asserted.
    std::printf(
        "512x512 image: %.1f ms plain, %.1f ms with detail (CPU: %.1f ms grid + simulation; GL calls "
        "%.1f ms); %zu parcels, %zu plants, %zu roofs\n",
        plain_ms, detailed_ms, t.cpu_ms, t.draw_ms, t.parcels, t.plants, t.roofs);
    EXPECT_GT(t.plants, 1000u);
    EXPECT_GT(t.parcels, 20u);
    EXPECT_EQ(t.roofs, 40u);
    int changed = 0;
    for (std::size_t i = 0; i < plain.size(); i += 4) changed += std::memcmp(&plain[i], &detailed[i], 3) != 0;
    EXPECT_GT(changed, 512 * 512 / 3);
    // Both images as the tile's RGB565 texture holds them. The elevation varies over the tile so
    // that the basic colours, too, spread over several 5- and 6-bit steps: a region of one colour
    // would be rounded all one way, the detail's varied colours either way.
    for (auto cls : {mo::SuperLandCover::Farmland, mo::SuperLandCover::Forest}) {
        const double de = mo::deltaE76(meanOf(plain, *tile, cls), meanOf(detailed, *tile, cls));
        EXPECT_LT(de, 1.0) << mo::superLandCoverName(cls) << ": the detail moved the mean colour by delta E " << de;
        std::printf("%s: mean colour moved by delta E %.2f\n", mo::superLandCoverName(cls), de);
    }
    // The roofs and their shadows change the houses' pixels; a roof keeps about its ground colour.
    const auto at = [&](const std::vector<std::uint8_t>& px, float x, float y) {
        const auto i =
            static_cast<std::size_t>(static_cast<int>(y / 2000.0f * 512) * 512 + static_cast<int>(x / 2000.0f * 512)) *
            4;
        return std::array<int, 3>{px[i], px[i + 1], px[i + 2]};
    };
    const auto shadow = at(detailed, 1310.0f, 298.5f), ground = at(plain, 1310.0f, 298.5f);
    EXPECT_LT(shadow[0] + shadow[1] + shadow[2], ground[0] + ground[1] + ground[2])
        << "no shadow south-east of the house";
}

TEST_F(OrthoGpu, ACancelledImageLeavesItsDetailBehind) {
    gl::OrthoGenerator gen(mo::loadNetwork(shippedWeights()));
    const auto forest = test::orthoTile([](double, double) { return mo::SuperLandCover::Forest; },
                                        [](double, double) { return 500.0f; });
    const gl::OrthoGenerator::Request req = request(forest, 64, true);
    std::string problem;
    const GLuint gone = gen.start(req, problem), kept = gen.start(req, problem);
    ASSERT_NE(gone, 0u);
    ASSERT_NE(kept, 0u);
    gen.cancel(gone);
    glDeleteTextures(1, &gone);
    EXPECT_EQ(gen.pending(), 1u);
    gen.step(0);
    EXPECT_TRUE(gen.ready(kept));
    EXPECT_EQ(gen.timings().images, 1u);
    EXPECT_EQ(gen.timings().detail_failures, 0u);
    EXPECT_GT(gen.detailTimings().plants, 1000u);
    glDeleteTextures(1, &kept);
    // A third image left pending when the generator goes: its worker job is dropped, nothing hangs.
    EXPECT_NE(gen.start(req, problem), 0u);
}

// With a pixel budget the finish of an image (the copy and the fields, the plants in slices, the
// roofs and the mipmaps) is spread over calls, one step each, and the input vectors come from the
// worker; the image is the one made in a single call without a budget, pixel for pixel.
TEST_F(OrthoGpu, AnImageMadeOverFramesEqualsOneMadeAtOnce) {
    gl::OrthoGenerator gen(mo::loadNetwork(shippedWeights()));
    const auto tile = test::orthoTile(
        [](double x, double) { return x < 1200 ? mo::SuperLandCover::Forest : mo::SuperLandCover::Farmland; },
        [](double, double y) { return static_cast<float>(400.0 + 0.1 * y); });
    const gl::OrthoGenerator::Request req = request(tile, 256, true);
    std::string problem;
    const GLuint at_once = gen.start(req, problem);
    ASSERT_NE(at_once, 0u) << problem;
    gen.step(0);
    ASSERT_TRUE(gen.ready(at_once));
    const std::size_t plants = gen.detailTimings().plants;
    ASSERT_GT(plants, gl::OrthoGenerator::kPlantsPerStep) << "the forest needs more than one slice";

    const GLuint over_frames = gen.start(req, problem);
    ASSERT_NE(over_frames, 0u) << problem;
    int calls = 0, band_calls = 0;
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(20);
    while (!gen.ready(over_frames) && std::chrono::steady_clock::now() < deadline) {
        const std::size_t before = gen.timings().pixels;
        const std::size_t images = gen.timings().images;
        gen.step(256 * 64);
        ++calls;
        band_calls += gen.timings().pixels > before;
        EXPECT_LE(gen.timings().pixels - before, 256u * 64u);
        // The call that finishes the image ran no band.
        if (gen.timings().images > images) {
            EXPECT_EQ(gen.timings().pixels, before);
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
    ASSERT_TRUE(gen.ready(over_frames));
    EXPECT_EQ(band_calls, 4);
    const auto slices =
        static_cast<int>((plants + gl::OrthoGenerator::kPlantsPerStep - 1) / gl::OrthoGenerator::kPlantsPerStep);
    EXPECT_GE(calls, band_calls + 1 + slices + 1) << "bands, copy and fields, " << slices << " plant slices, roofs";
    EXPECT_EQ(gen.timings().input_failures, 0u);
    EXPECT_GT(gen.timings().encode_ms, 0.0);
    EXPECT_EQ(gen.read(over_frames, 256), gen.read(at_once, 256));
    const GLuint textures[] = {at_once, over_frames};
    glDeleteTextures(2, textures);
}

// The detail's cost per 512 x 512 image (docs/benchmarks): the CPU grid and simulation, and the draw
// calls until the GPU has finished them, over a farmland, a forest and a mixed tile. Printed; what is
// asserted is that the detail drew.
TEST_F(OrthoGpu, TheDetailsCostPerImage) {
    using Clock = std::chrono::steady_clock;
    auto ms = [](Clock::time_point t0) { return std::chrono::duration<double, std::milli>(Clock::now() - t0).count(); };
    const std::map<std::string, std::shared_ptr<map::Tile>> tiles{
        {"farmland", test::orthoTile([](double, double) { return mo::SuperLandCover::Farmland; },
                                     [](double, double) { return 300.0f; })},
        {"forest", test::orthoTile([](double, double) { return mo::SuperLandCover::Forest; },
                                   [](double, double) { return 500.0f; })},
        {"village", villageTile()}};
    constexpr int kSize = 512;
    GLuint tex[2] = {0, 0}, fbo = 0;
    glGenTextures(2, tex);
    glBindTexture(GL_TEXTURE_2D, tex[0]);  // the basic layer
    glTexStorage2D(GL_TEXTURE_2D, 1, GL_RGBA8, kSize, kSize);
    glBindTexture(GL_TEXTURE_2D, tex[1]);  // the tile's image
    glTexStorage2D(GL_TEXTURE_2D, 1, GL_RGB565, kSize, kSize);
    glBindTexture(GL_TEXTURE_2D, 0);
    glGenFramebuffers(1, &fbo);
    glBindFramebuffer(GL_FRAMEBUFFER, fbo);
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, tex[0], 0);
    glClearColor(0.35f, 0.4f, 0.2f, 1.0f);
    glClear(GL_COLOR_BUFFER_BIT);
    gl::OrthoDetail detail;
    for (const auto& [name, tile] : tiles) {
        auto t0 = Clock::now();
        const auto grid = render::ortho::buildFieldGrid(*tile);
        const double grid_ms = ms(t0);
        t0 = Clock::now();
        const auto veg = render::ortho::simulateVegetation(*tile);
        const double veg_ms = ms(t0);
        const auto geometry = gl::OrthoDetail::build(*tile, {true, true, false});
        gl::OrthoDetail::Target target;
        target.tile = tile.get();
        target.extent = 2000.0f;
        target.size = kSize;
        target.basic = tex[0];
        glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, tex[1], 0);
        glViewport(0, 0, kSize, kSize);
        std::vector<double> draws;
        for (int i = 0; i < 4; ++i) {
            glClear(GL_COLOR_BUFFER_BIT);
            glFinish();
            t0 = Clock::now();
            detail.draw(target, geometry);
            glFinish();
            draws.push_back(ms(t0));
        }
        std::sort(draws.begin(), draws.end());
        std::vector<std::uint8_t> px(std::size_t{kSize} * kSize * 4);
        glReadPixels(0, 0, kSize, kSize, GL_RGBA, GL_UNSIGNED_BYTE, px.data());
        int changed = 0;
        for (std::size_t i = 0; i < px.size(); i += 4) changed += px[i] != px[0] || px[i + 1] != px[1];
        std::printf(
            "%s: field grid %.1f ms (%zu parcels), vegetation %.1f ms (%zu plants), detail build %.1f ms, "
            "draw until finished %.1f ms (median of 4)\n",
            name.c_str(), grid_ms, grid.parcels.size(), veg_ms, veg.plants.size(), geometry.cpu_ms,
            draws[draws.size() / 2]);
        EXPECT_GT(changed, kSize * kSize / 10) << name << ": the detail drew little";
        glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, tex[0], 0);
    }
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    glDeleteFramebuffers(1, &fbo);
    glDeleteTextures(2, tex);
}

}  // namespace
