// SPDX-License-Identifier: Apache-2.0
// Cost of one fixed layout step (seed 4.6.1 measures the same per frame on the GPU: ~2000
// labels in 10 ms). Single thread. Targets: 2000 labels < 1 ms, 10000 < 5 ms per step.
#include <cmath>
#include <cstdint>

#include <benchmark/benchmark.h>

#include "navmap/render/labels/label_layout.h"
#include "synthetic_label_scene.h"

namespace nl = navmap::render::labels;
namespace nt = navmap::test;

namespace {

constexpr double kFrame = 1.0 / 60.0;

void setCounters(benchmark::State& state, const nl::LabelLayout& layout, std::size_t n, bool frame_work = true) {
    const nl::LayoutStats s = layout.stats();
    state.counters["labels"] = static_cast<double>(n);
    state.counters["placed"] = static_cast<double>(s.visible + s.fading_in);
    state.counters["waiting"] = static_cast<double>(s.waiting + s.pending);
    state.counters["pairs"] = static_cast<double>(s.last_pairs);
    state.counters["collisions"] = static_cast<double>(s.last_collisions);
    // The last frame's work, the same on every machine (tests/render/labels/
    // label_layout_work_test.cpp asserts its growth). step() alone does not count it.
    if (!frame_work) return;
    state.counters["pair_tests"] = static_cast<double>(s.last_pair_tests);
    state.counters["sat_tests"] = static_cast<double>(s.last_sat_tests);
    state.counters["grid_cells"] = static_cast<double>(s.last_grid_cells);
}

// Dense scene (label area 1.5 x the screen): most labels wait for room, the placed ones
// settle; each iteration is one fixed step including placement retries.
void BM_StepDense(benchmark::State& state) {
    const auto n = static_cast<std::size_t>(state.range(0));
    nt::SyntheticScene scene = nt::makeSyntheticScene(n, 42, 1.5F);
    nl::LayoutParams p;
    p.max_placements_per_step = 64;
    nl::LabelLayout layout(p);
    for (int f = 0; f < 240; ++f) {  // 4 s warm-up: every label tried at least once
        layout.setFrame(scene.candidates, scene.camera);
        layout.advance(kFrame);
    }
    for (auto _ : state) {
        layout.step();
    }
    setCounters(state, layout, n, false);
}

// Every label placed and moving: sparse enough that nearly all fit, anchors wobbling each
// frame so collisions and forces never rest. One iteration = one frame (setFrame + one step).
void BM_FrameAllActive(benchmark::State& state) {
    const auto n = static_cast<std::size_t>(state.range(0));
    nt::SyntheticScene scene = nt::makeSyntheticScene(n, 7, 0.25F);
    nl::LayoutParams p;
    p.max_placements_per_step = 256;
    p.placement_zone_px = p.buffer_px;  // let labels start close, so the buffers collide
    nl::LabelLayout layout(p);
    std::uint64_t frame = 0;
    for (int f = 0; f < 120; ++f) {
        nt::wobbleScene(scene, frame++);
        layout.setFrame(scene.candidates, scene.camera);
        layout.advance(kFrame);
    }
    for (auto _ : state) {
        state.PauseTiming();
        nt::wobbleScene(scene, frame++);
        state.ResumeTiming();
        layout.setFrame(scene.candidates, scene.camera);
        layout.advance(kFrame);
    }
    setCounters(state, layout, n);
}

// A panning camera over the dense scene: one frame = setFrame + one step + output.
void BM_FramePanDense(benchmark::State& state) {
    const auto n = static_cast<std::size_t>(state.range(0));
    nt::SyntheticScene scene = nt::makeSyntheticScene(n, 42, 1.5F);
    nl::LayoutParams p;
    p.max_placements_per_step = 64;
    nl::LabelLayout layout(p);
    for (int f = 0; f < 240; ++f) {
        layout.setFrame(scene.candidates, scene.camera);
        layout.advance(kFrame);
    }
    for (auto _ : state) {
        state.PauseTiming();
        nt::panScene(scene, {1.0F, 0.5F});
        state.ResumeTiming();
        layout.setFrame(scene.candidates, scene.camera);
        layout.advance(kFrame);
    }
    setCounters(state, layout, n);
}

}  // namespace

BENCHMARK(BM_StepDense)->Arg(100)->Arg(500)->Arg(1000)->Arg(2000)->Arg(5000)->Arg(10000)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_FrameAllActive)
    ->Arg(100)
    ->Arg(500)
    ->Arg(1000)
    ->Arg(2000)
    ->Arg(5000)
    ->Arg(10000)
    ->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_FramePanDense)
    ->Arg(100)
    ->Arg(500)
    ->Arg(1000)
    ->Arg(2000)
    ->Arg(5000)
    ->Arg(10000)
    ->Unit(benchmark::kMicrosecond);

BENCHMARK_MAIN();
