// SPDX-License-Identifier: Apache-2.0
#pragma once
// StreetBarHold: which street the cluster's street bar shows (render::MapFrame::street_bar).
// The map match can flicker between two roads at a junction, or lose the road for a moment;
// the bar must not. The street shown changes only once the matched road's street (name and ref)
// has stayed the same for the hold time, 2 s by default, on the pose's clock (the CAN time the
// frame's pose is estimated for, not the wall clock: a replay shows the same bars). No confident
// match, or a road with neither name nor ref, counts as "no street": after the hold time of it
// the bar goes, so a lost match keeps the last street for the hold time and then hides it; at
// start there is no bar until a street has held that long. docs/navmapd.md "Street bar".
// One per display; render thread only.

#include <optional>

#include "navmap/render/map_frame.h"

namespace navmap::daemon {

class StreetBarHold {
public:
    static constexpr double kDefaultHoldS = 2.0;

    explicit StreetBarHold(double hold_s = kDefaultHoldS) : m_hold_s(hold_s) {}

    /// One frame: `t_s`, the pose's time in seconds (any epoch, non-decreasing; a time before
    /// the previous one, e.g. a replay started over, starts the wait again); `matched`, the
    /// street of the confidently matched road (none: no confident match). Returns the street
    /// to show: none, no bar.
    const std::optional<render::StreetBar>& update(double t_s, const std::optional<render::StreetBar>& matched);
    /// What the last update() returned.
    [[nodiscard]] const std::optional<render::StreetBar>& shown() const { return m_shown; }

private:
    double m_hold_s;
    bool m_started = false;                        // a frame was seen
    double m_last_s = 0.0;                         // its time
    std::optional<render::StreetBar> m_candidate;  // the street matched since m_since_s
    double m_since_s = 0.0;
    std::optional<render::StreetBar> m_shown;
};

}  // namespace navmap::daemon
