// SPDX-License-Identifier: Apache-2.0
#pragma once
// DayNight: the style navmapd draws (docs/navmapd.md "Day and night"). The control socket's
// set_style (or the configuration's mode) fixes day or night; in auto a light signal from CAN,
// or else the sun's elevation at the vehicle, chooses, with hysteresis so that a value at the
// threshold does not flicker; every change is a cross-fade over StyleConfig::fade_s. Render
// thread only. It reads no clock: the caller hands in the times (the tests simulate places and
// times), and never waits.

#include <chrono>
#include <optional>

#include "config.h"
#include "navmap/ipc/can/can_frame.h"
#include "navmap/ipc/control/control_command.h"
#include "navmap/render/map_frame.h"
#include "navmap/render/style_fade.h"
#include "vehicle_input.h"

namespace navmap::daemon {

/// What DayNight decides from, for one frame.
struct DayNightInput {
    ipc::MapStyle requested = ipc::MapStyle::Day;  ///< the control state's (set_style, the config's mode)
    bool requested_by_hmi = false;                 ///< `requested` came from set_style (ipc::ViewState::style_from_hmi)
    bool in_tunnel = false;                        ///< the vehicle is in a tunnel (EstimatedPose::in_tunnel)
    double lat_deg = 0.0;                          ///< where the vehicle is (or the map's centre)
    double lon_deg = 0.0;
    std::chrono::system_clock::time_point wall_time{};  ///< the time of day at it, for the sun
    AmbientLight light;                                 ///< VehicleInput::ambientLight()
    ipc::CanTime can_now{};                             ///< now on the CAN receive clock (the light's age)
    double now_s = 0.0;                                 ///< any steady clock, seconds: the fade's
};

/// Why the style is what it is: fixed (set_style, the config's day or night), auto by the sun or
/// by a CAN light signal, or night in a tunnel (any mode but a day style fixed by set_style).
enum class StyleReason { Fixed, Sun, Can, Tunnel };
const char* styleReasonName(StyleReason r) noexcept;  ///< "fixed" | "sun" | "can" | "tunnel"

/// The control state's style at start and after a reload: the configuration's mode.
ipc::MapStyle configuredStyle(const DaemonConfig& config);

class DayNight {
public:
    explicit DayNight(const StyleConfig& config);

    /// Decides the style for a frame and returns the style to draw: the day or night style, or a
    /// mix of the two while a fade is under way. The first call shows its decision at once.
    render::MapStyle update(const DayNightInput& in);

    /// The style decided (the fade's target): true night.
    [[nodiscard]] bool night() const { return m_night; }
    [[nodiscard]] StyleReason reason() const { return m_reason; }
    /// The style asked for in the latest update (DayNightInput::requested).
    [[nodiscard]] ipc::MapStyle requested() const { return m_requested; }
    /// The night style's weight in the latest frame: 0 day .. 1 night.
    [[nodiscard]] float weight() const { return m_weight; }
    /// The sun's elevation at the latest update in auto mode, degrees (none in fixed mode).
    [[nodiscard]] std::optional<double> sunElevationDeg() const { return m_sun_deg; }

private:
    // Night or day from the light signals, with hysteresis on the intensity; none while no signal
    // is fresh.
    [[nodiscard]] std::optional<bool> byLight(const DayNightInput& in) const;
    [[nodiscard]] bool bySun(double elevation_deg) const;

    StyleConfig m_config;
    render::StyleFade m_fade;
    render::MapStyle m_day = render::MapStyle::day(), m_night_style = render::MapStyle::night();
    bool m_started = false;
    bool m_night = false;
    StyleReason m_reason = StyleReason::Fixed;
    ipc::MapStyle m_requested = ipc::MapStyle::Day;
    float m_weight = 0.0f;
    std::optional<double> m_sun_deg;
};

}  // namespace navmap::daemon
