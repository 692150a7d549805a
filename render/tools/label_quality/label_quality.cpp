#include "label_quality.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <memory>
#include <stdexcept>
#include <vector>

#include "navmap/render/map_view.h"
#include "navmap/render/renderer.h"

namespace navmap::render::tools {

namespace {

using Clock = std::chrono::steady_clock;

std::string fmt(const char* f, double v) {
    char buf[64];
    std::snprintf(buf, sizeof buf, f, v);
    return buf;
}

}  // namespace

LabelQualityReport measureLabelQuality(const LabelQualityOptions& o) {
    if (o.width <= 0 || o.height <= 0 || o.frames <= 0 || o.settle_frames < 0 || !(o.dt_s > 0.0)) {
        throw std::runtime_error("label quality: width, height, frames and dt must be positive");
    }
    DriveScene scene = DriveScene::open(o.store, o.from, o.to);
    MapView& view = *scene.view;
    PlannedDrive& drive = scene.drive;
    if (drive.line.size() < 2) throw std::runtime_error("label quality: no route between the two places in " + o.store.string());
    const auto terrain = [&](double x, double y) { return view.terrainHeight(x, y); };
    const double aspect = static_cast<double>(o.width) / o.height;
    const double route_end = drive.line.back().measure_m;

    RendererOptions ro;
    ro.width = o.width;
    ro.height = o.height;
    auto renderer = Renderer::create(ro);
    CameraRig rig;
    rig.setMode(o.view);

    // Settle the camera and load the tiles around the start (terrain heights need tiles).
    const DriveScene::Shot shot = scene.settle(rig, o.start_m, o.speed_mps, aspect, o.height);
    VehiclePose pose = shot.pose;
    Camera cam = shot.camera;

    LabelQualityReport r;
    r.view = o.view == ViewMode::Bird ? "bird" : "snail";
    r.route_points = drive.line.size();
    labels::LayoutMetrics metrics;
    std::vector<double> label_ms;
    double frame_ms = 0.0, candidates = 0.0;
    double measure = o.start_m;
    const int total = o.settle_frames + o.frames;
    for (int i = 0; i < total; ++i) {
        measure = std::min(measure + o.speed_mps * o.dt_s, route_end);
        pose = poseAlong(drive, measure, o.speed_mps, terrain);
        cam = rig.update(pose, o.dt_s, terrain);
        // Deterministic replay: wait for the tiles of each frame instead of drawing parents.
        view.warmUp(cam, aspect, o.height, std::chrono::seconds(10));
        MapFrame frame;
        frame.camera = cam;
        frame.tiles = view.tilesFor(cam, aspect, o.height);
        frame.route = &drive.geometry;
        frame.route_progress_m = measure;
        frame.marker = MarkerState{pose.position, pose.heading_deg, false};
        frame.layers.labels = true;
        frame.frame_dt_s = o.dt_s;
        const auto t0 = Clock::now();
        renderer->renderMap(frame);
        renderer->finish();
        const double ms = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
        if (i < o.settle_frames) continue;
        const MapFrameStats& s = renderer->mapStats();
        metrics.addFrame(s.placed_labels, o.dt_s);
        if (labels::LayoutMetrics::countOverlaps(s.placed_labels) > 0) ++r.overlap_frames;
        label_ms.push_back(s.labels_ms);
        frame_ms += ms;
        candidates += static_cast<double>(s.label_candidates);
        r.world_weight_last = s.label_world_weight;
    }
    r.quality = metrics.summary();
    const auto n = static_cast<double>(o.frames);
    r.mean_frame_ms = frame_ms / n;
    r.mean_candidates = candidates / n;
    double sum = 0.0;
    for (double v : label_ms) sum += v;
    r.mean_labels_ms = sum / n;
    std::sort(label_ms.begin(), label_ms.end());
    r.p95_labels_ms = label_ms[std::min(label_ms.size() - 1, static_cast<std::size_t>(0.95 * n))];
    return r;
}

std::string toJson(const LabelQualityReport& r) {
    const labels::LayoutQuality& q = r.quality;
    std::string s = "{\"view\": \"" + r.view + "\"";
    s += ", \"frames\": " + std::to_string(q.frames);
    s += ", \"seconds\": " + fmt("%.3f", q.seconds);
    s += ", \"mean_visible\": " + fmt("%.2f", q.mean_visible);
    s += ", \"last_visible\": " + std::to_string(q.last_visible);
    s += ", \"max_overlaps\": " + std::to_string(q.max_overlaps);
    s += ", \"overlap_frames\": " + std::to_string(r.overlap_frames);
    s += ", \"pops\": " + std::to_string(q.pops);
    s += ", \"pops_per_s\": " + fmt("%.3f", q.pops_per_s);
    s += ", \"mean_jitter_px\": " + fmt("%.4f", q.mean_jitter_px);
    s += ", \"p95_jitter_px\": " + fmt("%.3f", q.p95_jitter_px);
    s += ", \"jitter_samples\": " + std::to_string(q.jitter_samples);
    s += ", \"mean_candidates\": " + fmt("%.1f", r.mean_candidates);
    s += ", \"mean_labels_ms\": " + fmt("%.3f", r.mean_labels_ms);
    s += ", \"p95_labels_ms\": " + fmt("%.3f", r.p95_labels_ms);
    s += ", \"mean_frame_ms\": " + fmt("%.3f", r.mean_frame_ms);
    s += ", \"label_world_weight\": " + fmt("%.3f", r.world_weight_last);
    s += "}";
    return s;
}

}  // namespace navmap::render::tools
