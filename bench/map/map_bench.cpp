// SPDX-License-Identifier: Apache-2.0
// map/ benchmarks (Google Benchmark, JSON with --benchmark_format=json):
//   BM_CompileAndorra   navmap-compile on the embedded extract + DEM: seconds, store bytes
//   BM_TileLoad         TileStore::load of every Andorra tile: per-tile load time
//   BM_CompileLarge     Andorra's road network copied over a 3x3 and a 7x7 grid of offsets (>= 5 M road
//                       vertices, the seed's Bavaria size) by navmap-synth-region's generator
//                       (map/compile/tools/synth_region.h), with its DEM tiles, and compiled: vertices/s,
//                       peak RSS, store bytes
//   BM_CacheFlight      a camera flying across the large store with a 3 MiB cache: hits,
//                       misses, resident bytes vs budget, load p50/p99, request() p99
#include <benchmark/benchmark.h>
#include <sys/resource.h>

#include <unistd.h>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <thread>

#include "navmap/map/compile/compiler.h"
#include "navmap/map/store_set.h"
#include "navmap/map/tile_cache.h"
#include "navmap/map/tile_store.h"
#include "synth_region.h"
#include "tile_selection.h"

namespace fs = std::filesystem;
using namespace navmap::map;
namespace tools = navmap::map::tools;

