// SPDX-License-Identifier: Apache-2.0
// CAN input benchmarks: candump parsing and DBC decode throughput (frames/s), and the latency from a
// frame's receive time (CanFrame::timestamp) to the decoded VehicleSample being available, both
// synchronously (decode on the input thread) and through Replayer thread -> FrameQueue -> consumer.
// Run: ipc_bench --benchmark_format=json

#include <benchmark/benchmark.h>

#include <algorithm>
#include <atomic>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <thread>

#include "frame_queue.h"
#include "navmap/ipc/can/candump_reader.h"
#include "navmap/ipc/can/dbc_database.h"
#include "navmap/ipc/can/replayer.h"
#include "navmap/ipc/can/signal_map.h"
#include "navmap/ipc/can/vehicle_decoder.h"

namespace ipc = navmap::ipc;

namespace {

// The real Ford log and DBC files of tests/ipc/data (see its SOURCES.md).
const std::filesystem::path kData = NAVMAP_IPC_BENCH_DATA;
constexpr const char* kLog = "ford_fusion_2017_acc_on_speed_changing_from_30km_to_80km_per_hour.candump";

std::shared_ptr<const ipc::DbcDatabase> load(const std::filesystem::path& p) {
    return std::make_shared<const ipc::DbcDatabase>(ipc::DbcDatabase::loadOrThrow(p));
}

std::shared_ptr<const ipc::DbcDatabase> navmapDbc() { return load(NAVMAP_IPC_DEFAULT_DBC); }

/// A synthetic 10 Hz GNSS stream (NAV_Position + NAV_Motion + NAV_Info) of `epochs` epochs.
std::vector<ipc::CanFrame> navmapFrames(const ipc::DbcDatabase& db, int epochs, std::chrono::microseconds period) {
    std::vector<ipc::CanFrame> out;
    const auto* pos = db.findMessage(std::string_view("NAV_Position"));
    const auto* mot = db.findMessage(std::string_view("NAV_Motion"));
    for (int i = 0; i < epochs; ++i) {
        auto p = pos->encode({{"NAV_Latitude", 42.5 + i * 1e-6}, {"NAV_Longitude", 1.5 + i * 1e-6}}).value();
        auto m = mot->encode({{"NAV_Heading", 90.0},
                              {"NAV_Speed", 50.0},
                              {"NAV_YawRate", 1.0},
                              {"NAV_FixType", 5},
                              {"NAV_Counter", i % 16}})
                     .value();
        p.timestamp = ipc::CanTime(std::chrono::seconds(1000) + period * i);
        m.timestamp = p.timestamp;
        out.push_back(p);
        out.push_back(m);
    }
    return out;
}

std::string readText(const std::filesystem::path& p) {
    std::ifstream in(p, std::ios::binary);
    std::ostringstream ss;
    ss << in.rdbuf();
    return ss.str();
}

void BM_CandumpParse(benchmark::State& state) {
    const auto path = kData / "can" / kLog;
    if (!std::filesystem::exists(path)) {
        state.SkipWithError((path.string() + " absent").c_str());
        return;
    }
    const std::string text = readText(path);
    std::size_t frames = 0;
    for (auto _ : state) {
        std::istringstream in(text);
        ipc::CandumpReader reader;
        const auto records = reader.readAll(in);
        frames += records.size();
        benchmark::DoNotOptimize(records.data());
    }
    state.counters["frames_per_s"] = benchmark::Counter(static_cast<double>(frames), benchmark::Counter::kIsRate);
    state.SetBytesProcessed(static_cast<std::int64_t>(text.size() * state.iterations()));
}
BENCHMARK(BM_CandumpParse)->Unit(benchmark::kMillisecond);

// Ford log through the Ford signal map: every frame is looked up, mapped ones decoded.
void BM_DecodeFordLog(benchmark::State& state) {
    const auto path = kData / "can" / kLog;
    if (!std::filesystem::exists(path)) {
        state.SkipWithError((path.string() + " absent").c_str());
        return;
    }
    const auto log = ipc::loadCandumpFile(path).value();
    auto map = ipc::SignalMap::loadToml(NAVMAP_IPC_BENCH_SIGNAL_MAP).value();
    auto dec =
        ipc::VehicleDecoder::create(
            {load(kData / "dbc" / "ford_lincoln_base_pt.dbc"), load(kData / "dbc" / "ford_fusion_2018_pt.dbc")}, map)
            .value();
    ipc::VehicleSample u;
    std::size_t frames = 0;
    std::size_t samples = 0;
    for (auto _ : state) {
        for (const auto& r : log.records) {
            samples += dec.decode(r.frame, u) ? 1 : 0;
        }
        frames += log.records.size();
    }
    state.counters["frames_per_s"] = benchmark::Counter(static_cast<double>(frames), benchmark::Counter::kIsRate);
    state.counters["decoded_fraction"] =
        static_cast<double>(samples) / static_cast<double>(std::max<std::size_t>(frames, 1));
}
BENCHMARK(BM_DecodeFordLog)->Unit(benchmark::kMillisecond);

// Only navmap.dbc GNSS frames (every frame mapped, 5 or 2 signals each).
void BM_DecodeNavmapFrames(benchmark::State& state) {
    const auto db = navmapDbc();
    const auto frames = navmapFrames(*db, 1000, std::chrono::milliseconds(100));
    auto dec = ipc::VehicleDecoder::create({db}, ipc::SignalMap::navmapDefaults()).value();
    ipc::VehicleSample u;
    std::size_t n = 0;
    for (auto _ : state) {
        for (const auto& f : frames) {
            benchmark::DoNotOptimize(dec.decode(f, u));
        }
        n += frames.size();
    }
    state.counters["frames_per_s"] = benchmark::Counter(static_cast<double>(n), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_DecodeNavmapFrames)->Unit(benchmark::kMicrosecond);

// Raw DBC codec: all 9 signals of Ford BrakeSysFeatures (Motorola).
void BM_DbcDecodeAllSignals(benchmark::State& state) {
    const auto path = kData / "dbc" / "ford_lincoln_base_pt.dbc";
    if (!std::filesystem::exists(path)) {
        state.SkipWithError((path.string() + " absent").c_str());
        return;
    }
    const auto db = load(path);
    const auto* msg = db->findMessage(0x415U);
    const std::uint8_t data[8] = {0x12, 0x6b, 0x00, 0x00, 0x00, 0x00, 0x00, 0x10};
    double sum = 0;
    for (auto _ : state) {
        msg->decodeAll(data, [&sum](const ipc::DbcSignal&, double v) { sum += v; });
    }
    benchmark::DoNotOptimize(sum);
    state.counters["signals_per_s"] =
        benchmark::Counter(static_cast<double>(state.iterations() * msg->signals.size()), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_DbcDecodeAllSignals);

// Synchronous latency: receive time stamped just before decode (as the input thread does with a
// frame it just read), sample available after decode. Reports p50/p99 in microseconds.
void BM_LatencyReceiveToSampleSync(benchmark::State& state) {
    const auto db = navmapDbc();
    auto frames = navmapFrames(*db, 500, std::chrono::milliseconds(100));
    auto dec = ipc::VehicleDecoder::create({db}, ipc::SignalMap::navmapDefaults()).value();
    ipc::VehicleSample u;
    std::vector<double> lat;
    lat.reserve(1 << 20);
    std::size_t i = 0;
    for (auto _ : state) {
        ipc::CanFrame f = frames[i++ % frames.size()];
        f.timestamp = ipc::CanClock::now();
        dec.decode(f, u);
        const auto done = ipc::CanClock::now();
        if (lat.size() < lat.capacity()) {
            lat.push_back(std::chrono::duration<double, std::micro>(done - u.source_time).count());
        }
    }
    std::sort(lat.begin(), lat.end());
    if (!lat.empty()) {
        state.counters["latency_p50_us"] = lat[lat.size() / 2];
        state.counters["latency_p99_us"] = lat[lat.size() * 99 / 100];
    }
}
BENCHMARK(BM_LatencyReceiveToSampleSync);

// Threaded pipeline: Replayer thread emits a 100 Hz GNSS stream in real time into a FrameQueue,
// a consumer thread polls the queue (yielding when empty) and decodes. Latency = time the sample is
// available minus the frame's receive (emission) time.
void BM_LatencyReplayQueueDecode(benchmark::State& state) {
    const auto db = navmapDbc();
    for (auto _ : state) {
        auto frames = navmapFrames(*db, 50, std::chrono::milliseconds(10));  // 0.5 s
        ipc::Replayer replayer(std::move(frames), ipc::ReplayOptions{});
        ipc::FrameQueue queue(1024);
        auto dec = ipc::VehicleDecoder::create({db}, ipc::SignalMap::navmapDefaults()).value();
        std::vector<double> lat;
        std::atomic<bool> done{false};
        std::thread consumer([&] {
            ipc::CanFrame f;
            ipc::VehicleSample u;
            while (true) {
                if (queue.tryPop(f)) {
                    if (dec.decode(f, u)) {
                        lat.push_back(
                            std::chrono::duration<double, std::micro>(ipc::CanClock::now() - u.source_time).count());
                    }
                } else if (done.load()) {
                    break;
                } else {
                    std::this_thread::yield();
                }
            }
        });
        replayer.start([&queue](const ipc::CanFrame& f) { queue.push(f); });
        replayer.waitFinished();
        replayer.stop();
        done = true;
        consumer.join();
        std::sort(lat.begin(), lat.end());
        if (!lat.empty()) {
            state.counters["latency_p50_us"] = lat[lat.size() / 2];
            state.counters["latency_p99_us"] = lat[lat.size() * 99 / 100];
            state.counters["samples"] = static_cast<double>(lat.size());
            state.counters["queue_drops"] = static_cast<double>(queue.dropped());
        }
    }
}
BENCHMARK(BM_LatencyReplayQueueDecode)->Iterations(1)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
