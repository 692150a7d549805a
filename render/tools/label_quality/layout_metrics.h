// SPDX-License-Identifier: Apache-2.0
#pragma once
// Label layout quality measured from successive layout outputs (docs/architecture.md "Quality bars"):
// visible labels, overlapping visible labels, pops per second, mean and p95 jitter.

#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "navmap/render/labels/label_types.h"

namespace navmap::render::labels {

/// Summary over the frames fed so far.
struct LayoutQuality {
    std::uint64_t frames = 0;
    double seconds = 0.0;
    double mean_visible = 0.0;  ///< mean number of visible labels per frame
    std::size_t last_visible = 0;
    std::size_t last_overlaps = 0;  ///< overlapping visible pairs in the last frame
    std::size_t max_overlaps = 0;   ///< worst frame
    std::uint64_t pops = 0;
    double pops_per_s = 0.0;
    double mean_jitter_px = 0.0;  ///< movement of a label relative to its anchor, px per frame
    double p95_jitter_px = 0.0;   ///< 95th percentile of the same, rounded down to 0.05 px
    std::uint64_t jitter_samples = 0;
};

/// What counts as a pop.
struct MetricsParams {
    float pop_alpha = 0.5F;     ///< appearing with, or vanishing from, alpha above this is a pop
    float pop_jump_px = 20.0F;  ///< moving more than this relative to the anchor in one frame is a pop
};

/// Accumulates quality figures from successive LabelLayout::output() snapshots. "Visible" is
/// state FadingIn or Visible. Memory stays bounded (jitter goes into a histogram).
class LayoutMetrics {
public:
    explicit LayoutMetrics(MetricsParams params = {}) : m_params(params) {}

    /// Adds one frame shown for dt_s seconds. `labels` as given by output() (any order).
    void addFrame(std::span<const PlacedLabel> labels, double dt_s);
    [[nodiscard]] LayoutQuality summary() const;
    void reset();

    /// Pairs of visible labels whose boxes overlap by more than `tolerance` pixels (SAT),
    /// found by sweep and prune along x.
    [[nodiscard]] static std::size_t countOverlaps(std::span<const PlacedLabel> labels, float tolerance = 1e-3F);

private:
    static constexpr std::size_t kBins = 4096;
    static constexpr float kBinPx = 0.05F;

    MetricsParams m_params;
    std::vector<PlacedLabel> m_prev;  ///< previous frame, sorted by id
    std::vector<PlacedLabel> m_curr;
    LayoutQuality m_q;
    double m_visible_sum = 0.0;
    double m_jitter_sum = 0.0;
    std::array<std::uint64_t, kBins> m_hist{};
};

}  // namespace navmap::render::labels
