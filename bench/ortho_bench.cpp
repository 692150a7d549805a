// SPDX-License-Identifier: Apache-2.0
// navmap_ortho_bench: what a synthetic orthoimage costs (seed Table 6.4: a 512 x 512 image, 3.64 s
// on one CPU thread against 0.2 s on a GPU with compressed inputs), on this machine's renderer
// (Mesa llvmpipe in development: there the "GPU" is the CPU too). JSON (Google Benchmark):
//   mlpGpu        the network's shader over 512 x 512 compressed input vectors: upload, draw and
//                 readback (glReadPixels waits for the GPU)
//   mlpCpu        the same network over the same inputs on one CPU thread (OrthoNetwork::color,
//                 the reference the shader is tested against)
//   encodeInputs  the input vectors of the 512 x 512 image from the tile's layers (CPU,
//                 OrthoTileSampler)
//   groundFrame/<profile>  map frames along the Andorra la Vella -> Encamp drive with the land cover
//                 and with the orthoimage as the ground, interleaved per camera (every image made
//                 before timing): p50 frame time (renderMap + finish) of each and their ratio; with
//                 NAVMAP_BENCH_PICTURES=DIR it also writes each camera's two frames there as PNG
//   tileUpload/<profile>   the frames that upload the tiles of cameras along the drive (a GPU tile
//                 cache of one tile, so each camera uploads its own), per tile, with the land cover
//                 and with the orthoimage (no pixel budget: each image made in its tile's upload
//                 frame); RendererOptions::profile_passes, so uploads_ms includes a glFinish
//   generationFrames/<profile>  four cameras along the drive, each held until its images are
//                 made with navmapd's pixel budget (16384 per frame): frame time (renderMap +
//                 finish) while images are made and once they are, the render thread's own time
//                 on them (MapFrameStats::ortho_ms: its GL calls wait for queued GPU work where
//                 the driver syncs) and the frames an image takes
// The inputs of the first three are those of the leaf tile under Andorra la Vella, its layers
// sampled from marble-qt-data (sampleOrthoLayers) as navmap-compile-ortho samples them; without
// the package the program says so and exits 1. The last two read a store compiled with the layers,
// NAVMAP_BENCH_ORTHO_STORE (default <build>/andorra-ortho.navmap, which the build makes: target
// navmap_ortho_store), that is
//   build/map/navmap-compile-ortho --osm data/andorra-2021-04-14.osm.pbf --dem data/N42E001.hgt
//       --ortho-data /usr/share/marble/data --out build/andorra-ortho.navmap

#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <iostream>
#include <memory>
#include <string>
#include <vector>

#include "display_profiles.h"
#include "drive_scene.h"
#include "gl/ortho_generator.h"
#include "navmap/common/percentile.h"
#include "navmap/map/compile/ortho/marble_inputs.h"
#include "navmap/map/compile/ortho/ortho_preprocess.h"
#include "navmap/map/ortho/ortho_network.h"
#include "navmap/map/ortho/tile_sampler.h"
#include "navmap/map/projection.h"
#include "navmap/map/tile_store.h"
#include "navmap/render/image.h"
#include "navmap/render/renderer.h"

