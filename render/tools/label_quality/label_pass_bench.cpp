// SPDX-License-Identifier: Apache-2.0
// Text rendering cost per frame for the cluster view (issue 4 benchmark): the default cluster
// profile (1280x480, snail's view) on the Andorra store, settled at Escaldes, one map frame
// with and without labels. Counters: labels_ms (CPU time of the label pass: collect, layout,
// shaping/layout of the text, draw submission), labels, glyphs. Prints JSON with
// --benchmark_format=json.
#include <benchmark/benchmark.h>

#include <chrono>
#include <memory>

#include "drive_scene.h"
#include "navmap/render/renderer.h"

namespace {

using namespace navmap::render;
using navmap::test::DriveScene;

constexpr int kW = 1280, kH = 480;

struct Cluster {
    DriveScene d;
    MapFrame frame;
};

Cluster& cluster() {
    static Cluster c = [] {
        Cluster x{DriveScene::open(NAVMAP_DEFAULT_STORE, navmap::test::kAndorraLaVella, navmap::test::kEncamp), {}};
        auto& view = x.d.view;
        CameraRig rig;
        rig.setMode(ViewMode::Snail);
        const auto shot = x.d.settle(rig, 1800.0, 13.0, double(kW) / kH, kH);
        const Camera& cam = shot.camera;
        const VehiclePose& pose = shot.pose;
        x.frame.camera = cam;
        x.frame.tiles = view->tilesFor(cam, double(kW) / kH, kH);
        x.frame.route_progress_m = 1800.0;
        x.frame.marker = MarkerState{pose.position, pose.heading_deg, false};
        x.frame.frame_dt_s = 1.0 / 30.0;
        return x;
    }();
    c.frame.route = &c.d.drive.geometry;  // after the move into the static: the address is final
    return c;
}

void BM_ClusterFrame(benchmark::State& state) {
    Cluster& c = cluster();
    RendererOptions o;
    o.width = kW;
    o.height = kH;
    auto renderer = Renderer::create(o);
    MapFrame frame = c.frame;
    frame.layers.labels = state.range(0) != 0;
    for (int i = 0; i < 60; ++i) renderer->renderMap(frame);  // tiles uploaded, labels settled
    renderer->finish();
    double labels_ms = 0;
    for (auto _ : state) {
        renderer->renderMap(frame);
        renderer->finish();
        labels_ms += renderer->mapStats().labels_ms;
    }
    const MapFrameStats& s = renderer->mapStats();
    state.counters["labels_ms"] = labels_ms / static_cast<double>(state.iterations());
    state.counters["labels"] = static_cast<double>(s.labels_visible);
    state.counters["candidates"] = static_cast<double>(s.label_candidates);
    state.counters["glyphs"] = static_cast<double>(s.label_glyphs);
}
BENCHMARK(BM_ClusterFrame)->ArgName("labels")->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
