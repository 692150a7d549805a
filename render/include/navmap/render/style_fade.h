// SPDX-License-Identifier: Apache-2.0
#pragma once
// The cross-fade between the day and the night style (docs/rendering.md "Day and night"): where
// it stands by time (StyleFade) and the style there (mixStyles), every colour of the style and
// the brightness that scales the ground taken between the two. Pure values, no GL.

#include "navmap/render/map_frame.h"

namespace navmap::render {

/// How long a change of style takes, seconds.
inline constexpr double kStyleFadeS = 2.0;

/// The style `t` of the way from `from` to `to` (t clamped to [0, 1]): each colour of MapStyle
/// and of its RoadStyle, the brightness and the glow and outline strengths are a * (1 - t) + b * t,
/// on the sRGB-encoded values the shaders use (the frame buffer is not sRGB: the colours blend in
/// the space they are drawn in). t = 0 gives `from` and t = 1 gives `to`, bit for bit; what is no
/// colour (widths, fog, the light, the ground) is `from`'s below one half and `to`'s from it (the
/// day and night styles share them).
MapStyle mixStyles(const MapStyle& from, const MapStyle& to, float t);

/// Where the fade between day (weight 0) and night (weight 1) stands at a time (seconds on any
/// steady clock). The weight moves at 1 / duration per second, linearly in time, towards the
/// latest target; a change of target midway turns back from where the fade stands.
class StyleFade {
public:
    explicit StyleFade(double duration_s = kStyleFadeS) : m_duration_s(duration_s) {}

    /// Shows `night` from now on without a fade (start-up: the first frame has its style).
    void reset(bool night);
    /// Heads for `night` from `now_s`; the same target again changes nothing.
    void target(bool night, double now_s);
    /// The weight at `now_s`: 0 day .. 1 night, exactly 0 or 1 once the fade is over.
    [[nodiscard]] float weightAt(double now_s) const;
    /// Whether the fade is still under way at `now_s`.
    [[nodiscard]] bool fading(double now_s) const { return weightAt(now_s) != m_to; }
    /// The target: the style shown once the fade is over.
    [[nodiscard]] bool night() const { return m_to == 1.0f; }

private:
    double m_duration_s;
    float m_from = 0.0f, m_to = 0.0f;
    double m_start_s = 0.0;
};

}  // namespace navmap::render
