// SPDX-License-Identifier: Apache-2.0
// The label quality report of a replayed trajectory (navmap-label-quality's library): the first
// 90 frames of data/drives/andorra-urban-trajectory.json with the two MapLibre-convention cameras
// it was measured with elsewhere. Checks that the report is complete and consistent with the
// drawn frames, and that a pop forced into those frames is counted; the quality aims themselves
// are not asserted here.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "drawn_label_metrics.h"
#include "drive_trajectory.h"
#include "label_quality.h"
#include "navmap/render/maplibre_camera.h"
#include "pop_causes.h"
#include "test_paths.h"

namespace {

using namespace navmap::render;
namespace nl = navmap::render::labels;
namespace nt = navmap::render::tools;

constexpr int kFrames = 90;
constexpr int kW = 1280, kH = 480;

struct DrawnFrame {
    std::vector<nl::DrawnLabel> labels;
    nl::DrawnMarker marker;
};

nl::DrawnLabelQuality measure(const std::vector<DrawnFrame>& frames, double dt) {
    nl::DrawnLabelMetrics m;
    for (const DrawnFrame& f : frames) m.addFrame(f.labels, f.marker, glm::vec2(kW, kH), dt);
    return m.summary();
}

bool visibleIn(const DrawnFrame& f, std::uint64_t id) {
    return std::any_of(f.labels.begin(), f.labels.end(),
                       [&](const nl::DrawnLabel& l) { return l.id == id && l.opacity >= 0.5F; });
}

class TrajectoryQuality : public ::testing::TestWithParam<MapLibreFollow> {};

TEST_P(TrajectoryQuality, ReportIsCompleteAndCountsAForcedPop) {
    nt::LabelQualityOptions o;
    o.store = navmap::test::binaryDir() / "andorra.navmap";
    o.trajectory = navmap::test::dataDir() / "drives" / "andorra-urban-trajectory.json";
    o.camera = GetParam();
    o.frames = kFrames;
    o.settle_frames = 30;
    std::vector<DrawnFrame> frames;
    int last_index = -1;
    bool indices_in_order = true;
    o.on_frame = [&](int i, const MapFrameStats& s) {
        indices_in_order = indices_in_order && i == last_index + 1;
        last_index = i;
        frames.push_back({s.drawn_labels, s.drawn_marker});
    };
    const nt::LabelQualityReport r = nt::measureLabelQuality(o);
    const std::string json = nt::toJson(r);
    std::printf("%s\n", json.c_str());

    // Every measured frame reached the caller, in order.
    ASSERT_EQ(frames.size(), static_cast<std::size_t>(kFrames));
    EXPECT_TRUE(indices_in_order);
    const nl::DrawnLabelQuality& q = r.drawn;
    EXPECT_EQ(q.frames, static_cast<std::uint64_t>(kFrames));
    EXPECT_NEAR(q.seconds, kFrames / 30.0, 1e-9);
    EXPECT_EQ(r.quality.frames, static_cast<std::uint64_t>(kFrames)) << "layout figures over the same frames";

    // The camera: MapLibre's distance for the first pose's latitude.
    const auto trajectory = nt::loadTrajectory(o.trajectory);
    EXPECT_NEAR(r.camera_distance_m, mapLibreCameraDistance(trajectory.frames[0].position.lat_deg, GetParam().zoom, kH),
                0.1);

    // Labels were drawn and counted consistently.
    EXPECT_GT(q.visible_median, 0.0);
    EXPECT_LE(static_cast<double>(q.visible_min), q.visible_median);
    EXPECT_LE(q.visible_median, static_cast<double>(q.visible_max));
    EXPECT_GE(q.distinct_visible_labels, q.visible_max);
    EXPECT_EQ(q.occlusion_measured_label_frames + q.occlusion_unmeasured_label_frames, q.visible_label_frames);
    EXPECT_GT(q.occlusion_measured_label_frames, 0U) << "measure_label_occlusion is on";
    EXPECT_GT(r.mean_label_occlusion_ms, 0.0);
    EXPECT_LE(q.occluded_label_frames, q.occlusion_measured_label_frames);
    EXPECT_LE(q.too_small_label_frames, q.visible_label_frames);
    EXPECT_EQ(q.marker_frames, static_cast<std::uint64_t>(kFrames)) << "the marker is drawn at every pose";
    EXPECT_LE(q.marker_overlap_frames, q.marker_frames);
    EXPECT_LE(q.interior_point_pops, q.pops);
    EXPECT_LE(q.frames_with_pop, q.pops);
    EXPECT_GT(q.jitter_samples, 0U);
    EXPECT_LE(q.jitter_mean_px, q.jitter_max_px);
    EXPECT_GT(r.frame_ms.p50, 0.0);
    EXPECT_LE(r.frame_ms.p50, r.frame_ms.p95);
    EXPECT_GT(r.labels_ms.mean, 0.0);

    // Every drawn pop has one cause (docs/labels.md "Pops by cause"), and the floor is below them.
    const nl::PopCauseFigures& pc = r.pop_causes;
    std::uint64_t by_cause = 0, interior_by_cause = 0;
    for (std::size_t c = 0; c < nl::kPopCauses; ++c) {
        by_cause += pc.pops[c];
        interior_by_cause += pc.interior_point_pops[c];
    }
    EXPECT_EQ(by_cause, q.pops);
    EXPECT_EQ(interior_by_cause, q.interior_point_pops);
    EXPECT_EQ(pc.enters + pc.leaves, q.pops);
    EXPECT_LE(pc.floor, q.pops);
    EXPECT_GE(pc.visible_runs, q.distinct_visible_labels);

    // The report is the metrics of exactly the frames that were drawn.
    const nl::DrawnLabelQuality again = measure(frames, o.dt_s);
    EXPECT_EQ(again.pops, q.pops);
    EXPECT_EQ(again.text_pops, q.text_pops);
    EXPECT_EQ(again.interior_point_pops, q.interior_point_pops);
    EXPECT_EQ(again.visible_label_frames, q.visible_label_frames);
    EXPECT_EQ(again.overlap_pairs_sum, q.overlap_pairs_sum);
    EXPECT_EQ(again.marker_overlap_label_frames, q.marker_overlap_label_frames);
    EXPECT_DOUBLE_EQ(again.jitter_mean_px, q.jitter_mean_px);

    // Force a pop: a label visible in frames 44 to 46 vanishes from frame 45 (it leaves, then
    // enters again): two more pops, counted where it was visible for the interior rule.
    const DrawnFrame& before = frames[44];
    const nl::DrawnLabel* victim = nullptr;
    for (const nl::DrawnLabel& l : frames[45].labels) {
        if (l.opacity >= 0.5F && visibleIn(before, l.id) && visibleIn(frames[46], l.id)) {
            victim = &l;
            break;
        }
    }
    ASSERT_NE(victim, nullptr) << "no label visible in frames 44-46";
    const std::uint64_t id = victim->id;
    const std::string text = victim->text;
    std::vector<DrawnFrame> forced = frames;
    std::erase_if(forced[45].labels, [&](const nl::DrawnLabel& l) { return l.id == id; });
    auto interior = [&](const DrawnFrame& f) {
        for (const nl::DrawnLabel& l : f.labels) {
            if (l.id != id) continue;
            return (l.kind == nl::LabelKind::Point || l.kind == nl::LabelKind::Area) && l.anchor.x >= 64 &&
                   l.anchor.x <= kW - 64 && l.anchor.y >= 64 && l.anchor.y <= kH - 64;
        }
        return false;
    };
    const bool text_stays = std::any_of(forced[45].labels.begin(), forced[45].labels.end(),
                                        [&](const nl::DrawnLabel& l) { return l.text == text && l.opacity >= 0.5F; });
    const nl::DrawnLabelQuality popped = measure(forced, o.dt_s);
    EXPECT_EQ(popped.pops, q.pops + 2);
    EXPECT_EQ(popped.interior_point_pops,
              q.interior_point_pops + (interior(frames[44]) ? 1 : 0) + (interior(frames[46]) ? 1 : 0));
    EXPECT_EQ(popped.text_pops, q.text_pops + (text_stays ? 0 : 2));
    EXPECT_GE(popped.frames_with_pop, q.frames_with_pop);
    EXPECT_LE(popped.frames_with_pop, q.frames_with_pop + 2);
    EXPECT_GT(popped.pops_per_s, q.pops_per_s);

    // The JSON carries every figure.
    const auto j = nlohmann::json::parse(json);
    EXPECT_EQ(j.at("name"), nt::cameraSpecName(GetParam()));
    EXPECT_EQ(j.at("drive"), "andorra-urban-trajectory.json");
    EXPECT_EQ(j.at("size"), "1280x480");
    for (const char* key : {"zoom",
                            "pitch",
                            "camera_distance_m",
                            "frames",
                            "seconds",
                            "visible_median",
                            "visible_mean",
                            "visible_min",
                            "visible_max",
                            "overlap_pairs_max",
                            "overlap_pairs_sum",
                            "overlap_frames",
                            "occluded_share",
                            "occluded_label_frames",
                            "occlusion_measured_label_frames",
                            "occlusion_unmeasured_label_frames",
                            "too_small_share",
                            "too_small_label_frames",
                            "too_small_labels",
                            "marker_overlap_label_frames",
                            "marker_overlap_frames",
                            "marker_overlap_labels",
                            "pops",
                            "pops_per_s",
                            "interior_point_pops",
                            "interior_point_pops_per_s",
                            "text_pops",
                            "text_pops_per_s",
                            "pop_enters",
                            "pop_leaves",
                            "pops_edge",
                            "pops_too_small",
                            "pops_overlap",
                            "pops_gone",
                            "pops_keep_out",
                            "pops_other",
                            "interior_point_pops_edge",
                            "interior_point_pops_overlap",
                            "interior_point_pops_other",
                            "pop_floor",
                            "pop_floor_per_s",
                            "visible_runs",
                            "layout_removed_keep_out",
                            "frames_with_pop",
                            "pop_frame_share",
                            "jitter_mean_px",
                            "jitter_p95_px",
                            "jitter_samples",
                            "frame_ms_p50",
                            "frame_ms_p95",
                            "frame_ms_mean",
                            "label_occlusion_ms_mean",
                            "layout_mean_visible",
                            "layout_max_overlaps",
                            "layout_pops_per_s",
                            "layout_mean_jitter_px",
                            "layout_p95_jitter_px"}) {
        ASSERT_TRUE(j.contains(key)) << key;
        EXPECT_TRUE(j.at(key).is_number()) << key;
    }
    EXPECT_EQ(j.at("frames"), kFrames);
    EXPECT_EQ(j.at("pops"), q.pops);
    EXPECT_FALSE(j.contains("mean_visible")) << "layout figures only under layout_* names";
}

INSTANTIATE_TEST_SUITE_P(Cameras, TrajectoryQuality,
                         ::testing::Values(MapLibreFollow{16.5, 60.0, std::nullopt},
                                           MapLibreFollow{14.5, 30.0, std::nullopt}),
                         [](const ::testing::TestParamInfo<MapLibreFollow>& p) {
                             return std::string(p.param.zoom > 15.0 ? "zoom16_5_pitch60" : "zoom14_5_pitch30");
                         });

TEST(TrajectoryQualityErrors, BrokenTrajectoryIsAClearError) {
    nt::LabelQualityOptions o;
    o.store = navmap::test::binaryDir() / "andorra.navmap";
    o.trajectory = navmap::test::binaryDir() / "no-such-trajectory.json";
    o.camera = MapLibreFollow{16.5, 60.0, std::nullopt};
    try {
        nt::measureLabelQuality(o);
        FAIL() << "no error";
    } catch (const nt::TrajectoryError& e) {
        EXPECT_NE(std::string(e.what()).find("no-such-trajectory.json): No such file or directory"), std::string::npos)
            << e.what();
    }
    o.camera.reset();
    o.trajectory = navmap::test::dataDir() / "drives" / "andorra-urban-trajectory.json";
    EXPECT_THROW(nt::measureLabelQuality(o), std::runtime_error);
}

}  // namespace
