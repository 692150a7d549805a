#pragma once
// Label quality of a replayed drive (issue 4, "measured quality"): drives a camera rig along a
// route on a tile store through the renderer and measures the label layout per view with
// labels::LayoutMetrics: visible labels, overlapping visible labels after settling, pops per
// second and jitter relative to the anchor. Used by navmap-label-quality and its gpu test.
#include <cstdint>
#include <filesystem>
#include <string>

#include "navmap/render/camera_rig.h"
#include "navmap/render/labels/layout_metrics.h"
#include "navmap/render/map_scene.h"

namespace navmap::render::tools {

struct LabelQualityOptions {
    std::filesystem::path store;                 ///< compiled tile store (build/andorra.navmap)
    GeoPoint from = kAndorraLaVella;
    GeoPoint to = kEncamp;
    ViewMode view = ViewMode::Bird;
    int width = 1280;
    int height = 480;
    int frames = 300;              ///< frames measured (after the settling frames)
    int settle_frames = 90;        ///< frames rendered before measuring (labels fade in, layout settles)
    double dt_s = 1.0 / 30.0;      ///< fixed frame time
    double start_m = 1800.0;       ///< distance along the route where the drive starts
    double speed_mps = 13.0;
};

struct LabelQualityReport {
    std::string view;                 ///< "bird" or "snail"
    labels::LayoutQuality quality;    ///< over the measured frames
    std::size_t overlap_frames = 0;   ///< measured frames with at least one overlapping visible pair
    double mean_candidates = 0;
    double mean_labels_ms = 0;        ///< CPU time of the label pass per frame
    double p95_labels_ms = 0;
    double mean_frame_ms = 0;         ///< renderMap + finish per frame
    double world_weight_last = 0;     ///< 0 screen-space labels, 1 world-space
    std::size_t route_points = 0;
};

/// Throws std::runtime_error when the store cannot be opened, no route exists, or the GL
/// backend is unusable (render::RenderError).
LabelQualityReport measureLabelQuality(const LabelQualityOptions& options);

/// One JSON object (no trailing newline).
std::string toJson(const LabelQualityReport& report);

}  // namespace navmap::render::tools