namespace {

using namespace navmap;
using namespace navmap::render;
namespace mo = navmap::map::ortho;
using navmap::percentile;
constexpr int kSize = 512;

const mo::OrthoNetwork& network() {
    static const mo::OrthoNetwork n = mo::loadNetwork(NAVMAP_ORTHO_WEIGHTS);
    return n;
}

// The leaf tile under Andorra la Vella with its orthoimage layers.
std::shared_ptr<const map::Tile> andorraTile() {
    static const std::shared_ptr<const map::Tile> t = [] {
        const auto store = map::TileStore::open(NAVMAP_DEFAULT_STORE);
        const map::Projection proj(store->info().origin_lat, store->info().origin_lon);
        const auto& scheme = store->info().scheme;
        const auto id = scheme.tileAt(scheme.leafLevel(), proj.forward(42.5075, 1.5218));
        auto tile = std::make_shared<map::Tile>(*store->load(*id).tile);
        if (tile->ortho.empty()) {
            mo::MarbleInputOptions o;
            o.bounds = std::array<double, 4>{42.0, 1.0, 43.0, 2.0};
            tile->ortho = mo::sampleOrthoLayers(*tile, mo::loadGlobalInputs(mo::kDebianMarbleData, o), proj);
        }
        return std::shared_ptr<const map::Tile>(std::move(tile));
    }();
    return t;
}

const std::vector<mo::OrthoInput>& inputs() {
    static const std::vector<mo::OrthoInput> v = [] {
        std::vector<mo::OrthoInput> in(static_cast<std::size_t>(kSize) * kSize);
        const mo::OrthoTileSampler s(*andorraTile());
        s.encodeRows(0, 0, andorraTile()->size_m, kSize, 0, kSize, in.data());
        return in;
    }();
    return v;
}

// A renderer for its EGL context (current on this thread) and its device's name.
Renderer& context() {
    static const std::unique_ptr<Renderer> r = [] {
        RendererOptions o;
        o.width = o.height = 16;
        return Renderer::create(o);
    }();
    return *r;
}

void mlpGpu(benchmark::State& state) {
    const std::string device = context().device().renderer;
    gl::OrthoGenerator gen(network());
    (void)gen.runNetwork(inputs(), kSize);  // compiles the shader's code on first use
    for (auto _ : state) benchmark::DoNotOptimize(gen.runNetwork(inputs(), kSize));
    state.counters["pixels"] = kSize * kSize;
    state.SetLabel(device);
}

void mlpCpu(benchmark::State& state) {
    std::vector<std::uint8_t> out(static_cast<std::size_t>(kSize) * kSize * 3);
    for (auto _ : state) {
        for (std::size_t i = 0; i < inputs().size(); ++i) {
            const auto c = network().color(inputs()[i]);
            std::memcpy(&out[i * 3], c.data(), 3);
        }
        benchmark::DoNotOptimize(out.data());
    }
    state.counters["pixels"] = kSize * kSize;
    state.SetLabel("1 CPU thread");
}

void encodeInputs(benchmark::State& state) {
    std::vector<mo::OrthoInput> in(static_cast<std::size_t>(kSize) * kSize);
    const mo::OrthoTileSampler s(*andorraTile());
    for (auto _ : state) {
        s.encodeRows(0, 0, andorraTile()->size_m, kSize, 0, kSize, in.data());
        benchmark::DoNotOptimize(in.data());
    }
    state.counters["pixels"] = kSize * kSize;
}

// --- The orthoimage in the map ---

using navmap::test::DriveScene;
using Clock = std::chrono::steady_clock;
using Profile = navmap::bench::DisplayProfile;
constexpr Profile kProfiles[] = {navmap::bench::kCluster, navmap::bench::kHud, navmap::bench::kCenter};

std::string orthoStorePath() {
    const char* env = std::getenv("NAVMAP_BENCH_ORTHO_STORE");
    return env ? env : NAVMAP_ORTHO_STORE;
}

DriveScene& drive() {
    static DriveScene d = DriveScene::open(orthoStorePath(), navmap::test::kAndorraLaVella, navmap::test::kEncamp,
                                           std::size_t{512} << 20);
    return d;
}

std::vector<DriveScene::Shot> shots(const Profile& p, int count) {
    DriveScene& d = drive();
    CameraRig rig;
    rig.setMode(p.mode);
    std::vector<DriveScene::Shot> out;
    const double length = d.drive.line.back().measure_m;
    for (int i = 0; i < count; ++i) {
        const double m = length * (0.05 + 0.9 * i / count);
        out.push_back(d.settle(rig, m, 14.0, double(p.width) / p.height, p.height, std::chrono::seconds(30)));
    }
    return out;
}

MapFrame frameOf(const Profile& p, const DriveScene::Shot& s) {
    MapFrame f = drive().frameFor(s, double(p.width) / p.height, p.height);
    f.layers.route = f.layers.marker = true;
    return f;
}

MapStyle styleWith(Ground g) {
    MapStyle s = MapStyle::day();
    s.ground = g;
    return s;
}

bool haveOrthoStore(benchmark::State& state) {
    if (std::filesystem::exists(orthoStorePath())) return true;
    state.SkipWithError((orthoStorePath() + " is absent: compile it with navmap-compile-ortho (see the head of "
                                            "bench/ortho_bench.cpp)")
                            .c_str());
    return false;
}

// The frames of every view with either ground, as DIR/<profile>-<view>-{landcover,orthoimage}.png
// (the README's picture pair is one of them).
void writePictures(Renderer& r, const Profile& p, const std::vector<DriveScene::Shot>& views, const std::string& dir) {
    std::filesystem::create_directories(dir);
    for (std::size_t i = 0; i < views.size(); ++i) {
        for (Ground g : {Ground::LandCover, Ground::Orthoimage}) {
            r.setMapStyle(styleWith(g));
            r.renderMap(frameOf(p, views[i]));
            r.finish();
            const Image image = r.readSync(r.primaryTarget());
            const std::filesystem::path path =
                std::filesystem::path(dir) / (std::string(p.name) + "-" + std::to_string(i) + "-" +
                                              (g == Ground::LandCover ? "landcover" : "orthoimage") + ".png");
            std::string error;
            if (!writePng(path, image, &error)) std::cerr << "navmap_ortho_bench: " << error << "\n";
        }
    }
}

void groundFrame(benchmark::State& state) {
    if (!haveOrthoStore(state)) return;
    const Profile& p = kProfiles[state.range(0)];
    const auto views = shots(p, 12);
    RendererOptions o;
    o.width = p.width;
    o.height = p.height;
    o.ortho_weights = NAVMAP_ORTHO_WEIGHTS;
    auto r = Renderer::create(o);
    std::size_t images = 0;
    for (Ground g : {Ground::LandCover, Ground::Orthoimage}) {  // upload every tile, make every image
        r->setMapStyle(styleWith(g));
        for (const auto& s : views) {
            r->renderMap(frameOf(p, s));
            images += r->mapStats().ortho_generated;
        }
    }
    r->finish();
    if (const char* dir = std::getenv("NAVMAP_BENCH_PICTURES")) writePictures(*r, p, views, dir);
    std::vector<double> cover_ms, ortho_ms;
    std::size_t i = 0;
    for (auto _ : state) {
        const MapFrame f = frameOf(p, views[i++ % views.size()]);
        for (Ground g : {Ground::LandCover, Ground::Orthoimage}) {
            r->setMapStyle(styleWith(g));
            const auto t0 = Clock::now();
            r->renderMap(f);
            r->finish();
            (g == Ground::LandCover ? cover_ms : ortho_ms)
                .push_back(std::chrono::duration<double, std::milli>(Clock::now() - t0).count());
        }
    }
    state.counters["landcover_p50_ms"] = percentile(cover_ms, 0.5);
    state.counters["orthoimage_p50_ms"] = percentile(ortho_ms, 0.5);
    state.counters["orthoimage_ratio"] =
        percentile(cover_ms, 0.5) > 0 ? percentile(ortho_ms, 0.5) / percentile(cover_ms, 0.5) : 0.0;
    state.counters["images"] = double(images);
    state.SetLabel(std::string(p.name) + (p.mode == ViewMode::Bird ? " bird" : " snail"));
}

void tileUpload(benchmark::State& state) {
    if (!haveOrthoStore(state)) return;
    const Profile& p = kProfiles[state.range(0)];
    const auto views = shots(p, 4);
    for (auto _ : state) {
        for (Ground g : {Ground::LandCover, Ground::Orthoimage}) {
            RendererOptions o;
            o.width = p.width;
            o.height = p.height;
            o.ortho_weights = NAVMAP_ORTHO_WEIGHTS;
            o.tile_resource_cache = 1;  // each camera uploads its own tiles
            o.profile_passes = true;
            auto r = Renderer::create(o);
            r->setMapStyle(styleWith(g));
            double upload_ms = 0, ortho_ms = 0;
            std::size_t tiles = 0, images = 0;
            for (const auto& s : views) {
                r->renderMap(frameOf(p, s));
                upload_ms += r->mapStats().uploads_ms;
                ortho_ms += r->mapStats().ortho_ms;
                tiles += r->mapStats().tiles_uploaded;
                images += r->mapStats().ortho_generated;
            }
            const std::string name = g == Ground::LandCover ? "landcover" : "orthoimage";
            state.counters[name + "_ms_per_tile"] = tiles ? upload_ms / double(tiles) : 0.0;
            state.counters[name + "_tiles"] = double(tiles);
            if (g == Ground::Orthoimage) {
                state.counters["images"] = double(images);
                state.counters["ortho_cpu_ms_per_image"] = images ? ortho_ms / double(images) : 0.0;
            }
        }
    }
    state.SetLabel(std::string(p.name) + (p.mode == ViewMode::Bird ? " bird" : " snail"));
}

void generationFrames(benchmark::State& state) {
    if (!haveOrthoStore(state)) return;
    const Profile& p = kProfiles[state.range(0)];
    const auto views = shots(p, 4);
    std::vector<double> ortho_ms, making_ms, made_ms;
    std::size_t frames = 0, images = 0;
    auto timed = [](Renderer& r, const MapFrame& f) {
        const auto t0 = Clock::now();
        r.renderMap(f);
        r.finish();
        return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
    };
    for (auto _ : state) {
        RendererOptions o;
        o.width = p.width;
        o.height = p.height;
        o.ortho_weights = NAVMAP_ORTHO_WEIGHTS;
        o.ortho_pixels_per_frame = 16384;  // navmapd's budget
        auto r = Renderer::create(o);
        r->setMapStyle(styleWith(Ground::Orthoimage));
        r->renderMap(frameOf(p, views[0]));  // the generator's creation: weights and shaders
        r->finish();
        for (const auto& s : views) {
            // The camera holds still until every image of its view is made, as after a jump.
            const MapFrame f = frameOf(p, s);
            for (int i = 0; i < 2000; ++i) {
                const double ms = timed(*r, f);
                const MapFrameStats& st = r->mapStats();
                images += st.ortho_generated;
                if (st.ortho_pending == 0 && st.ortho_generated == 0) break;
                making_ms.push_back(ms);
                ortho_ms.push_back(st.ortho_ms);
                ++frames;
            }
            for (int i = 0; i < 8; ++i) made_ms.push_back(timed(*r, f));
        }
    }
    state.counters["frame_ms_p50_making"] = percentile(making_ms, 0.5);
    state.counters["frame_ms_p95_making"] = percentile(making_ms, 0.95);
    state.counters["frame_ms_max_making"] = percentile(making_ms, 1.0);
    state.counters["frame_ms_p50_made"] = percentile(made_ms, 0.5);
    state.counters["render_thread_ms_p50"] = percentile(ortho_ms, 0.5);
    state.counters["render_thread_ms_p95"] = percentile(ortho_ms, 0.95);
    state.counters["frames_per_image"] = images ? double(frames) / double(images) : 0.0;
    state.counters["images"] = double(images);
    state.SetLabel(std::string(p.name) + (p.mode == ViewMode::Bird ? " bird" : " snail"));
}

BENCHMARK(mlpGpu)->Unit(benchmark::kMillisecond)->MinTime(2.0);
BENCHMARK(mlpCpu)->Unit(benchmark::kMillisecond)->MinTime(2.0);
BENCHMARK(encodeInputs)->Unit(benchmark::kMillisecond)->MinTime(2.0);
// Cluster (snail's view) and center (bird's-eye).
BENCHMARK(groundFrame)->Arg(0)->Arg(2)->Unit(benchmark::kMillisecond)->Iterations(24);
BENCHMARK(tileUpload)->Arg(0)->Arg(2)->Unit(benchmark::kMillisecond)->Iterations(1);
BENCHMARK(generationFrames)->Arg(0)->Arg(2)->Unit(benchmark::kMillisecond)->Iterations(1);

}  // namespace

int main(int argc, char** argv) {
    if (!std::filesystem::exists(mo::kDebianMarbleData / "maps/earth/temp-dec/temp-dec.jpg")) {
        std::cerr << "navmap_ortho_bench: " << mo::kDebianMarbleData.string()
                  << " is absent (Debian package marble-qt-data, scripts/install-deps.sh)\n";
        return 1;
    }
    benchmark::Initialize(&argc, argv);
    if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
    benchmark::RunSpecifiedBenchmarks();
    benchmark::Shutdown();
    return 0;
}
