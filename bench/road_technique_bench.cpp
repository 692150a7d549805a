// SPDX-License-Identifier: Apache-2.0
// navmap_road_technique_bench: what roads cost relative to terrain alone, geometric (seed 3.4)
// versus shadow-volume roads (seed 3.5), along a fixed flight through the densest built-up area
// of the default data (Andorra la Vella / Escaldes, the first 2.6 km of the drive from
// kAndorraLaVella to kEncamp). seed 3.7, Fig. 3.14: average cost 26 % for GEO, 35-42 % for SV on
// a Radeon HD 5870. The three variants are rendered interleaved, shot by shot, so machine noise
// hits them alike; the ratios are the figures to compare. Prints Google Benchmark JSON:
//
//   build-*/bench/navmap_road_technique_bench --benchmark_format=json
//
// roadTechniques/profile:P/dem:D   P: 0 center (bird's-eye 1280x720), 1 cluster (snail 1280x480)
//                                  D: 0 the store's DEM (62.5 m), 1 refined to 10 m (dem_refine.h)
// Counters: terrain/geo/sv p50 frame ms, geo_cost_pct and sv_cost_pct (mean over the shots of
// (roads - terrain) / terrain), sv_over_geo (sv p50 / geo p50), road segments per frame.
// NAVMAP_BENCH_MSAA overrides the sample count as in navmap-bench; NAVMAP_BENCH_PROFILE=1 adds a
// glFinish per pass (RendererOptions::profile_passes) and the counters geo_pass_ms / sv_pass_ms,
// the road passes alone (frame times then include the finishes).

#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <memory>
#include <unordered_map>
#include <vector>

#include "dem_refine.h"
#include "display_profiles.h"
#include "drive_scene.h"
#include "navmap/common/percentile.h"
#include "navmap/render/renderer.h"