namespace {

const fs::path kData = fs::path(NAVMAP_SOURCE_DIR) / "data";
fs::path scratch() {
    static const fs::path kDir = fs::temp_directory_path() / ("navmap-bench-" + std::to_string(::getpid()));
    fs::create_directories(kDir);
    return kDir;
}

double peakRssMb() {
    rusage ru{};
    getrusage(RUSAGE_SELF, &ru);
    return static_cast<double>(ru.ru_maxrss) / 1024.0;
}

/// Writes the synthetic large input once (navmap-synth-region's generator, highways only); returns
/// its files and the road vertex count.
std::pair<tools::SynthRegion, std::size_t> largeInput(int grid) {
    tools::SynthRegionOptions opt;
    opt.osm = kData / "andorra-2021-04-14.osm.pbf";
    opt.dem = kData / "N42E001.hgt";
    opt.out_dir = scratch() / ("large-" + std::to_string(grid));
    opt.copies = grid * grid;
    opt.highways_only = true;
    const auto region = tools::synthesizeRegion(opt);
    return {region, region.way_nodes};
}

fs::path andorraStore() {
    static fs::path out;
    if (out.empty()) {
        CompileOptions opt;
        opt.osm = kData / "andorra-2021-04-14.osm.pbf";
        opt.dems = {kData / "N42E001.hgt"};
        opt.out = scratch() / "andorra.navmap";
        compileStore(opt);
        out = opt.out;
    }
    return out;
}

fs::path g_large_store;

void BM_CompileAndorra(benchmark::State& state) {
    CompileStats stats;
    for (auto _ : state) {
        CompileOptions opt;
        opt.osm = kData / "andorra-2021-04-14.osm.pbf";
        opt.dems = {kData / "N42E001.hgt"};
        opt.out = scratch() / "andorra-bm.navmap";
        stats = compileStore(opt);
    }
    state.counters["store_bytes"] = static_cast<double>(stats.store_bytes);
    state.counters["tiles"] = static_cast<double>(stats.tiles);
    state.counters["road_vertices"] = static_cast<double>(stats.road_vertices);
    state.counters["input_bytes"] = static_cast<double>(fs::file_size(kData / "andorra-2021-04-14.osm.pbf"));
}
BENCHMARK(BM_CompileAndorra)->Unit(benchmark::kMillisecond)->Iterations(3);

// Arg 0: from the store; 1: through a StoreSet in a frame 800 km north, which re-expresses every
// tile (a scale and a translation, docs/tile-store.md "Several stores").
void BM_TileLoad(benchmark::State& state) {
    const auto store = TileStore::open(andorraStore());
    const auto ids = store->tileIds();
    const bool mounted = state.range(0) == 1;
    const auto set = StoreSet::mount({store}, Projection(store->info().origin_lat + 7.2, store->info().origin_lon));
    std::vector<double> ms;
    std::size_t i = 0;
    for (auto _ : state) {
        const TileId id = ids[i++ % ids.size()];
        const auto t0 = std::chrono::steady_clock::now();
        auto res = mounted ? set->load(*set->scheme().fromWorld(store->scheme().worldTile(id))) : store->load(id);
        ms.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
        benchmark::DoNotOptimize(res.tile);
    }
    std::sort(ms.begin(), ms.end());
    state.counters["load_p50_ms"] = ms[ms.size() / 2];
    state.counters["load_p99_ms"] = ms[std::min(ms.size() - 1, ms.size() * 99 / 100)];
    state.counters["tiles_in_store"] = static_cast<double>(ids.size());
}
BENCHMARK(BM_TileLoad)->Arg(0)->Arg(1)->Unit(benchmark::kMicrosecond);

void BM_CompileLarge(benchmark::State& state) {
    const int grid = static_cast<int>(state.range(0));
    const auto [region, vertices] = largeInput(grid);
    const fs::path input = region.osm;
    CompileStats stats;
    const double rss_before = peakRssMb();
    for (auto _ : state) {
        CompileOptions opt;
        opt.osm = input;
        opt.dems = region.dems;
        opt.out = scratch() / "large.navmap";
        stats = compileStore(opt);
        g_large_store = opt.out;
    }
    state.counters["road_vertices"] = static_cast<double>(stats.road_vertices);
    state.counters["vertices_per_s"] = static_cast<double>(stats.road_vertices) / stats.total_seconds;
    state.counters["read_s"] = stats.read_seconds;
    state.counters["compile_s"] = stats.total_seconds;
    state.counters["peak_rss_mb"] = peakRssMb();
    state.counters["rss_before_compile_mb"] = rss_before;
    state.counters["store_bytes"] = static_cast<double>(stats.store_bytes);
    state.counters["input_bytes"] = static_cast<double>(fs::file_size(input));
    state.counters["tiles"] = static_cast<double>(stats.tiles);
    state.counters["graph_edges"] = static_cast<double>(stats.graph_edges);
    state.counters["copies"] = grid * grid;
    fs::remove_all(input.parent_path());
}
// 3x3 copies (~1 M vertices) then 7x7 (>= 5 M): compile time should grow linearly.
BENCHMARK(BM_CompileLarge)->Arg(3)->Arg(7)->Unit(benchmark::kSecond)->Iterations(1);

void BM_CacheFlight(benchmark::State& state) {
    if (g_large_store.empty()) {
        state.SkipWithError("needs BM_CompileLarge first");
        return;
    }
    const auto store = TileStore::open(g_large_store);
    const TileScheme& s = store->scheme();
    const int level = s.leafLevel();
    const std::size_t budget = std::size_t{3} << 20;  // small on purpose: forces eviction
    const double rss_before = peakRssMb();
    TileCache cache(store, {budget, true});
    // Fly diagonally across the grid of copies at 100 m per frame (a fast car at 30 fps would
    // be ~1 m per frame: this is a stress test), 4 ms per frame.
    const Box b{s.rootMinX(), s.rootMinY(), s.rootMinX() + s.rootSize(), s.rootMinY() + s.rootSize()};
    const Projection proj = store->projection();
    const PlanarPoint start = proj.forward(store->info().south + 0.1, store->info().west + 0.3);
    const PlanarPoint end = proj.forward(store->info().north - 0.1, store->info().east - 0.3);
    const double len = std::hypot(end.x - start.x, end.y - start.y);
    const double heading = std::atan2(end.x - start.x, end.y - start.y) * 180.0 / 3.14159265358979;
    std::vector<double> request_us;
    std::size_t max_resident = 0, frames = 0, center_missing = 0;
    for (auto _ : state) {
        for (double d = 0; d < len; d += 100.0, ++frames) {
            const PlanarPoint p{start.x + (end.x - start.x) * d / len, start.y + (end.y - start.y) * d / len};
            CameraFootprint cam;
            cam.position = p;
            cam.ground = {
                {p.x - 1500, p.y - 1500}, {p.x + 1500, p.y - 1500}, {p.x + 1500, p.y + 1500}, {p.x - 1500, p.y + 1500}};
            cam.heading_deg = heading;
            cam.prefetch_m = 4000;
            const auto want = selectTiles(s, level, cam);
            const auto t0 = std::chrono::steady_clock::now();
            const auto got = cache.request(want);
            request_us.push_back(
                std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - t0).count());
            if (!want.empty() && !got[0]) ++center_missing;
            max_resident = std::max(max_resident, cache.metrics().resident_bytes);
            std::this_thread::sleep_for(std::chrono::milliseconds(4));
        }
    }
    (void)b;
    const auto m = cache.metrics();
    std::sort(request_us.begin(), request_us.end());
    state.counters["frames"] = static_cast<double>(frames);
    state.counters["hits"] = static_cast<double>(m.hits);
    state.counters["misses"] = static_cast<double>(m.misses);
    state.counters["loads"] = static_cast<double>(m.loads);
    state.counters["evictions"] = static_cast<double>(m.evictions);
    state.counters["dropped_over_budget"] = static_cast<double>(m.dropped_over_budget);
    state.counters["budget_mb"] = static_cast<double>(budget) / 1048576.0;
    state.counters["max_resident_mb"] = static_cast<double>(max_resident) / 1048576.0;
    state.counters["peak_resident_mb"] = static_cast<double>(m.peak_resident_bytes) / 1048576.0;
    state.counters["load_p50_ms"] = m.load_p50_ms;
    state.counters["load_p99_ms"] = m.load_p99_ms;
    state.counters["request_p99_us"] = request_us.empty() ? 0 : request_us[request_us.size() * 99 / 100];
    state.counters["frames_center_tile_missing"] = static_cast<double>(center_missing);
    state.counters["peak_rss_mb"] = peakRssMb();
    state.counters["rss_before_flight_mb"] = rss_before;
}
BENCHMARK(BM_CacheFlight)->Unit(benchmark::kSecond)->Iterations(1);

}  // namespace

int main(int argc, char** argv) {
    benchmark::Initialize(&argc, argv);
    benchmark::RunSpecifiedBenchmarks();
    benchmark::Shutdown();
    std::error_code ec;
    fs::remove_all(scratch(), ec);
    return 0;
}
