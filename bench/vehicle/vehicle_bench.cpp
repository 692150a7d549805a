// SPDX-License-Identifier: Apache-2.0
// Vehicle input to pose: a simulated Andorra drive's CAN frames (navmap.dbc, GNSS 10 Hz, motion
// 50 Hz) through the DBC decoder and the state estimator, measuring per frame the time from
// receipt to the pose at that time being available (decode + fuse + snapshot + poseAt), and the
// throughput in frames per second. Prints JSON (Google Benchmark).

#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <memory>
#include <vector>

#include "navmap/daemon/vehicle/vehicle_state_estimator.h"
#include "navmap/ipc/can/dbc_database.h"
#include "navmap/ipc/can/signal_map.h"
#include "navmap/ipc/can/vehicle_decoder.h"
#include "navmap/map/tile_store.h"
#include "navmap/sim/drive_simulator.h"

namespace {

using namespace navmap;

struct Input {
    std::vector<ipc::CanFrame> frames;
    std::shared_ptr<const ipc::DbcDatabase> dbc;
    std::shared_ptr<const map::RoadGraph> graph;
    map::Projection projection{0, 0};
};

const Input& input() {
    static const Input kIn = [] {
        sim::DriveRequest request;
        request.store = NAVMAP_DEFAULT_STORE;
        request.dbc = NAVMAP_DATA_DIR "/navmap.dbc";
        request.from = "Andorra la Vella";
        request.to = "Encamp";
        request.frames.noise_m = 2.0;
        request.frames.max_duration_s = 120.0;
        const auto simulator = sim::DriveSimulator::create(request);
        Input x;
        x.frames = simulator.frames();
        x.dbc = simulator.dbc();
        x.graph = std::make_shared<const map::RoadGraph>(simulator.store()->loadGraph());
        x.projection = simulator.projection();
        return x;
    }();
    return kIn;
}

void receiptToPose(benchmark::State& state) {
    const Input& in = input();
    std::vector<double> us;
    std::size_t frames = 0;
    for (auto _ : state) {
        auto decoder = ipc::VehicleDecoder::create({in.dbc}, ipc::SignalMap::navmapDefaults());
        daemon::VehicleStateEstimator estimator(in.projection, std::make_shared<const daemon::MapMatcher>(in.graph));
        ipc::VehicleSample update;
        us.clear();
        for (const auto& f : in.frames) {
            const auto t0 = std::chrono::steady_clock::now();
            if (decoder.value().decode(f, update)) estimator.addSample(update);
            const daemon::EstimatedPose pose = estimator.snapshot()->poseAt(f.timestamp);
            benchmark::DoNotOptimize(pose);
            us.push_back(std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - t0).count());
        }
        frames += in.frames.size();
    }
    std::sort(us.begin(), us.end());
    state.counters["latency_p50_us"] = us[us.size() / 2];
    state.counters["latency_p99_us"] = us[us.size() * 99 / 100];
    state.counters["frames_per_s"] = benchmark::Counter(static_cast<double>(frames), benchmark::Counter::kIsRate);
    state.counters["frames_per_drive"] = static_cast<double>(in.frames.size());
}
BENCHMARK(receiptToPose)->Unit(benchmark::kMillisecond)->Iterations(3);

}  // namespace

BENCHMARK_MAIN();
