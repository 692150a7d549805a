// SPDX-License-Identifier: Apache-2.0
#pragma once
// Label quality measured on the drawn frames (docs/architecture.md "Quality bars": what the driver sees, not
// the layout boxes): visible labels, overlapping glyphs, labels hidden by the scene, text too
// small to read, labels over the vehicle marker, pops as MapLibre GL JS's placement counts them,
// and jitter. Fed one frame at a time with MapFrameStats::drawn_labels and drawn_marker; GL-free,
// single-threaded. The definitions are in docs/labels.md "Measured quality".

#include <cstdint>
#include <span>
#include <string>
#include <unordered_map>
#include <unordered_set>
#include <vector>

#include <glm/vec2.hpp>

#include "navmap/render/labels/drawn_label.h"

namespace navmap::render::labels {

/// The thresholds of the definitions. The defaults are the definitions; tests may vary them.
struct DrawnMetricsParams {
    float visible_opacity = 0.5F;       ///< a label is visible with drawn opacity >= this
    float overlap_tolerance_px = 1.0F;  ///< glyph boxes overlap when the SAT penetration depth exceeds this
    float occluded_fraction = 0.10F;    ///< a label is occluded when more than this share is hidden
    float min_cap_height_px = 9.0F;     ///< text with a smaller cap height is too small to read
    float marker_tolerance_px = 1.0F;   ///< a glyph box overlaps the marker when the SAT depth exceeds this
    float interior_margin_px = 64.0F;   ///< interior point labels: anchor at least this far inside the viewport
};

/// What one frame showed (returned by DrawnLabelMetrics::addFrame).
struct DrawnFrameFigures {
    std::size_t visible = 0;          ///< distinct visible labels
    std::size_t overlap_pairs = 0;    ///< pairs of visible labels with overlapping glyph boxes
    std::size_t marker_overlaps = 0;  ///< visible labels over the marker
    std::size_t pops = 0;             ///< ids entering or leaving the visible set since the previous frame
    std::size_t interior_point_pops = 0;
    std::size_t text_pops = 0;
};

/// Summary over the frames fed so far. "label-frames": one label in one frame.
struct DrawnLabelQuality {
    std::uint64_t frames = 0;
    double seconds = 0.0;  ///< sum of the frames' dt (each frame is shown for its dt)
    // Labels visible per frame.
    double visible_median = 0.0;  ///< median over frames (mean of the two middle ones for an even count)
    double visible_mean = 0.0;
    std::size_t visible_min = 0;
    std::size_t visible_max = 0;
    std::uint64_t visible_label_frames = 0;     ///< sum over frames of the visible labels
    std::uint64_t distinct_visible_labels = 0;  ///< ids visible in at least one frame
    // Overlapping glyphs.
    std::size_t overlap_pairs_max = 0;    ///< worst frame
    std::uint64_t overlap_pairs_sum = 0;  ///< summed over frames
    std::uint64_t overlap_frames = 0;     ///< frames with at least one overlapping pair
    // Hidden by the scene (occluded_fraction of the renderer, aura taken into account).
    std::uint64_t occluded_label_frames = 0;              ///< visible, measured, occluded_fraction > 0.10
    std::uint64_t occlusion_measured_label_frames = 0;    ///< visible with occluded_fraction >= 0
    std::uint64_t occlusion_unmeasured_label_frames = 0;  ///< visible with occluded_fraction < 0 (not measured)
    double occluded_share = 0.0;  ///< occluded / measured visible label-frames (0 when none measured)
    // Too small to read.
    std::uint64_t too_small_label_frames = 0;  ///< visible with cap height < 9 px
    double too_small_share = 0.0;              ///< of the visible label-frames
    std::uint64_t too_small_labels = 0;        ///< distinct ids ever visible with cap height < 9 px
    // Over the vehicle marker.
    std::uint64_t marker_overlap_label_frames = 0;
    std::uint64_t marker_overlap_frames = 0;
    std::uint64_t marker_overlap_labels = 0;  ///< distinct ids
    std::uint64_t marker_frames = 0;          ///< frames with a marker outline
    // Pops (MapLibre placement's count: ids entering or leaving the visible set).
    std::uint64_t pops = 0;
    double pops_per_s = 0.0;
    std::uint64_t interior_point_pops = 0;  ///< Point/Area labels with the anchor >= 64 px inside
    double interior_point_pops_per_s = 0.0;
    std::uint64_t text_pops = 0;  ///< texts entering or leaving the set of visible texts
    double text_pops_per_s = 0.0;
    std::uint64_t frames_with_pop = 0;  ///< frames (after the first) with at least one pop
    double pop_frame_share = 0.0;       ///< frames_with_pop / (frames - 1)
    // Jitter: movement of a visible label's drawn center relative to its anchor, px per frame.
    double jitter_mean_px = 0.0;
    double jitter_p95_px = 0.0;  ///< nearest-rank 95th percentile
    double jitter_max_px = 0.0;
    std::uint64_t jitter_samples = 0;
    // Input sanity.
    std::uint64_t duplicate_ids = 0;  ///< entries sharing an id with another entry of the same frame (merged)
};

/// Accumulates DrawnLabelQuality over successive drawn frames. Labels are matched across frames
/// by id; a label missing from a frame counts as opacity 0. Entries of one frame that share an
/// id are merged (highest opacity; glyph boxes of the visible entries) and counted as duplicates.
class DrawnLabelMetrics {
public:
    explicit DrawnLabelMetrics(DrawnMetricsParams params = {});

