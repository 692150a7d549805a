// SPDX-License-Identifier: Apache-2.0
// navmap_occlusion_bench: the cost of the visibility techniques of seed chapter 5 (Table 5.1)
// along a fixed flight through the densest built-up part of the data (Andorra la Vella and
// Escaldes, the first kilometres of the drive from kAndorraLaVella), bird's-eye with labels:
// baseline vs transparency label aura vs glowing roads (single colour) vs glowing roads (road
// colour), at 1024x768 and 1680x1050. The four variants are rendered interleaved per camera in
// one renderer, so machine noise hits them alike. Prints JSON (Google Benchmark).
//
// Seed Table 5.1 (GeForce-class GPU, 1024x768): aura -25%, glow single -18%, glow road colour
// -24% frame rate against the baseline; here the counters *_fps_ratio and *_drop_pct are the same
// figures on this machine (llvmpipe in CI).

#include <benchmark/benchmark.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cstdlib>
#include <memory>
#include <numeric>
#include <string>
#include <vector>

#include "drive_scene.h"
#include "navmap/render/renderer.h"

namespace {

using namespace navmap::render;
using navmap::test::DriveScene;
using navmap::test::kAndorraLaVella;
using navmap::test::kEncamp;
using Clock = std::chrono::steady_clock;

struct Size {
    int width, height;
};
constexpr Size kSizes[] = {{1024, 768}, {1680, 1050}};

enum Variant { kBaseline, kAura, kGlowSingle, kGlowRoad, kVariants };
constexpr std::array<const char*, kVariants> kNames = {"baseline", "aura", "glow_single", "glow_road"};

DriveScene& flight() {
    static DriveScene f = DriveScene::open(NAVMAP_DEFAULT_STORE, kAndorraLaVella, kEncamp, std::size_t{512} << 20);
    return f;
}

// Cameras every 150 m over the first 2.4 km of the drive (the town centre), bird's-eye at
// standstill: the closest bird's-eye view, where buildings hide roads and labels.
using Shot = DriveScene::Shot;
std::vector<Shot> shots(const Size& s) {
    DriveScene& f = flight();
    CameraRig rig;
    rig.setMode(ViewMode::Bird);
    std::vector<Shot> out;
    const double length = f.drive.line.empty() ? 0.0 : f.drive.line.back().measure_m;
    for (double m = 150.0; m <= std::min(2400.0, length); m += 150.0) {
        const auto shot = f.settle(rig, m, 0.0, double(s.width) / s.height, s.height, std::chrono::seconds(30));
        out.push_back(shot);
    }
    return out;
}

MapFrame frameFor(const Size& s, const Shot& shot, Variant v) {
    DriveScene& f = flight();
    MapFrame frame = f.frameFor(shot, double(s.width) / s.height, s.height);
    frame.layers.labels = true;
    frame.layers.label_aura = v == kAura;
    frame.layers.glow_roads = v == kGlowSingle || v == kGlowRoad;
    frame.layers.glow_mode = v == kGlowRoad ? MapLayers::GlowMode::RoadColor : MapLayers::GlowMode::SingleColor;
    return frame;
}

double mean(const std::vector<double>& v) {
    return v.empty() ? 0.0 : std::accumulate(v.begin(), v.end(), 0.0) / double(v.size());
}

void occlusionEffects(benchmark::State& state) {
    const Size& s = kSizes[state.range(0)];
    const auto views = shots(s);
    if (views.empty()) {
        state.SkipWithError("no drive through Andorra la Vella in the store");
        return;
    }
    RendererOptions o;
    o.width = s.width;
    o.height = s.height;
    if (const char* env = std::getenv("NAVMAP_BENCH_MSAA")) o.msaa_samples = std::atoi(env);
    // NAVMAP_BENCH_PROFILE=1: glFinish per pass, and the aura/glow pass times as counters (the
    // frame times then include the extra synchronisation).
    o.profile_passes = std::getenv("NAVMAP_BENCH_PROFILE") != nullptr;
    auto r = Renderer::create(o);
    if (const char* env = std::getenv("NAVMAP_BENCH_GLOW_STRENGTH")) {  // 1: opaque glow, no per-pixel stencil
        MapStyle style = MapStyle::day();
        style.glow_strength = static_cast<float>(std::atof(env));
        r->setMapStyle(style);
    }
    // Upload every tile and create every effect's buffers once; labels settle.
    for (const auto& shot : views) {
        for (int v = 0; v < kVariants; ++v) r->renderMap(frameFor(s, shot, Variant(v)));
    }
    r->finish();
    std::array<std::vector<double>, kVariants> ms;
    std::size_t i = 0;
    double labels = 0, buildings = 0, aura_pass = 0, glow_pass = 0, roads_pass = 0, buildings_pass = 0;
    // Per variant, with NAVMAP_BENCH_PROFILE: terrain, buildings, label block (labels and arrows).
    std::array<double, kVariants> terrain_pass{}, variant_buildings_pass{}, label_pass{};
    for (auto _ : state) {
        const Shot& shot = views[i++ % views.size()];
        double total = 0;
        for (int v = 0; v < kVariants; ++v) {
            const MapFrame frame = frameFor(s, shot, Variant(v));
            const auto t0 = Clock::now();
            r->renderMap(frame);
            r->finish();
            const double dt = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
            ms[static_cast<std::size_t>(v)].push_back(dt);
            total += dt;
            const MapFrameStats& st = r->mapStats();
            if (v == kBaseline) {
                labels += double(st.labels_visible);
                buildings += double(st.building_triangles);
                roads_pass += st.roads_ms + st.route_ms;
                buildings_pass += st.buildings_ms;
            }
            terrain_pass[static_cast<std::size_t>(v)] += st.terrain_ms;
            variant_buildings_pass[static_cast<std::size_t>(v)] += st.buildings_ms;
            label_pass[static_cast<std::size_t>(v)] += st.label_block_ms;
            aura_pass += st.aura_ms;
            glow_pass += v == kGlowSingle ? st.glow_ms : 0.0;
        }
        state.SetIterationTime(total / 1000.0);
    }
    const double base = mean(ms[kBaseline]);
    for (int v = 0; v < kVariants; ++v) {
        const double m = mean(ms[static_cast<std::size_t>(v)]);
        const std::string n = kNames[static_cast<std::size_t>(v)];
        state.counters[n + "_ms"] = m;
        state.counters[n + "_fps"] = m > 0 ? 1000.0 / m : 0.0;
        if (v != kBaseline && m > 0) {
            state.counters[n + "_fps_ratio"] = base / m;                 // fps(variant) / fps(baseline)
            state.counters[n + "_drop_pct"] = 100.0 * (1.0 - base / m);  // seed Table 5.1 "diff"
        }
    }
    const double n = double(std::max<std::size_t>(ms[kBaseline].size(), 1));
    state.counters["labels_visible"] = labels / n;
    state.counters["building_triangles"] = buildings / n;
    state.counters["cameras"] = double(views.size());
    if (o.profile_passes) {
        state.counters["aura_pass_ms"] = aura_pass / n;
        state.counters["glow_single_pass_ms"] = glow_pass / n;
        state.counters["baseline_roads_route_ms"] = roads_pass / n;
        state.counters["baseline_buildings_ms"] = buildings_pass / n;
        for (int v = 0; v < kVariants; ++v) {
            const std::string name = kNames[static_cast<std::size_t>(v)];
            state.counters[name + "_terrain_pass_ms"] = terrain_pass[static_cast<std::size_t>(v)] / n;
            state.counters[name + "_buildings_pass_ms"] = variant_buildings_pass[static_cast<std::size_t>(v)] / n;
            state.counters[name + "_label_pass_ms"] = label_pass[static_cast<std::size_t>(v)] / n;
        }
    }
    state.SetLabel(std::to_string(s.width) + "x" + std::to_string(s.height));
}

BENCHMARK(occlusionEffects)
    ->DenseRange(0, 1)
    ->ArgName("size")
    ->UseManualTime()
    ->Unit(benchmark::kMillisecond)
    ->Iterations(16);

}  // namespace

BENCHMARK_MAIN();
