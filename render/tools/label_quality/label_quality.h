// SPDX-License-Identifier: Apache-2.0
#pragma once
// Label quality of a replayed drive (docs/labels.md "Measured quality"): renders a drive frame by
// frame through the renderer and measures what was drawn with labels::DrawnLabelMetrics (visible
// labels, overlapping glyphs, occluded and too-small labels, labels over the marker, pops as
// MapLibre's placement counts them, jitter), the layout's own figures with labels::LayoutMetrics
// (reported as layout_*), and the frame time. Two drives: a recorded trajectory of poses
// (data/drives/*-trajectory.json) with a MapLibre-convention camera, or a route planned on the
// store with the camera rig (bird's-eye, snail's view or a MapLibre follow camera). Used by
// navmap-label-quality and its gpu test.
#include <cstdint>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>

#include "drawn_label_metrics.h"
#include "drive_scene.h"
#include "layout_metrics.h"
#include "navmap/render/camera_rig.h"
#include "navmap/render/map_frame.h"
#include "pop_causes.h"

namespace navmap::render::tools {

struct LabelQualityOptions {
    std::filesystem::path store;  ///< compiled tile store (build/andorra.navmap)
    /// A trajectory file to replay pose by pose (needs `camera`); empty: drive the route from -> to.
    std::filesystem::path trajectory;
    /// MapLibre-convention camera centred on the vehicle (bearing: the pose's unless fixed). For a
    /// route drive it puts the rig in its MapLibre follow mode instead of `view`.
    std::optional<MapLibreFollow> camera;
    navmap::GeoCoordinate from = navmap::test::kAndorraLaVella;
    navmap::GeoCoordinate to = navmap::test::kEncamp;
    ViewMode view = ViewMode::Bird;
    int width = 1280;
    int height = 480;
    /// Frames measured (after the settling frames); empty: 300 on a route, every pose of a trajectory.
    std::optional<int> frames;
    /// Frames rendered before measuring (labels fade in, the layout settles); a trajectory holds its
    /// first pose meanwhile.
    int settle_frames = 90;
    double dt_s = 1.0 / 30.0;       ///< fixed frame time
    double start_m = 1800.0;        ///< route: distance along the route where the drive starts
    double speed_mps = 13.0;        ///< route: speed
    bool measure_occlusion = true;  ///< MapLayers::measure_label_occlusion
    bool label_aura = false;        ///< MapLayers::label_aura
    bool glow_roads = false;        ///< MapLayers::glow_roads
    /// Called after each measured frame with its index (0 = first measured) and its stats.
    std::function<void(int frame, const MapFrameStats& stats)> on_frame;
};

/// Percentiles of a per-frame time, ms (nearest rank).
struct TimeFigures {
    double p50 = 0, p95 = 0, mean = 0;
};

struct LabelQualityReport {
    std::string name;   ///< "bird", "snail" or "zoom=16.5,pitch=60"
    std::string drive;  ///< "route" or the trajectory file's name
    int width = 0, height = 0;
    int settle_frames = 0;
    double dt_s = 0;
    std::optional<MapLibreFollow> camera;
    double camera_distance_m = 0;        ///< eye to look-at point in the first measured frame
    labels::DrawnLabelQuality drawn;     ///< over the measured frames, on the drawn labels
    labels::PopCauseFigures pop_causes;  ///< the drawn pops by cause, and their floor
    /// The layout output's figures (LayoutMetrics on the layout boxes, not what is drawn),
    /// reported as layout_*.
    labels::LayoutQuality quality;
    std::size_t overlap_frames = 0;  ///< measured frames with overlapping layout boxes (layout_overlap_frames)
    double mean_candidates = 0;
    TimeFigures labels_ms;  ///< CPU time of the label pass per frame
    /// renderMap + finish per frame, labels on, without the occlusion measurement's own time.
    TimeFigures frame_ms;
    double mean_label_occlusion_ms = 0;  ///< the measurement's time per frame (left out of frame_ms)
    double world_weight_last = 0;        ///< 0 screen-space labels, 1 world-space
    std::size_t route_points = 0;        ///< route drive: points of the planned route
    /// The layout's events over the measured frames: placements and removals by reason.
    struct LayoutEvents {
        std::uint64_t placed = 0, removed_speed = 0, removed_constricted = 0, removed_overlap = 0,
                      removed_off_screen = 0, removed_gone = 0;
        std::uint64_t removed_keep_out = 0;  ///< of removed_overlap: over a keep-out area
        /// Placement attempts that found no free candidate: all outside the viewport, one blocked
        /// by a keep-out area (marker, route), only blocked by other labels.
        std::uint64_t failures_off_screen = 0, failures_keep_out = 0, failures_labels = 0;
    } layout_events;
};

/// Throws std::runtime_error when the store or the trajectory cannot be opened (TrajectoryError
/// names the file and the problem), no route exists, the options are inconsistent, or the GL
/// backend is unusable (render::RenderError).
LabelQualityReport measureLabelQuality(const LabelQualityOptions& options);

/// One JSON object (no trailing newline).
std::string toJson(const LabelQualityReport& report);

/// "zoom=16.5,pitch=60[,bearing=90]" -> camera; std::nullopt and `error` set when malformed or out
/// of range (zoom 0..24, pitch 0..85, bearing -360..360).
std::optional<MapLibreFollow> parseCameraSpec(const std::string& spec, std::string* error);
/// The inverse, shortest decimal form ("zoom=16.5,pitch=60").
std::string cameraSpecName(const MapLibreFollow& camera);

}  // namespace navmap::render::tools