    /// Adds one frame shown for dt_s seconds (non-finite or negative dt counts as 0). `viewport` is
    /// the frame's size in pixels (for the interior rule); `marker` may have an empty outline.
    DrawnFrameFigures addFrame(std::span<const DrawnLabel> labels, const DrawnMarker& marker, glm::vec2 viewport,
                               double dt_s);
    [[nodiscard]] DrawnLabelQuality summary() const;
    void reset();
    [[nodiscard]] const DrawnMetricsParams& params() const { return m_params; }

    /// Separating axis test of two convex polygons (corners in order, either winding): the
    /// smallest overlap of their projections over all edge normals. Positive: penetration depth
    /// in pixels; 0: touching; negative: separated by that much. A polygon with fewer than three
    /// corners or no edge longer than 1e-6 px never overlaps (returns -infinity).
    [[nodiscard]] static float penetrationDepth(std::span<const glm::vec2> a, std::span<const glm::vec2> b);

private:
    // One visible label of a frame, merged by id.
    struct Visible {
        std::uint64_t id = 0;
        const DrawnLabel* label = nullptr;  ///< the entry with the highest opacity
        std::vector<const ScreenQuad*> boxes;
        glm::vec2 lo{0.0F}, hi{0.0F};  ///< bounding box of the glyph boxes
    };
    struct Previous {
        glm::vec2 offset{0.0F};  ///< drawn center minus anchor
        bool interior_point = false;
    };

    [[nodiscard]] bool interiorPoint(const DrawnLabel& l, glm::vec2 viewport) const;
    [[nodiscard]] bool glyphsOverlap(const Visible& a, const Visible& b) const;

    DrawnMetricsParams m_params;
    DrawnLabelQuality m_q;
    std::vector<std::size_t> m_visible_counts;           ///< per frame, for the median
    std::unordered_map<std::uint64_t, Previous> m_prev;  ///< visible ids of the previous frame
    std::unordered_set<std::string> m_prev_texts;        ///< visible texts of the previous frame
    std::unordered_set<std::uint64_t> m_seen, m_too_small, m_over_marker;
    std::vector<float> m_jitter;  ///< every sample, for the exact p95
    double m_jitter_sum = 0.0;
};

}  // namespace navmap::render::labels
