// SPDX-License-Identifier: Apache-2.0
#include "day_night.h"

#include "sun_position.h"

namespace navmap::daemon {

const char* styleReasonName(StyleReason r) noexcept {
    switch (r) {
        case StyleReason::Fixed: return "fixed";
        case StyleReason::Sun: return "sun";
        case StyleReason::Can: return "can";
        case StyleReason::Tunnel: return "tunnel";
    }
    return "fixed";
}

ipc::MapStyle configuredStyle(const DaemonConfig& config) {
    if (config.style.automatic) return ipc::MapStyle::Auto;
    return config.night ? ipc::MapStyle::Night : ipc::MapStyle::Day;
}

DayNight::DayNight(const StyleConfig& config) : m_config(config), m_fade(config.fade_s) {}

std::optional<bool> DayNight::byLight(const DayNightInput& in) const {
    const auto fresh = [&](ipc::CanTime t) {
        return std::chrono::duration<double>(in.can_now - t).count() <= m_config.can_timeout_s;
    };
    // The intensity first: it says how dark it is, where the low beam may be on by day (a tunnel,
    // a daytime-lights setting).
    if (in.light.intensity_pct && fresh(in.light.intensity_time)) {
        const double pct = *in.light.intensity_pct;
        if (pct < m_config.light_night_below_pct) return true;
        if (pct > m_config.light_day_above_pct) return false;
        return m_started ? m_night : pct < 0.5 * (m_config.light_night_below_pct + m_config.light_day_above_pct);
    }
    if (in.light.low_beam && fresh(in.light.low_beam_time)) return *in.light.low_beam;
    return std::nullopt;
}

bool DayNight::bySun(double elevation_deg) const {
    const double half = 0.5 * m_config.hysteresis_deg;
    if (!m_started) return elevation_deg < m_config.twilight_deg;
    // Night stays until the sun is half the band above the threshold, day until half below it.
    return m_night ? elevation_deg < m_config.twilight_deg + half : elevation_deg < m_config.twilight_deg - half;
}

render::MapStyle DayNight::update(const DayNightInput& in) {
    m_requested = in.requested;
    bool night = in.requested == ipc::MapStyle::Night;
    m_reason = StyleReason::Fixed;
    m_sun_deg.reset();
    if (in.requested == ipc::MapStyle::Auto) {
        m_sun_deg = solarElevationDeg(in.lat_deg, in.lon_deg, in.wall_time);
        const std::optional<bool> by_light = m_config.prefer_can ? byLight(in) : std::nullopt;
        night = by_light ? *by_light : bySun(*m_sun_deg);
        m_reason = by_light ? StyleReason::Can : StyleReason::Sun;
    }
    // In a tunnel the view dims to night with the same fade, whatever the configuration or auto
    // says; a day style the HMI fixed with set_style wins (docs/navmapd.md "Tunnels").
    const bool hmi_day = in.requested_by_hmi && in.requested == ipc::MapStyle::Day;
    if (in.in_tunnel && !night && !hmi_day) {
        night = true;
        m_reason = StyleReason::Tunnel;
    }
    if (!m_started) {
        m_fade.reset(night);
        m_started = true;
    } else {
        m_fade.target(night, in.now_s);
    }
    m_night = night;
    m_weight = m_fade.weightAt(in.now_s);
    return render::mixStyles(m_day, m_night_style, m_weight);
}

}  // namespace navmap::daemon
