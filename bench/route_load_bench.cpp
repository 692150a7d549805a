// SPDX-License-Identifier: Apache-2.0
// What a route costs the map frame, over the real Andorra store: frame time and resident memory
// of the HUD (guidance style) and the cluster (full scene) with no route, the planned drive's
// route, a route of 2,000 and of 20,000 points (set_route's maximum) zig-zagging across the drawn
// area, and no route again after them (clear_route). The route work is bounded by the tiles drawn
// (RoutePass, kRoutePiecesPerTile), so the zig-zags cost about what a normal route costs and the
// memory comes back once the route is gone. JSON:
//   navmap_route_bench --benchmark_format=json
// The benchmarks run in order on one renderer per profile (the memory after one is the start of
// the next); each reports p50_ms, p95_ms, first_ms (the frame that drapes the route), rss_mb
// (after its frames), the route pieces the frame's tiles hold and those uploaded in the last frame.

#include <benchmark/benchmark.h>

#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <string>
#include <vector>

#include "display_profiles.h"
#include "drive_scene.h"
#include "gl/gl_renderer.h"
#include "navmap/common/percentile.h"
#include "navmap/render/renderer.h"

namespace {

using namespace navmap::render;
using navmap::test::DriveScene;
using Clock = std::chrono::steady_clock;
using Profile = navmap::bench::DisplayProfile;

constexpr Profile kProfiles[] = {navmap::bench::kHud, navmap::bench::kCluster};

DriveScene& scene() {
    static DriveScene s = DriveScene::open(NAVMAP_DEFAULT_STORE, navmap::test::kAndorraLaVella, navmap::test::kEncamp,
                                           std::size_t{512} << 20);
    return s;
}

double rssMb() {
    long pages = 0, resident = 0;
    if (FILE* f = std::fopen("/proc/self/statm", "r")) {
        if (std::fscanf(f, "%ld %ld", &pages, &resident) != 2) resident = 0;
        std::fclose(f);
    }
    return double(resident) * double(::sysconf(_SC_PAGESIZE)) / (1024.0 * 1024.0);
}

// A route of `points` points zig-zagging east-west across a 2 km square around `centre` (store
// frame), from its south edge to its north edge: every point far from its neighbours, so every
// segment crosses the drawn area.
RouteGeometry zigZag(glm::dvec2 centre, int points) {
    RouteGeometry r;
    double m = 0.0;
    for (int i = 0; i < points; ++i) {
        const glm::dvec2 p = centre + glm::dvec2(i % 2 == 0 ? -1000.0 : 1000.0, -1000.0 + 2000.0 * i / (points - 1));
        if (i > 0) m += glm::length(p - glm::dvec2(r.points.back()));
        r.points.emplace_back(p.x, p.y, 0.0);
        r.measure_m.push_back(m);
    }
    r.version = 1;
    return r;
}

enum class Load { None, Normal, ZigZag2k, ZigZag20k, Cleared };
constexpr const char* kLoadNames[] = {"no_route", "normal_route", "zigzag_2000", "zigzag_20000", "after_clear"};

struct ProfileRun {
    std::unique_ptr<Renderer> renderer;
    DriveScene::Shot shot;
    RouteGeometry zig_2k, zig_20k;
};

ProfileRun& run(int profile) {
    static std::unique_ptr<ProfileRun> runs[std::size(kProfiles)];
    auto& r = runs[profile];
    if (!r) {
        const Profile& p = kProfiles[profile];
        r = std::make_unique<ProfileRun>();
        CameraRig rig;
        rig.setMode(p.mode);
        DriveScene& s = scene();
        r->shot = s.settle(rig, 0.3 * s.drive.line.back().measure_m, 14.0, double(p.width) / p.height, p.height,
                           std::chrono::seconds(30));
        RendererOptions o;
        o.width = p.width;
        o.height = p.height;
        r->renderer = Renderer::create(o);
        if (profile == 0) r->renderer->setMapStyle(MapStyle::hud());
        const glm::dvec2 centre(r->shot.pose.position);
        r->zig_2k = zigZag(centre, 2000);
        r->zig_20k = zigZag(centre, 20000);
    }
    return *r;
}

void routeLoad(benchmark::State& state) {
    const int profile = static_cast<int>(state.range(0));
    const auto load = static_cast<Load>(state.range(1));
    const Profile& p = kProfiles[profile];
    ProfileRun& r = run(profile);
    MapFrame frame = scene().frameFor(r.shot, double(p.width) / p.height, p.height);
    if (profile == 0) frame.layers = MapLayers::hud();
    switch (load) {
        case Load::None:
        case Load::Cleared: frame.route = nullptr; break;
        case Load::Normal: break;  // the drive's own route
        case Load::ZigZag2k: frame.route = &r.zig_2k; break;
        case Load::ZigZag20k: frame.route = &r.zig_20k; break;
    }
    std::vector<double> ms;
    for (auto _ : state) {
        const auto t0 = Clock::now();
        r.renderer->renderMap(frame);
        r.renderer->finish();
        const double dt = std::chrono::duration<double>(Clock::now() - t0).count();
        state.SetIterationTime(dt);
        ms.push_back(dt * 1000.0);
    }
    const MapFrameStats& st = r.renderer->mapStats();
    const auto* gl = dynamic_cast<const navmap::render::gl::GlRenderer*>(r.renderer.get());
    state.counters["p50_ms"] = navmap::percentile(ms, 0.5);
    state.counters["p95_ms"] = navmap::percentile(ms, 0.95);
    state.counters["first_ms"] = ms.empty() ? 0.0 : ms.front();  // the frame that drapes the route
    state.counters["rss_mb"] = rssMb();
    state.counters["tiles"] = double(st.tiles_drawn);
    if (gl) {
        state.counters["route_pieces"] = double(gl->routeWork().pieces);
        state.counters["route_pieces_uploaded"] = double(gl->routeWork().pieces_uploaded);
    }
    state.SetLabel(std::string(p.name) + "/" + kLoadNames[static_cast<int>(load)]);
}

// In this order: each load starts from the memory the one before left.
void registerLoads(benchmark::internal::Benchmark* b) {
    for (int profile = 0; profile < static_cast<int>(std::size(kProfiles)); ++profile)
        for (int load = 0; load < static_cast<int>(std::size(kLoadNames)); ++load) b->Args({profile, load});
}

// NAVMAP_BENCH_ROUTE_FRAMES: frames per load (default 12).
int framesPerLoad() {
    const char* env = std::getenv("NAVMAP_BENCH_ROUTE_FRAMES");
    return env && std::atoi(env) > 0 ? std::atoi(env) : 12;
}

BENCHMARK(routeLoad)->Apply(registerLoads)->Iterations(framesPerLoad())->UseManualTime()->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