namespace {

using namespace navmap::render;
using navmap::test::DriveScene;
using navmap::test::kAndorraLaVella;
using navmap::test::kEncamp;
using Clock = std::chrono::steady_clock;

using Profile = navmap::bench::DisplayProfile;
constexpr Profile kProfiles[] = {navmap::bench::kCenter, navmap::bench::kCluster};

DriveScene& flight() {
    static DriveScene f = DriveScene::open(NAVMAP_DEFAULT_STORE, kAndorraLaVella, kEncamp, std::size_t{512} << 20);
    return f;
}

struct Shot {
    Camera camera;
    std::vector<std::shared_ptr<const navmap::map::Tile>> tiles;
};

// The flight: 16 settled cameras from 200 m to 2600 m into the drive (through the towns).
std::vector<Shot> shots(const Profile& p, bool refined) {
    DriveScene& f = flight();
    CameraRig rig;
    rig.setMode(p.mode);
    std::unordered_map<std::uint64_t, std::shared_ptr<const navmap::map::Tile>> fine;  // refined once per tile
    std::vector<Shot> out;
    constexpr int kShots = 16;
    const double end = std::min(2600.0, f.drive.line.back().measure_m);
    for (int i = 0; i < kShots; ++i) {
        const double m = 200.0 + (end - 200.0) * i / (kShots - 1);
        const auto s = f.settle(rig, m, 14.0, double(p.width) / p.height, p.height, std::chrono::seconds(30));
        Shot shot{s.camera, f.view->tilesFor(s.camera, double(p.width) / p.height, p.height)};
        if (refined) {
            // Leaf tiles (2 km) only: the distant coarse levels keep their DEM, as a real
            // high-resolution pyramid would be coarse there too.
            const int leaf = f.scene.store->scheme().leafLevel();
            for (auto& t : shot.tiles) {
                if (t->id.level != leaf) continue;
                auto& slot = fine[t->id.key()];
                if (!slot) slot = refineTile(*t);
                t = slot;
            }
        }
        out.push_back(std::move(shot));
    }
    return out;
}

MapFrame frameFor(const Shot& s, bool roads, RoadTechnique technique) {
    MapFrame frame;
    frame.camera = s.camera;
    frame.tiles = s.tiles;
    frame.layers.roads = frame.layers.outlines = roads;
    frame.layers.buildings = frame.layers.route = frame.layers.marker = false;
    frame.layers.road_technique = technique;
    return frame;
}

using navmap::percentile;

void roadTechniques(benchmark::State& state) {
    const Profile& p = kProfiles[state.range(0)];
    const bool refined = state.range(1) != 0;
    const auto views = shots(p, refined);
    RendererOptions o;
    o.width = p.width;
    o.height = p.height;
    if (const char* env = std::getenv("NAVMAP_BENCH_MSAA")) o.msaa_samples = std::atoi(env);
    const char* profile = std::getenv("NAVMAP_BENCH_PROFILE");
    o.profile_passes = profile && std::atoi(profile) != 0;
    auto r = Renderer::create(o);
    // Upload everything (tiles, both road representations) before timing.
    for (const auto& s : views) {
        r->renderMap(frameFor(s, true, RoadTechnique::Geometric));
        r->renderMap(frameFor(s, true, RoadTechnique::ShadowVolume));
    }
    r->finish();
    std::vector<double> terrain, geo, sv, geo_cost, sv_cost;
    double geo_segments = 0, sv_segments = 0, geo_pass = 0, sv_pass = 0;
    std::size_t i = 0;
    auto timed = [&](const MapFrame& frame) {
        const auto t0 = Clock::now();
        r->renderMap(frame);
        r->finish();
        return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
    };
    for (auto _ : state) {
        const Shot& s = views[i++ % views.size()];
        const double t = timed(frameFor(s, false, RoadTechnique::Geometric));
        const double g = timed(frameFor(s, true, RoadTechnique::Geometric));
        geo_segments += double(r->mapStats().road_segments);
        geo_pass += r->mapStats().roads_ms;
        const double v = timed(frameFor(s, true, RoadTechnique::ShadowVolume));
        sv_segments += double(r->mapStats().road_segments);
        sv_pass += r->mapStats().sv_roads_ms;
        terrain.push_back(t);
        geo.push_back(g);
        sv.push_back(v);
        geo_cost.push_back(100.0 * (g - t) / t);
        sv_cost.push_back(100.0 * (v - t) / t);
        state.SetIterationTime((t + g + v) / 1000.0);
    }
    auto mean = [](const std::vector<double>& v) {
        double sum = 0.0;
        for (double x : v) sum += x;
        return v.empty() ? 0.0 : sum / double(v.size());
    };
    const double n = double(std::max<std::size_t>(i, 1));
    state.counters["terrain_p50_ms"] = percentile(terrain, 0.5);
    state.counters["geo_p50_ms"] = percentile(geo, 0.5);
    state.counters["sv_p50_ms"] = percentile(sv, 0.5);
    state.counters["geo_cost_pct"] = mean(geo_cost);
    state.counters["sv_cost_pct"] = mean(sv_cost);
    state.counters["geo_cost_max_pct"] = geo_cost.empty() ? 0.0 : *std::max_element(geo_cost.begin(), geo_cost.end());
    state.counters["sv_cost_max_pct"] = sv_cost.empty() ? 0.0 : *std::max_element(sv_cost.begin(), sv_cost.end());
    state.counters["sv_over_geo"] = percentile(geo, 0.5) > 0 ? percentile(sv, 0.5) / percentile(geo, 0.5) : 0.0;
    state.counters["geo_segments"] = geo_segments / n;
    state.counters["sv_segments"] = sv_segments / n;
    if (o.profile_passes) {
        state.counters["geo_pass_ms"] = geo_pass / n;
        state.counters["sv_pass_ms"] = sv_pass / n;
    }
    state.SetLabel(std::string(p.name) + (refined ? "/dem10m" : "/srtm"));
}

BENCHMARK(roadTechniques)
    ->ArgsProduct({{0, 1}, {0, 1}})
    ->ArgNames({"profile", "dem"})
    ->UseManualTime()
    ->Unit(benchmark::kMillisecond)
    ->Iterations(32);

}  // namespace

BENCHMARK_MAIN();
