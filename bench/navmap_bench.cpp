// SPDX-License-Identifier: Apache-2.0
// navmap-bench: frame-level benchmarks on the real data, printed as JSON (Google Benchmark's
// JSON reporter unless --benchmark_format says otherwise). Each figure is the median of
// repeated runs; compare ratios taken in one run, the machine is noisy.
//
//   heightfield/<w>x<h>        render the Andorra heightfield (terrain only) and wait for the GPU
//   readback_sync/<w>x<h>      render + synchronous glReadPixels
//   readback_ring/<w>x<h>      render + ring of pixel-pack buffers (steady state, 3 in flight)

#include <benchmark/benchmark.h>

#include <cstdlib>
#include <cstring>
#include <memory>
#include <string>
#include <vector>

#include "navmap/render/renderer.h"
#include "terrain_scene.h"

namespace {

using navmap::render::Renderer;

const navmap::render::TerrainScene& scene() {
    static const auto kS = navmap::render::loadTerrainScene(NAVMAP_DEFAULT_DEM);
    return kS;
}

std::unique_ptr<Renderer> makeRenderer(int w, int h) {
    navmap::render::RendererOptions o;
    o.width = w;
    o.height = h;
    auto r = Renderer::create(o);
    r->setTerrain(scene().mesh);
    return r;
}

// Cameras cycle along the fly-over so caches do not flatter a single view.
navmap::render::Camera cameraAt(std::int64_t i) {
    return navmap::render::andorraFlyoverCamera(scene().projection, static_cast<double>(i % 48) / 48.0);
}

void heightfield(benchmark::State& state) {
    auto r = makeRenderer(static_cast<int>(state.range(0)), static_cast<int>(state.range(1)));
    std::int64_t i = 0;
    for (auto _ : state) {
        r->render(cameraAt(i++));
        r->finish();
    }
    state.counters["triangles"] = static_cast<double>(scene().mesh.indices.size() / 3);
    state.SetLabel(r->device().renderer);
}

void readbackSync(benchmark::State& state) {
    auto r = makeRenderer(static_cast<int>(state.range(0)), static_cast<int>(state.range(1)));
    std::int64_t i = 0;
    for (auto _ : state) {
        r->render(cameraAt(i++));
        benchmark::DoNotOptimize(r->readSync());
    }
}

void readbackRing(benchmark::State& state) {
    auto r = makeRenderer(static_cast<int>(state.range(0)), static_cast<int>(state.range(1)));
    std::int64_t i = 0;
    for (int warm = 0; warm < 3; ++warm) {  // fill the ring so every timed iteration is steady state
        r->render(cameraAt(i));
        (void)r->readAsync(static_cast<std::uint64_t>(i++));
    }
    for (auto _ : state) {
        r->render(cameraAt(i));
        benchmark::DoNotOptimize(r->readAsync(static_cast<std::uint64_t>(i++)));
    }
    (void)r->drainReadbacks();
}

void profiles(benchmark::internal::Benchmark* b) {
    b->Args({1280, 480})->Args({800, 240});
    b->ArgNames({"w", "h"});
    b->Unit(benchmark::kMillisecond)->UseRealTime()->MinTime(0.5);
    b->Repetitions(5)->ReportAggregatesOnly(true);
}

BENCHMARK(heightfield)->Apply(profiles);
BENCHMARK(readbackSync)->Apply(profiles);
BENCHMARK(readbackRing)->Apply(profiles);

}  // namespace

int main(int argc, char** argv) {
    // JSON by default (docs/architecture.md "Quality bars": benchmarks print JSON); an explicit --benchmark_format
    // wins.
    std::vector<char*> args(argv, argv + argc);
    bool has_format = false;
    for (int i = 1; i < argc; ++i) has_format |= std::strncmp(argv[i], "--benchmark_format", 18) == 0;
    static char json[] = "--benchmark_format=json";
    if (!has_format) args.push_back(json);
    int n = static_cast<int>(args.size());
    benchmark::Initialize(&n, args.data());
    if (benchmark::ReportUnrecognizedArguments(n, args.data())) return 1;
    benchmark::RunSpecifiedBenchmarks();
    benchmark::Shutdown();
    return 0;
}
