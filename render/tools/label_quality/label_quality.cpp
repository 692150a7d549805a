// SPDX-License-Identifier: Apache-2.0
#include "label_quality.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <optional>
#include <stdexcept>
#include <vector>

#include <nlohmann/json.hpp>

#include "drive_trajectory.h"
#include "navmap/map/map_scene.h"
#include "navmap/render/map_view.h"
#include "navmap/render/maplibre_camera.h"
#include "navmap/render/renderer.h"

namespace navmap::render::tools {

namespace {

using Clock = std::chrono::steady_clock;

// Nearest-rank percentiles and the mean.
TimeFigures figuresOf(std::vector<double> v) {
    TimeFigures f;
    if (v.empty()) return f;
    std::sort(v.begin(), v.end());
    auto rank = [&](double p) {
        const auto r = static_cast<std::size_t>(std::ceil(p * static_cast<double>(v.size())));
        return v[std::clamp<std::size_t>(r, 1, v.size()) - 1];
    };
    f.p50 = rank(0.50);
    f.p95 = rank(0.95);
    double sum = 0.0;
    for (const double x : v) sum += x;
    f.mean = sum / static_cast<double>(v.size());
    return f;
}

std::string shortest(double v) {
    char buf[64];
    std::snprintf(buf, sizeof buf, "%g", v);
    return buf;
}

// Renders one frame and returns renderMap + finish in ms.
double renderTimed(Renderer& renderer, const MapFrame& frame) {
    const auto t0 = Clock::now();
    renderer.renderMap(frame);
    renderer.finish();
    return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

// One measured frame's figures, accumulated.
struct Accumulator {
    labels::DrawnLabelMetrics drawn;
    labels::LayoutMetrics layout;
    labels::PopCauses causes;
    std::vector<double> labels_ms, frame_ms;
    double occlusion_ms = 0.0, candidates = 0.0;
    std::optional<labels::LayoutStats> first_layout;

    void add(const MapFrameStats& s, glm::vec2 viewport, double dt, double render_ms, LabelQualityReport& r) {
        if (!first_layout) first_layout = s.label_layout;
        // The layout's events over the measured frames (what makes labels come and go).
        const labels::LayoutStats& a = *first_layout;
        const labels::LayoutStats& b = s.label_layout;
        r.layout_events = {b.placed - a.placed,
                           b.removed_speed - a.removed_speed,
                           b.removed_constricted - a.removed_constricted,
                           b.removed_overlap - a.removed_overlap,
                           b.removed_off_screen - a.removed_off_screen,
                           b.removed_gone - a.removed_gone,
                           b.removed_keep_out - a.removed_keep_out,
                           b.failures_off_screen - a.failures_off_screen,
                           b.failures_keep_out - a.failures_keep_out,
                           b.failures_labels - a.failures_labels};
        drawn.addFrame(s.drawn_labels, s.drawn_marker, viewport, dt);
        layout.addFrame(s.placed_labels, dt);
        if (labels::LayoutMetrics::countOverlaps(s.placed_labels) > 0) ++r.overlap_frames;
        labels_ms.push_back(s.labels_ms);
        frame_ms.push_back(render_ms - s.label_occlusion_ms);
        occlusion_ms += s.label_occlusion_ms;
        candidates += static_cast<double>(s.label_candidates);
        r.world_weight_last = s.label_world_weight;
    }
    /// Renders one frame; the measured ones (i >= 0, after the settling frames) go into `r`.
    void frame(int i, Renderer& renderer, const MapFrame& frame, glm::vec2 viewport, const LabelQualityOptions& o,
               LabelQualityReport& r) {
        const double ms = renderTimed(renderer, frame);
        const MapFrameStats& st = renderer.mapStats();
        causes.addFrame(st.drawn_labels, st.placed_labels, st.label_input_changes, viewport, i >= 0);
        if (i < 0) return;
        if (i == 0) r.camera_distance_m = glm::length(frame.camera.target - frame.camera.eye);
        const MapFrameStats& s = renderer.mapStats();
        add(s, viewport, o.dt_s, ms, r);
        if (o.on_frame) o.on_frame(i, s);
    }

    void finish(LabelQualityReport& r) const {
        r.drawn = drawn.summary();
        r.pop_causes = causes.summary();
        r.quality = layout.summary();
        const auto n = static_cast<double>(std::max<std::size_t>(frame_ms.size(), 1));
        r.mean_candidates = candidates / n;
        r.mean_label_occlusion_ms = occlusion_ms / n;
        r.labels_ms = figuresOf(labels_ms);
        r.frame_ms = figuresOf(frame_ms);
    }
};

void applyLayers(MapFrame& frame, const LabelQualityOptions& o) {
    frame.layers.labels = true;
    frame.layers.measure_label_occlusion = o.measure_occlusion;
    frame.layers.label_aura = o.label_aura;
    frame.layers.glow_roads = o.glow_roads;
    frame.frame_dt_s = o.dt_s;
}

std::unique_ptr<Renderer> makeRenderer(const LabelQualityOptions& o) {
    RendererOptions ro;
    ro.width = o.width;
    ro.height = o.height;
    return Renderer::create(ro);
}

// A recorded trajectory, pose by pose, each frame's camera in MapLibre's convention centred on
// the vehicle (MapLibre GL JS was measured on the same poses this way).
LabelQualityReport replayTrajectory(const LabelQualityOptions& o, LabelQualityReport r) {
    const DriveTrajectory trajectory = loadTrajectory(o.trajectory);
    const int available = static_cast<int>(trajectory.frames.size());
    const int frames = std::min(o.frames.value_or(available), available);
    map::MapScene scene = map::MapScene::open(o.store);
    MapView view(scene.cache);
    const map::Projection projection = scene.projection();
    const auto terrain = [&](double x, double y) { return view.terrainHeight(x, y); };
    const double aspect = static_cast<double>(o.width) / o.height;
    const glm::vec2 viewport(static_cast<float>(o.width), static_cast<float>(o.height));
    auto renderer = makeRenderer(o);
    Accumulator acc;
    for (int i = -o.settle_frames; i < frames; ++i) {
        const TrajectoryPose& pose = trajectory.frames[static_cast<std::size_t>(std::max(i, 0))];
        MapLibreCamera ml;
        ml.center = pose.position;
        ml.zoom = o.camera->zoom;
        ml.pitch_deg = o.camera->pitch_deg;
        ml.bearing_deg = o.camera->bearing_deg.value_or(pose.bearing_deg);
        // Deterministic replay: wait for the tiles of each frame instead of drawing parents; the
        // second round sees the terrain height under the center the first one loaded.
        Camera cam = cameraFromMapLibre(ml, projection, o.height, terrain);
        view.warmUp(cam, aspect, o.height, std::chrono::seconds(10));
        cam = cameraFromMapLibre(ml, projection, o.height, terrain);
        view.warmUp(cam, aspect, o.height, std::chrono::seconds(10));
        MapFrame frame;
        frame.camera = cam;
        view.select(frame, aspect, o.height);  // tiles and their geomorph, as navmapd draws them
        frame.marker = MarkerState{
            cam.target, gridBearingDeg(projection, pose.position.lat_deg, pose.position.lon_deg, pose.bearing_deg),
            false};
        applyLayers(frame, o);
        acc.frame(i, *renderer, frame, viewport, o, r);
    }
    acc.finish(r);
    return r;
}

// The route from -> to planned on the store, driven at a constant speed with the camera rig.
LabelQualityReport driveRoute(const LabelQualityOptions& o, LabelQualityReport r) {
    const int frames = o.frames.value_or(300);
    navmap::test::DriveScene scene = navmap::test::DriveScene::open(o.store, o.from, o.to);
    MapView& view = *scene.view;
    navmap::test::PlannedDrive& drive = scene.drive;
    if (drive.line.size() < 2)
        throw std::runtime_error("label quality: no route between the two places in " + o.store.string());
    const auto terrain = [&](double x, double y) { return view.terrainHeight(x, y); };
    const double aspect = static_cast<double>(o.width) / o.height;
    const glm::vec2 viewport(static_cast<float>(o.width), static_cast<float>(o.height));
    const double route_end = drive.line.back().measure_m;
    auto renderer = makeRenderer(o);
    CameraRig rig;
    rig.setMode(o.view);
    if (o.camera) rig.setMapLibreFollow(*o.camera, scene.scene.projection(), o.height);

    // Settle the camera and load the tiles around the start (terrain heights need tiles).
    const navmap::test::DriveScene::Shot shot = scene.settle(rig, o.start_m, o.speed_mps, aspect, o.height);
    VehiclePose pose = shot.pose;
    r.route_points = drive.line.size();
    Accumulator acc;
    double measure = o.start_m;
    for (int i = -o.settle_frames; i < frames; ++i) {
        measure = std::min(measure + o.speed_mps * o.dt_s, route_end);
        pose = navmap::test::poseAlong(drive, measure, o.speed_mps, terrain);
        const Camera cam = rig.update(pose, o.dt_s, terrain);
        // Deterministic replay: wait for the tiles of each frame instead of drawing parents.
        view.warmUp(cam, aspect, o.height, std::chrono::seconds(10));
        MapFrame frame;
        frame.camera = cam;
        frame.tiles = view.tilesFor(cam, aspect, o.height);
        frame.route = &drive.geometry;
        frame.route_progress_m = measure;
        frame.marker = MarkerState{pose.position, pose.heading_deg, false};
        applyLayers(frame, o);
        acc.frame(i, *renderer, frame, viewport, o, r);
    }
    acc.finish(r);
    return r;
}

double rounded(double v, int digits) {
    const double f = std::pow(10.0, digits);
    return std::round(v * f) / f;
}

}  // namespace

std::optional<MapLibreFollow> parseCameraSpec(const std::string& spec, std::string* error) {
    std::string local;
    std::string& err = error ? *error : local;
    std::optional<double> zoom, pitch, bearing;
    std::size_t begin = 0;
    while (begin <= spec.size()) {
        const std::size_t end = std::min(spec.find(',', begin), spec.size());
        const std::string item = spec.substr(begin, end - begin);
        begin = end + 1;
        const std::size_t eq = item.find('=');
        const std::string key = item.substr(0, eq);
        std::optional<double>* slot = key == "zoom"      ? &zoom
                                      : key == "pitch"   ? &pitch
                                      : key == "bearing" ? &bearing
                                                         : nullptr;
        if (eq == std::string::npos || !slot) {
            err = "camera \"" + spec + "\": expected zoom=Z,pitch=P[,bearing=B], not \"" + item + "\"";
            return std::nullopt;
        }
        const std::string text = item.substr(eq + 1);
        char* stop = nullptr;
        const double v = std::strtod(text.c_str(), &stop);
        if (text.empty() || *stop != '\0' || !std::isfinite(v)) {
            err = "camera \"" + spec + "\": " + key + " must be a number, not \"" + text + "\"";
            return std::nullopt;
        }
        if (slot->has_value()) {
            err = "camera \"" + spec + "\": " + key + " given twice";
            return std::nullopt;
        }
        *slot = v;
    }
    if (!zoom || !pitch) {
        err = "camera \"" + spec + "\": needs zoom and pitch (zoom=Z,pitch=P[,bearing=B])";
        return std::nullopt;
    }
    auto range = [&](const char* name, double v, double lo, double hi) {
        if (v >= lo && v <= hi) return true;
        err = "camera \"" + spec + "\": " + name + " " + shortest(v) + " out of range [" + shortest(lo) + ", " +
              shortest(hi) + "]";
        return false;
    };
    if (!range("zoom", *zoom, kMapLibreMinZoom, kMapLibreMaxZoom) ||
        !range("pitch", *pitch, kMapLibreMinPitchDeg, kMapLibreMaxPitchDeg) ||
        (bearing && !range("bearing", *bearing, -360.0, 360.0))) {
        return std::nullopt;
    }
    return MapLibreFollow{*zoom, *pitch, bearing};
}

std::string cameraSpecName(const MapLibreFollow& c) {
    std::string s = "zoom=" + shortest(c.zoom) + ",pitch=" + shortest(c.pitch_deg);
    if (c.bearing_deg) s += ",bearing=" + shortest(*c.bearing_deg);
    return s;
}

LabelQualityReport measureLabelQuality(const LabelQualityOptions& o) {
    if (o.width <= 0 || o.height <= 0 || (o.frames && *o.frames <= 0) || o.settle_frames < 0 || !(o.dt_s > 0.0)) {
        throw std::runtime_error("label quality: width, height, frames and dt must be positive, settle not negative");
    }
    if (!o.trajectory.empty() && !o.camera) {
        throw std::runtime_error("label quality: replaying a trajectory needs a camera (zoom and pitch)");
    }
    LabelQualityReport r;
    r.width = o.width;
    r.height = o.height;
    r.settle_frames = o.settle_frames;
    r.dt_s = o.dt_s;
    r.camera = o.camera;
    r.name = o.camera ? cameraSpecName(*o.camera) : o.view == ViewMode::Bird ? "bird" : "snail";
    if (!o.trajectory.empty()) {
        r.drive = o.trajectory.filename().string();
        return replayTrajectory(o, std::move(r));
    }
    r.drive = "route";
    return driveRoute(o, std::move(r));
}

std::string toJson(const LabelQualityReport& r) {
    const labels::DrawnLabelQuality& q = r.drawn;
    const labels::LayoutQuality& l = r.quality;
    nlohmann::ordered_json j;
    j["name"] = r.name;
    j["drive"] = r.drive;
    if (r.camera) {
        j["zoom"] = r.camera->zoom;
        j["pitch"] = r.camera->pitch_deg;
        if (r.camera->bearing_deg) j["bearing"] = *r.camera->bearing_deg;
    }
    j["size"] = std::to_string(r.width) + "x" + std::to_string(r.height);
    j["camera_distance_m"] = rounded(r.camera_distance_m, 1);
    j["settle_frames"] = r.settle_frames;
    j["frames"] = q.frames;
    j["seconds"] = rounded(q.seconds, 3);
    // On the drawn frames (docs/labels.md "Measured quality").
    j["visible_median"] = q.visible_median;
    j["visible_mean"] = rounded(q.visible_mean, 2);
    j["visible_min"] = q.visible_min;
    j["visible_max"] = q.visible_max;
    j["distinct_visible_labels"] = q.distinct_visible_labels;
    j["overlap_pairs_max"] = q.overlap_pairs_max;
    j["overlap_pairs_sum"] = q.overlap_pairs_sum;
    j["overlap_frames"] = q.overlap_frames;
    j["occluded_share"] = rounded(q.occluded_share, 4);
    j["occluded_label_frames"] = q.occluded_label_frames;
    j["occlusion_measured_label_frames"] = q.occlusion_measured_label_frames;
    j["occlusion_unmeasured_label_frames"] = q.occlusion_unmeasured_label_frames;
    j["too_small_share"] = rounded(q.too_small_share, 4);
    j["too_small_label_frames"] = q.too_small_label_frames;
    j["too_small_labels"] = q.too_small_labels;
    j["marker_overlap_label_frames"] = q.marker_overlap_label_frames;
    j["marker_overlap_frames"] = q.marker_overlap_frames;
    j["marker_overlap_labels"] = q.marker_overlap_labels;
    j["marker_frames"] = q.marker_frames;
    j["pops"] = q.pops;
    j["pops_per_s"] = rounded(q.pops_per_s, 3);
    j["interior_point_pops"] = q.interior_point_pops;
    j["interior_point_pops_per_s"] = rounded(q.interior_point_pops_per_s, 3);
    j["text_pops"] = q.text_pops;
    j["text_pops_per_s"] = rounded(q.text_pops_per_s, 3);
    // The pops by cause (docs/labels.md "Pops by cause") and the floor no layout avoids.
    const labels::PopCauseFigures& pc = r.pop_causes;
    j["pop_enters"] = pc.enters;
    j["pop_leaves"] = pc.leaves;
    for (std::size_t c = 0; c < labels::kPopCauses; ++c) {
        j[std::string("pops_") + labels::popCauseName(static_cast<labels::PopCause>(c))] = pc.pops[c];
    }
    for (std::size_t c = 0; c < labels::kPopCauses; ++c) {
        j[std::string("interior_point_pops_") + labels::popCauseName(static_cast<labels::PopCause>(c))] =
            pc.interior_point_pops[c];
    }
    j["pop_floor"] = pc.floor;
    j["pop_floor_per_s"] = rounded(q.seconds > 0.0 ? static_cast<double>(pc.floor) / q.seconds : 0.0, 3);
    j["visible_runs"] = pc.visible_runs;
    j["frames_with_pop"] = q.frames_with_pop;
    j["pop_frame_share"] = rounded(q.pop_frame_share, 4);
    j["jitter_mean_px"] = rounded(q.jitter_mean_px, 4);
    j["jitter_p95_px"] = rounded(q.jitter_p95_px, 3);
    j["jitter_max_px"] = rounded(q.jitter_max_px, 2);
    j["jitter_samples"] = q.jitter_samples;
    j["duplicate_ids"] = q.duplicate_ids;
    // Frame time (labels on, with terrain) without the occlusion measurement.
    j["frame_ms_p50"] = rounded(r.frame_ms.p50, 2);
    j["frame_ms_p95"] = rounded(r.frame_ms.p95, 2);
    j["frame_ms_mean"] = rounded(r.frame_ms.mean, 2);
    j["label_occlusion_ms_mean"] = rounded(r.mean_label_occlusion_ms, 2);
    j["labels_ms_p50"] = rounded(r.labels_ms.p50, 3);
    j["labels_ms_p95"] = rounded(r.labels_ms.p95, 3);
    j["labels_ms_mean"] = rounded(r.labels_ms.mean, 3);
    j["mean_candidates"] = rounded(r.mean_candidates, 1);
    j["label_world_weight"] = rounded(r.world_weight_last, 3);
    // The layout's own figures (labels::LayoutMetrics on its boxes), not what is drawn.
    j["layout_mean_visible"] = rounded(l.mean_visible, 2);
    j["layout_last_visible"] = l.last_visible;
    j["layout_max_overlaps"] = l.max_overlaps;
    j["layout_overlap_frames"] = r.overlap_frames;
    j["layout_pops"] = l.pops;
    j["layout_pops_per_s"] = rounded(l.pops_per_s, 3);
    j["layout_mean_jitter_px"] = rounded(l.mean_jitter_px, 4);
    j["layout_p95_jitter_px"] = rounded(l.p95_jitter_px, 3);
    j["layout_jitter_samples"] = l.jitter_samples;
    j["layout_placed"] = r.layout_events.placed;
    j["layout_removed_speed"] = r.layout_events.removed_speed;
    j["layout_removed_constricted"] = r.layout_events.removed_constricted;
    j["layout_removed_overlap"] = r.layout_events.removed_overlap;
    j["layout_removed_off_screen"] = r.layout_events.removed_off_screen;
    j["layout_removed_gone"] = r.layout_events.removed_gone;
    j["layout_removed_keep_out"] = r.layout_events.removed_keep_out;
    j["layout_unplaced_off_screen"] = r.layout_events.failures_off_screen;
    j["layout_unplaced_keep_out"] = r.layout_events.failures_keep_out;
    j["layout_unplaced_labels"] = r.layout_events.failures_labels;
    if (r.drive == "route") j["route_points"] = r.route_points;
    return j.dump();
}

}  // namespace navmap::render::tools
