// SPDX-License-Identifier: Apache-2.0
#include "config_reloader.h"

#include "day_night.h"

namespace navmap::daemon {

void ConfigReloader::reload(ipc::ControlState& control, DisplayScheduler& displays) {
    if (!m_path) return;
    ConfigError error;
    auto fresh = loadConfig(*m_path, &error);
    if (fresh) {
        // What a reload does not change (store, input, sockets, ...) keeps its running value,
        // command-line overrides and built-in defaults included, so the file is validated as it
        // will run.
        DaemonConfig merged = m_running;
        merged.night = fresh->night;
        merged.style.automatic = fresh->style.automatic;
        merged.orthoimage_ground = fresh->orthoimage_ground;
        merged.profiles = fresh->profiles;
        fresh = std::move(merged);
    }
    if (!fresh || !validateConfig(*fresh, &error)) {
        m_log(Log::kErr, "reload: %s (keeping the running configuration)", error.message.c_str());
        ++m_errors;
        m_last_error = error.message;
        return;
    }
    // Style and per-profile view settings change in place; clients stay connected.
    ipc::SetStyleCommand style;
    style.style = configuredStyle(*fresh);
    style.configured = true;
    style.ground = fresh->orthoimage_ground ? ipc::Ground::Orthoimage : ipc::Ground::LandCover;
    (void)control.setStyle(style);
    m_running.night = fresh->night;
    m_running.style.automatic = fresh->style.automatic;
    m_running.orthoimage_ground = fresh->orthoimage_ground;
    displays.reconfigure(fresh->profiles);
    ++m_reloads;
    m_log(Log::kNotice, "reloaded %s: style %s, ground %s", m_path->c_str(), ipc::mapStyleName(configuredStyle(*fresh)),
          fresh->orthoimage_ground ? "orthoimage" : "landcover");
}

}  // namespace navmap::daemon
