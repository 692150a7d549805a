// SPDX-License-Identifier: Apache-2.0
// Generation speed of the drive simulator: route + profile setup, frames per second of CPU for
// the GNSS frame stream (with and without faults), and candump formatting.
#include <benchmark/benchmark.h>

#include "navmap/sim/candump_writer.h"
#include "navmap/sim/drive_simulator.h"

namespace {

const navmap::sim::DriveSimulator& drive() {
    static const navmap::sim::DriveSimulator kSim = [] {
        navmap::sim::DriveRequest r;
        r.store = NAVMAP_SIM_BENCH_STORE;
        r.dbc = NAVMAP_IPC_DEFAULT_DBC;
        r.from = "Andorra la Vella";
        r.to = "Encamp";
        return navmap::sim::DriveSimulator::create(r);
    }();
    return kSim;
}

void BM_SetupRouteAndProfile(benchmark::State& state) {
    navmap::sim::DriveRequest r;
    r.store = NAVMAP_SIM_BENCH_STORE;
    r.dbc = NAVMAP_IPC_DEFAULT_DBC;
    r.from = "Andorra la Vella";
    r.to = "Encamp";
    for (auto _ : state) {
        auto sim = navmap::sim::DriveSimulator::create(r);
        benchmark::DoNotOptimize(sim.route().length());
    }
}
BENCHMARK(BM_SetupRouteAndProfile)->Unit(benchmark::kMillisecond);

void BM_GenerateFrames(benchmark::State& state) {
    const auto& sim = drive();
    navmap::sim::FrameOptions o;
    if (state.range(0) != 0) {
        o.noise_m = 2.0;
        o.dropouts = 3;
        o.bad_bursts = 10;
    }
    std::uint64_t frames = 0;
    for (auto _ : state) {
        auto gen = sim.generator(o);
        navmap::ipc::CanFrame f;
        while (gen.next(f)) ++frames;
    }
    state.counters["frames_per_s"] = benchmark::Counter(static_cast<double>(frames), benchmark::Counter::kIsRate);
    state.counters["drive_s"] = sim.profile().duration();
}
BENCHMARK(BM_GenerateFrames)->Arg(0)->Arg(1)->ArgNames({"faults"})->Unit(benchmark::kMillisecond);

void BM_FormatCandump(benchmark::State& state) {
    const auto frames = drive().frames();
    std::size_t bytes = 0;
    for (auto _ : state) {
        for (const auto& f : frames) bytes += navmap::sim::formatCandumpLine(f, "can0").size() + 1;
    }
    state.counters["lines_per_s"] =
        benchmark::Counter(static_cast<double>(frames.size() * state.iterations()), benchmark::Counter::kIsRate);
    state.SetBytesProcessed(static_cast<std::int64_t>(bytes));
}
BENCHMARK(BM_FormatCandump)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
