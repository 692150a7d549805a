// SPDX-License-Identifier: Apache-2.0
#pragma once
// Screen-space vs world-space labels (seed 5.2.1, 5.4.3, 5.5): SS in bird's-eye view, WS in
// snail's view, with hysteresis and a cross-fade so the switch never pops.

#include <cstdint>

#include <glm/vec3.hpp>

namespace navmap::render::labels {

enum class LabelSpace : std::uint8_t { Screen, World };

/// Thresholds of the switching rule. Tilt is the angle between the camera look direction and
/// the downward ground normal in degrees (0 = looking straight down, 90 = at the horizon);
/// height is the camera height above the ground in metres.
struct SpaceSwitchParams {
    float enter_tilt_deg = 60.0F;   ///< WS needs tilt >= this ...
    float enter_height_m = 120.0F;  ///< ... and height <= this (seed 5.5, both conditions)
    float exit_tilt_deg = 52.0F;    ///< back to SS when tilt < this ...
    float exit_height_m = 160.0F;   ///< ... or height > this
    float crossfade_s = 0.5F;       ///< duration of the cross-fade between the two label sets
};

/// The switching rule as a small state machine. Pure: state changes only through update().
class LabelSpaceSwitch {
public:
    /// Throws a std::runtime_error when the exit thresholds do not
    /// enclose the enter thresholds (no hysteresis) or a value is not finite.
    explicit LabelSpaceSwitch(SpaceSwitchParams params = {}, LabelSpace initial = LabelSpace::Screen);

    /// Tilt in degrees between a look direction and the ground normal pointing up (both need
    /// not be normalized): 0 looking straight down, 90 looking at the horizon.
    [[nodiscard]] static float tiltDeg(glm::vec3 look_dir, glm::vec3 ground_up);

    /// Seed 5.5: snail's view (WS) is active when the tilt is large enough AND the camera is
    /// close enough to the ground. `current` selects which thresholds apply (hysteresis).
    [[nodiscard]] static LabelSpace decide(LabelSpace current, float tilt_deg, float height_m,
                                           const SpaceSwitchParams& params);

    /// Feeds one frame: applies the rule, advances the cross-fade by dt_s. Non-finite input
    /// keeps the current decision. Returns the space now selected.
    LabelSpace update(float tilt_deg, float height_m, double dt_s);

    [[nodiscard]] LabelSpace space() const { return m_space; }
    /// Weight of the world-space labels in the cross-fade, smoothstep-eased, in [0, 1];
    /// screen-space labels get 1 - worldWeight().
    [[nodiscard]] float worldWeight() const;
    /// True while both label sets are drawn.
    [[nodiscard]] bool crossFading() const { return m_linear > 0.0F && m_linear < 1.0F; }
    [[nodiscard]] const SpaceSwitchParams& params() const { return m_params; }

private:
    SpaceSwitchParams m_params;
    LabelSpace m_space;
    float m_linear;  ///< linear fade position, 0 = SS, 1 = WS
};

}  // namespace navmap::render::labels
