// SPDX-License-Identifier: Apache-2.0
#pragma once
// Pops by cause (docs/labels.md "Pops by cause"): every pop that DrawnLabelMetrics counts (an id
// entering or leaving the set of labels drawn with opacity >= 0.5) attributed to what made it,
// from the layout's output of the same frame (why a label fades out, what held it back before it
// was placed) and the renderer's input changes (why a candidate came or went). Also the floor:
// the pops no layout can avoid for the set of labels it shows. GL-free, single-threaded.

#include <cstdint>
#include <span>
#include <unordered_map>
#include <unordered_set>

#include <glm/vec2.hpp>

#include "drawn_label_metrics.h"
#include "navmap/render/labels/drawn_label.h"
#include "navmap/render/labels/label_types.h"

namespace navmap::render::labels {

/// What made a pop.
enum class PopCause : std::uint8_t {
    Edge,      ///< the camera's motion: text crossing the viewport's edge, an anchor crossing it or the near plane
    TooSmall,  ///< world-space text too small to read fading out, or grown readable again
    Overlap,   ///< taken out for another label (pushed into a more important one), or placed once one made room
    Gone,      ///< the feature left the drawn tiles or came with them (tile loaded, dropped, level of detail)
    KeepOut,   ///< the marker, the route ahead or an arrow took its place, or gave it back
    Other,     ///< anything else (terrain, one name per street, speed or constriction, the SS/WS cross-fade)
};
inline constexpr std::size_t kPopCauses = 6;
/// "edge", "too_small", "overlap", "gone", "keep_out", "other" (the JSON names' suffixes).
const char* popCauseName(PopCause cause);

struct PopCauseFigures {
    std::uint64_t enters = 0, leaves = 0;                ///< the pops split by direction (enters + leaves = pops)
    std::uint64_t pops[kPopCauses] = {};                 ///< by PopCause; sums to the drawn pops
    std::uint64_t interior_point_pops[kPopCauses] = {};  ///< the interior point pops by PopCause
    /// The floor: each label visible in some frame but not in the first one enters at least
    /// once, each one not visible in the last frame leaves at least once, whatever the layout.
    std::uint64_t floor = 0;
    std::uint64_t visible_runs = 0;  ///< spans of consecutive frames one id was visible
};

/// Attributes the pops of successive frames. Feed every frame, the settling ones included
/// (`measured` false: their input changes and removals are remembered, nothing is counted).
class PopCauses {
public:
    explicit PopCauses(DrawnMetricsParams params = {});

    /// `drawn`: MapFrameStats::drawn_labels, `placed`: placed_labels (the layout output of the
    /// same frame), `changes`: label_input_changes.
    void addFrame(std::span<const DrawnLabel> drawn, std::span<const PlacedLabel> placed,
                  std::span<const LabelInputChange> changes, glm::vec2 viewport, bool measured);
    [[nodiscard]] PopCauseFigures summary() const;

private:
    struct Seen {
        bool interior_point = false;
    };
    [[nodiscard]] PopCause enterCause(const PlacedLabel* p, std::uint64_t id) const;
    [[nodiscard]] PopCause leaveCause(const PlacedLabel* p, std::uint64_t id) const;
    [[nodiscard]] PopCause inputCause(std::uint64_t id) const;

    DrawnMetricsParams m_params;
    PopCauseFigures m_f;
    bool m_started = false;
    std::unordered_map<std::uint64_t, InputCause> m_last_input;  ///< latest input change per id
    std::unordered_map<std::uint64_t, Seen> m_prev;              ///< visible ids of the previous measured frame
    std::unordered_set<std::uint64_t> m_first, m_seen;           ///< visible in the first measured frame, in any
};

}  // namespace navmap::render::labels
