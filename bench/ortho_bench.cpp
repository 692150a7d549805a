// SPDX-License-Identifier: Apache-2.0
// navmap_ortho_bench: what a synthetic orthoimage costs (seed Table 6.4: a 512 x 512 image, 3.64 s
// on one CPU thread against 0.2 s on a GPU with compressed inputs), on this machine's renderer
// (Mesa llvmpipe in development: there the "GPU" is the CPU too). JSON (Google Benchmark):
//   mlpGpu        the network's shader over 512 x 512 compressed input vectors: upload, draw and
//                 readback (glReadPixels waits for the GPU)
//   mlpCpu        the same network over the same inputs on one CPU thread (OrthoNetwork::color,
//                 the reference the shader is tested against)
//   encodeInputs  the input vectors of the 512 x 512 image from the tile's layers (CPU,
//                 OrthoTileSampler)
// The inputs are those of the leaf tile under Andorra la Vella, its layers sampled from
// marble-qt-data (sampleOrthoLayers) as navmap-compile-ortho samples them; without the package the
// program says so and exits 1.

#include <benchmark/benchmark.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <iostream>
#include <memory>
#include <string>
#include <vector>

#include "gl/ortho_generator.h"
#include "navmap/map/ortho/marble_inputs.h"
#include "navmap/map/ortho/ortho_network.h"
#include "navmap/map/ortho/ortho_preprocess.h"
#include "navmap/map/ortho/tile_sampler.h"
#include "navmap/map/projection.h"
#include "navmap/map/tile_store.h"
#include "navmap/render/renderer.h"

namespace {

using namespace navmap;
using namespace navmap::render;
namespace mo = navmap::map::ortho;
constexpr int kSize = 512;

const mo::OrthoNetwork& network() {
    static const mo::OrthoNetwork n = mo::loadNetwork(NAVMAP_ORTHO_WEIGHTS);
    return n;
}

// The leaf tile under Andorra la Vella with its orthoimage layers.
std::shared_ptr<const map::Tile> andorraTile() {
    static const std::shared_ptr<const map::Tile> t = [] {
        const auto store = map::TileStore::open(NAVMAP_DEFAULT_STORE);
        const map::Projection proj(store->info().origin_lat, store->info().origin_lon);
        const auto& scheme = store->info().scheme;
        const auto id = scheme.tileAt(scheme.leafLevel(), proj.forward(42.5075, 1.5218));
        auto tile = std::make_shared<map::Tile>(*store->load(*id).tile);
        if (tile->ortho.empty()) {
            mo::MarbleInputOptions o;
            o.bounds = std::array<double, 4>{42.0, 1.0, 43.0, 2.0};
            tile->ortho = mo::sampleOrthoLayers(*tile, mo::loadGlobalInputs(mo::kDebianMarbleData, o), proj);
        }
        return std::shared_ptr<const map::Tile>(std::move(tile));
    }();
    return t;
}

const std::vector<mo::OrthoInput>& inputs() {
    static const std::vector<mo::OrthoInput> v = [] {
        std::vector<mo::OrthoInput> in(static_cast<std::size_t>(kSize) * kSize);
        const mo::OrthoTileSampler s(*andorraTile());
        s.encodeRows(0, 0, andorraTile()->size_m, kSize, 0, kSize, in.data());
        return in;
    }();
    return v;
}

// A renderer for its EGL context (current on this thread) and its device's name.
Renderer& context() {
    static const std::unique_ptr<Renderer> r = [] {
        RendererOptions o;
        o.width = o.height = 16;
        return Renderer::create(o);
    }();
    return *r;
}

void mlpGpu(benchmark::State& state) {
    const std::string device = context().device().renderer;
    gl::OrthoGenerator gen(network());
    (void)gen.runNetwork(inputs(), kSize);  // compiles the shader's code on first use
    for (auto _ : state) benchmark::DoNotOptimize(gen.runNetwork(inputs(), kSize));
    state.counters["pixels"] = kSize * kSize;
    state.SetLabel(device);
}

void mlpCpu(benchmark::State& state) {
    std::vector<std::uint8_t> out(static_cast<std::size_t>(kSize) * kSize * 3);
    for (auto _ : state) {
        for (std::size_t i = 0; i < inputs().size(); ++i) {
            const auto c = network().color(inputs()[i]);
            std::memcpy(&out[i * 3], c.data(), 3);
        }
        benchmark::DoNotOptimize(out.data());
    }
    state.counters["pixels"] = kSize * kSize;
    state.SetLabel("1 CPU thread");
}

void encodeInputs(benchmark::State& state) {
    std::vector<mo::OrthoInput> in(static_cast<std::size_t>(kSize) * kSize);
    const mo::OrthoTileSampler s(*andorraTile());
    for (auto _ : state) {
        s.encodeRows(0, 0, andorraTile()->size_m, kSize, 0, kSize, in.data());
        benchmark::DoNotOptimize(in.data());
    }
    state.counters["pixels"] = kSize * kSize;
}

BENCHMARK(mlpGpu)->Unit(benchmark::kMillisecond)->MinTime(2.0);
BENCHMARK(mlpCpu)->Unit(benchmark::kMillisecond)->MinTime(2.0);
BENCHMARK(encodeInputs)->Unit(benchmark::kMillisecond)->MinTime(2.0);

}  // namespace

int main(int argc, char** argv) {
    if (!std::filesystem::exists(mo::kDebianMarbleData / "maps/earth/temp-dec/temp-dec.jpg")) {
        std::cerr << "navmap_ortho_bench: " << mo::kDebianMarbleData.string()
                  << " is absent (Debian package marble-qt-data, scripts/install-deps.sh)\n";
        return 1;
    }
    benchmark::Initialize(&argc, argv);
    if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
    benchmark::RunSpecifiedBenchmarks();
    benchmark::Shutdown();
    return 0;
}
