// SPDX-License-Identifier: Apache-2.0
// Map-frame benchmarks over the real Andorra store along a fixed drive (Andorra la Vella ->
// Encamp), per display profile: frame time p50/p95 for terrain only, +roads, +buildings and the
// full scene; per-pass breakdown; and the roads/terrain ratio measured interleaved in one run.
// Registered into navmap-bench (JSON).

#include <benchmark/benchmark.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include <sys/resource.h>

#include "display_profiles.h"
#include "drive_scene.h"
#include "navmap/common/percentile.h"
#include "navmap/render/renderer.h"
#include "tile_mesh.h"

namespace {

using namespace navmap::render;
using navmap::test::DriveScene;
using navmap::test::kAndorraLaVella;
using navmap::test::kEncamp;
using Clock = std::chrono::steady_clock;

using Profile = navmap::bench::DisplayProfile;
using navmap::bench::kCenter;
using navmap::bench::kHud;
constexpr Profile kProfiles[] = {navmap::bench::kCluster, kHud, kCenter};

using Flight = DriveScene;

Flight& flight() {
    static Flight f = DriveScene::open(NAVMAP_DEFAULT_STORE, kAndorraLaVella, kEncamp, std::size_t{512} << 20);
    return f;
}

// The cameras of one profile along the flight, with every tile they need resident.
using Shot = DriveScene::Shot;

std::vector<Shot> shots(const Profile& p, int count) {
    Flight& f = flight();
    CameraRig rig;
    rig.setMode(p.mode);
    std::vector<Shot> out;
    const double length = f.drive.line.back().measure_m;
    for (int i = 0; i < count; ++i) {
        const double m = length * (0.05 + 0.9 * i / count);
        out.push_back(f.settle(rig, m, 14.0, double(p.width) / p.height, p.height, std::chrono::seconds(30)));
    }
    return out;
}

MapLayers layersFor(int step) {
    MapLayers l;
    l.roads = l.outlines = step >= 1;
    l.buildings = step >= 2;
    l.route = l.marker = step >= 3;
    return l;
}
constexpr const char* kSteps[] = {"terrain", "roads", "buildings", "full"};

// NAVMAP_BENCH_MSAA overrides the sample count (default: the renderer's choice, none on a software
// rasterizer and 4 on a GPU) to compare the cost of MSAA.
RendererOptions optionsFor(const Profile& p) {
    RendererOptions o;
    o.width = p.width;
    o.height = p.height;
    if (const char* env = std::getenv("NAVMAP_BENCH_MSAA")) o.msaa_samples = std::atoi(env);
    return o;
}

// NAVMAP_BENCH_OUTLINE_MASK=gpu or cpu picks where the outline filter learns about the road mask
// (MapLayers::outline_mask; default: automatic, the CPU on llvmpipe).
MapFrame frameFor(const Profile& p, const Shot& s, const MapLayers& layers) {
    MapFrame frame = flight().frameFor(s, double(p.width) / p.height, p.height);
    frame.layers = layers;
    if (const char* env = std::getenv("NAVMAP_BENCH_OUTLINE_MASK")) {
        const std::string where(env);
        if (where == "gpu") {
            frame.layers.outline_mask = MapLayers::OutlineMask::Gpu;
        } else if (where == "cpu") {
            frame.layers.outline_mask = MapLayers::OutlineMask::Cpu;
        } else {
            static const bool kWarned = [&] {
                std::fprintf(stderr, "NAVMAP_BENCH_OUTLINE_MASK=%s: not gpu or cpu, using the automatic choice\n", env);
                return true;
            }();
            (void)kWarned;
        }
    }
    return frame;
}

double processCpuSeconds() {
    rusage u{};
    getrusage(RUSAGE_SELF, &u);
    return double(u.ru_utime.tv_sec + u.ru_stime.tv_sec) + 1e-6 * double(u.ru_utime.tv_usec + u.ru_stime.tv_usec);
}

using navmap::percentile;

void mapFrame(benchmark::State& state) {
    const Profile& p = kProfiles[state.range(0)];
    const int step = static_cast<int>(state.range(1));
    const auto views = shots(p, 24);
    RendererOptions o = optionsFor(p);
    auto r = Renderer::create(o);
    for (const auto& s : views) r->renderMap(frameFor(p, s, layersFor(step)));  // upload everything once
    r->finish();
    std::vector<double> ms;
    std::size_t i = 0;
    const double cpu0 = processCpuSeconds();
    for (auto _ : state) {
        const auto t0 = Clock::now();
        r->renderMap(frameFor(p, views[i++ % views.size()], layersFor(step)));
        r->finish();
        const double dt = std::chrono::duration<double>(Clock::now() - t0).count();
        state.SetIterationTime(dt);
        ms.push_back(dt * 1000.0);
    }
    state.counters["p50_ms"] = percentile(ms, 0.5);
    state.counters["p95_ms"] = percentile(ms, 0.95);
    // CPU time of all threads (the render thread and llvmpipe's rasterizer threads) per frame:
    // less sensitive than wall time to other load on a shared machine, and what a frame costs
    // the ECU's cores.
    if (!ms.empty()) state.counters["cpu_ms"] = (processCpuSeconds() - cpu0) * 1000.0 / double(ms.size());
    state.SetLabel(std::string(p.name) + "/" + kSteps[step]);
}

// Per-pass breakdown of the full scene (glFinish after each pass, so the total is higher).
void mapPasses(benchmark::State& state) {
    const Profile& p = kProfiles[state.range(0)];
    const auto views = shots(p, 24);
    RendererOptions o = optionsFor(p);
    o.profile_passes = true;
    auto r = Renderer::create(o);
    for (const auto& s : views) r->renderMap(frameFor(p, s, layersFor(3)));
    MapFrameStats sum;
    std::size_t n = 0, i = 0;
    for (auto _ : state) {
        r->renderMap(frameFor(p, views[i++ % views.size()], layersFor(3)));
        const auto& s = r->mapStats();
        sum.terrain_ms += s.terrain_ms;
        sum.roads_ms += s.roads_ms;
        sum.outlines_ms += s.outlines_ms;
        sum.buildings_ms += s.buildings_ms;
        sum.route_ms += s.route_ms;
        sum.marker_ms += s.marker_ms;
        sum.tiles_drawn += s.tiles_drawn;
        sum.road_segments += s.road_segments;
        sum.terrain_triangles += s.terrain_triangles;
        sum.outline_pixels += s.outline_pixels;
        sum.outline_cells_ms += s.outline_cells_ms;
        sum.road_blocks_hidden += s.road_blocks_hidden;
        sum.horizon_ms += s.horizon_ms;
        sum.terrain_work += s.terrain_work;
        sum.roads_work += s.roads_work;
        sum.buildings_work += s.buildings_work;
        sum.frame_work += s.frame_work;
        ++n;
    }
    const double k = n ? 1.0 / n : 0.0;
    state.counters["terrain_ms"] = sum.terrain_ms * k;
    state.counters["buildings_ms"] = sum.buildings_ms * k;
    state.counters["roads_ms"] = sum.roads_ms * k;
    state.counters["route_ms"] = sum.route_ms * k;
    state.counters["outlines_ms"] = sum.outlines_ms * k;
    state.counters["outline_cells_ms"] = sum.outline_cells_ms * k;  // CPU, included in outlines_ms
    state.counters["outline_pixels"] = double(sum.outline_pixels) * k;
    state.counters["marker_ms"] = sum.marker_ms * k;
    state.counters["tiles"] = double(sum.tiles_drawn) * k;
    state.counters["road_segments"] = double(sum.road_segments) * k;
    state.counters["road_blocks_hidden"] = double(sum.road_blocks_hidden) * k;  // behind the terrain (TerrainHorizon)
    state.counters["horizon_ms"] = sum.horizon_ms * k;  // CPU beside the render thread, not in the passes
    state.counters["terrain_triangles"] = double(sum.terrain_triangles) * k;
    // GL work per frame (gl_work.h): the same on every machine.
    state.counters["draw_calls"] = double(sum.frame_work.draw_calls) * k;
    state.counters["vertices"] = double(sum.frame_work.vertices) * k;
    state.counters["bytes_uploaded"] = double(sum.frame_work.bytes_uploaded) * k;
    state.counters["terrain_draw_calls"] = double(sum.terrain_work.draw_calls) * k;
    state.counters["roads_draw_calls"] = double(sum.roads_work.draw_calls) * k;
    state.counters["roads_vertices"] = double(sum.roads_work.vertices) * k;
    state.counters["buildings_draw_calls"] = double(sum.buildings_work.draw_calls) * k;
    state.SetLabel(p.name);
}

// seed 3.7 / Fig. 3.14: the cost of roads relative to terrain alone, measured interleaved in one
// run so machine noise hits both alike. roads_cost_pct: the roads as drawn, with their dark
// outlines (3.6.3); roads_no_outline_cost_pct: without the outlines, as the seed's GEO curve was
// measured (3.7 compares terrain with and without roads; the outlines are an option of 3.6.3).
// The seed states its result as a drop in frame rate (Fig. 3.14 plots frames per second: "the
// maximum (average) performance drop is about 30% (26%)"); the *_fps_drop_pct counters give ours
// in that unit, 1 - terrain time / roads time, next to the growth in frame time. The every_class_*
// counters: the same with every road class drawn at every distance (seed 7.3's selection of minor
// classes off, MapLayers::road_selection).
void roadsVsTerrain(benchmark::State& state) {
    const Profile& p = kProfiles[state.range(0)];
    const auto views = shots(p, 24);
    RendererOptions o = optionsFor(p);
    auto r = Renderer::create(o);
    for (const auto& s : views) r->renderMap(frameFor(p, s, layersFor(1)));
    MapLayers no_outline = layersFor(1);
    no_outline.outlines = false;
    MapLayers every_class = layersFor(1), every_class_no_outline = no_outline;
    every_class.road_selection = every_class_no_outline.road_selection = false;
    const std::array<MapLayers, 5> steps{layersFor(0), layersFor(1), no_outline, every_class, every_class_no_outline};
    std::array<std::vector<double>, 5> ms;
    std::size_t i = 0;
    for (auto _ : state) {
        const Shot& s = views[i++ % views.size()];
        for (std::size_t k = 0; k < steps.size(); ++k) {
            const auto t0 = Clock::now();
            r->renderMap(frameFor(p, s, steps[k]));
            r->finish();
            ms[k].push_back(std::chrono::duration<double, std::milli>(Clock::now() - t0).count());
        }
    }
    const double t = percentile(ms[0], 0.5), rd = percentile(ms[1], 0.5), plain = percentile(ms[2], 0.5);
    state.counters["terrain_p50_ms"] = t;
    state.counters["roads_p50_ms"] = rd;
    state.counters["roads_no_outline_p50_ms"] = plain;
    state.counters["roads_cost_pct"] = t > 0 ? 100.0 * (rd - t) / t : 0.0;
    state.counters["roads_no_outline_cost_pct"] = t > 0 ? 100.0 * (plain - t) / t : 0.0;
    state.counters["roads_fps_drop_pct"] = rd > 0 ? 100.0 * (1.0 - t / rd) : 0.0;
    state.counters["roads_no_outline_fps_drop_pct"] = plain > 0 ? 100.0 * (1.0 - t / plain) : 0.0;
    // The same with every road class drawn at every distance (MapLayers::road_selection off).
    const double all = percentile(ms[3], 0.5), all_plain = percentile(ms[4], 0.5);
    state.counters["every_class_cost_pct"] = t > 0 ? 100.0 * (all - t) / t : 0.0;
    state.counters["every_class_no_outline_cost_pct"] = t > 0 ? 100.0 * (all_plain - t) / t : 0.0;
    state.counters["every_class_fps_drop_pct"] = all > 0 ? 100.0 * (1.0 - t / all) : 0.0;
    state.counters["every_class_no_outline_fps_drop_pct"] = all_plain > 0 ? 100.0 * (1.0 - t / all_plain) : 0.0;
    state.SetLabel(p.name);
}

// seed 3.6.1 clipped roads at every triangle edge and saw about 10x the vertices. Counts over
// every tile of the store: polyline vertices as stored, pieces after draping, pieces after merging
// within the default tolerance (TileMeshOptions::road_merge_tolerance_m), the pieces of each
// coarser road level (kRoadLodTolerance) and all pieces stored (every level, shared pieces once);
// the time is the mesh build of all tiles with the default options (done at tile-load time).
void drapingGrowth(benchmark::State& state) {
    const auto& store = *flight().scene.store;
    std::vector<std::shared_ptr<const navmap::map::Tile>> tiles;
    for (const auto id : store.tileIds()) {
        if (auto r = store.load(id); r.tile) tiles.push_back(r.tile);
    }
    TileMeshOptions every_piece;
    every_piece.road_merge_tolerance_m = 0.0;
    double source = 0, draped = 0, stored = 0;
    std::array<double, kRoadLods> level{};  // level 0: the merged pieces
    for (const auto& t : tiles) {
        for (const BlockRun& run : buildTileMesh(*t, every_piece).road_runs) draped += (run.lods & 1u) ? run.count : 0;
    }
    for (auto _ : state) {
        source = stored = 0;
        level.fill(0.0);
        for (const auto& t : tiles) {
            const TileMesh m = buildTileMesh(*t);
            source += double(m.source_road_vertices);
            stored += double(m.roads.size());
            for (const BlockRun& run : m.road_runs) {
                for (int k = 0; k < kRoadLods; ++k)
                    level[static_cast<std::size_t>(k)] += (run.lods >> k & 1u) ? run.count : 0;
            }
        }
    }
    const double merged = level[0];
    state.counters["tiles"] = double(tiles.size());
    state.counters["source_vertices"] = source;
    state.counters["draped_pieces"] = draped;
    state.counters["merged_pieces"] = merged;
    state.counters["growth_draped"] = source > 0 ? draped / source : 0.0;
    state.counters["growth_merged"] = source > 0 ? merged / source : 0.0;
    for (int k = 1; k < kRoadLods; ++k)
        state.counters["level" + std::to_string(k) + "_pieces"] = level[static_cast<std::size_t>(k)];
    state.counters["stored_pieces"] = stored;  // every level; GPU memory grows with it
    state.counters["growth_stored"] = merged > 0 ? stored / merged : 0.0;
}

void profilesAndSteps(benchmark::internal::Benchmark* b) {
    for (int p = 0; p < 3; ++p)
        for (int s = 0; s < 4; ++s) b->Args({p, s});
    b->ArgNames({"profile", "layers"})->UseManualTime()->Unit(benchmark::kMillisecond)->Iterations(48);
}
void profilesOnly(benchmark::internal::Benchmark* b) {
    b->DenseRange(0, 2)->ArgName("profile")->Unit(benchmark::kMillisecond)->Iterations(48);
}

// The ground beyond the data (MapLayers::far_ground), full scene, measured interleaved with it
// off on the same views (each first in turn): its cost in one run.
void farGround(benchmark::State& state) {
    const Profile& p = kProfiles[state.range(0)];
    const auto views = shots(p, 24);
    auto r = Renderer::create(optionsFor(p));
    for (const auto& s : views) r->renderMap(frameFor(p, s, layersFor(3)));
    MapLayers without = layersFor(3);
    without.far_ground = false;
    const std::array<MapLayers, 2> steps{without, layersFor(3)};
    std::array<std::vector<double>, 2> ms;
    std::size_t i = 0;
    for (auto _ : state) {
        const Shot& s = views[i % views.size()];
        const std::size_t first = i++ % 2;  // alternate which goes first: no order bias
        for (std::size_t j = 0; j < steps.size(); ++j) {
            const std::size_t k = (first + j) % steps.size();
            const auto t0 = Clock::now();
            r->renderMap(frameFor(p, s, steps[k]));
            r->finish();
            ms[k].push_back(std::chrono::duration<double, std::milli>(Clock::now() - t0).count());
        }
    }
    state.counters["without_p50_ms"] = percentile(ms[0], 0.5);
    state.counters["with_p50_ms"] = percentile(ms[1], 0.5);
    state.counters["without_p95_ms"] = percentile(ms[0], 0.95);
    state.counters["with_p95_ms"] = percentile(ms[1], 0.95);
    state.SetLabel(p.name);
}

// navmapd's shipped frame (docs/navmapd.md "Where the frame time goes"): one renderer with a
// target per shipped profile, rendered one after another as navmapd's display scheduler does,
// each with the layers and style navmapd gives it (daemon/profiles.cpp layersFor: cluster and
// center with labels, the transparency label aura and glowing roads; the HUD's guidance view,
// MapLayers::hud() in MapStyle::hud(), here without its guidance panel) and read back as navmapd publishes it. Per
// profile: the wall time of render plus readback (p50, p95) and its CPU time (mean); per round of the three: wall and
// CPU time (all threads: the render thread and llvmpipe's rasterizer threads). cores_at_shipped_rates is the CPU the
// three profiles need at their shipped 30 fps each, in cores: above the machine's core count no scheduling can keep
// every profile at 30 fps.
MapLayers shippedLayers(std::size_t profile) {
    if (profile == 1) return MapLayers::hud();
    MapLayers l = layersFor(3);
    l.labels = l.glow_roads = l.label_aura = true;
    return l;
}

void shippedRound(benchmark::State& state) {
    constexpr std::size_t kViews = 24;
    RendererOptions o = optionsFor(kProfiles[0]);
    auto r = Renderer::create(o);
    std::array<TargetHandle, 3> targets{r->primaryTarget(), r->addTarget(kHud.width, kHud.height),
                                        r->addTarget(kCenter.width, kCenter.height)};
    std::array<std::vector<Shot>, 3> views;
    for (std::size_t k = 0; k < 3; ++k) views[k] = shots(kProfiles[k], kViews);
    const auto draw = [&](std::size_t k, std::size_t i) {
        r->setMapStyle(k == 1 ? MapStyle::hud() : MapStyle::day());
        const MapFrame frame = frameFor(kProfiles[k], views[k][i % kViews], shippedLayers(k));
        r->renderMap(targets[k], frame);
        (void)r->readSync(targets[k]);
    };
    for (std::size_t i = 0; i < kViews; ++i)
        for (std::size_t k = 0; k < 3; ++k) draw(k, i);  // uploads, buffers, settled labels
    std::array<std::vector<double>, 3> ms;
    std::array<double, 3> cpu_s{};
    std::vector<double> round_ms;
    std::size_t i = 0;
    const double cpu0 = processCpuSeconds();
    for (auto _ : state) {
        const auto t_round = Clock::now();
        for (std::size_t k = 0; k < 3; ++k) {
            const auto t0 = Clock::now();
            const double c0 = processCpuSeconds();
            draw(k, i);
            cpu_s[k] += processCpuSeconds() - c0;
            ms[k].push_back(std::chrono::duration<double, std::milli>(Clock::now() - t0).count());
        }
        ++i;
        const double dt = std::chrono::duration<double>(Clock::now() - t_round).count();
        state.SetIterationTime(dt);
        round_ms.push_back(dt * 1000.0);
    }
    const double cpu_ms = round_ms.empty() ? 0.0 : (processCpuSeconds() - cpu0) * 1000.0 / double(round_ms.size());
    for (std::size_t k = 0; k < 3; ++k) {
        state.counters[std::string(kProfiles[k].name) + "_p50_ms"] = percentile(ms[k], 0.5);
        state.counters[std::string(kProfiles[k].name) + "_p95_ms"] = percentile(ms[k], 0.95);
        if (!ms[k].empty())
            state.counters[std::string(kProfiles[k].name) + "_cpu_ms"] = cpu_s[k] * 1000.0 / double(ms[k].size());
    }
    state.counters["round_p50_ms"] = percentile(round_ms, 0.5);
    state.counters["round_cpu_ms"] = cpu_ms;
    state.counters["cores_at_shipped_rates"] = cpu_ms * 30.0 / 1000.0;
    state.counters["machine_cores"] = double(std::thread::hardware_concurrency());
    state.SetLabel("cluster+hud+center, shipped layers");
}

BENCHMARK(mapFrame)->Apply(profilesAndSteps);
BENCHMARK(shippedRound)->UseManualTime()->Unit(benchmark::kMillisecond)->Iterations(48);
BENCHMARK(mapPasses)->Apply(profilesOnly);
BENCHMARK(roadsVsTerrain)->Apply(profilesOnly);
BENCHMARK(farGround)->Apply(profilesOnly);
BENCHMARK(drapingGrowth)->Unit(benchmark::kMillisecond)->Iterations(1);

}  // namespace
