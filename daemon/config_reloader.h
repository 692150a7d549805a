// SPDX-License-Identifier: Apache-2.0
#pragma once
// ConfigReloader: SIGHUP. Re-reads the configuration file and applies what can change while
// clients stay connected: the map style (through the control state, as set_style would) and each
// profile's view settings (DisplayScheduler::reconfigure). Everything else keeps its running
// value. A file that does not load or validate is refused with one error line; the running
// configuration stays. Render thread only.

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>

#include "config.h"
#include "display_scheduler.h"
#include "log.h"
#include "navmap/ipc/control/control_state.h"

namespace navmap::daemon {

class ConfigReloader {
public:
    /// `running`: the daemon's configuration, updated in place; `path`: the file (none: a reload
    /// changes nothing).
    ConfigReloader(DaemonConfig& running, std::optional<std::filesystem::path> path, Log log)
        : m_running(running), m_path(std::move(path)), m_log(log) {}

    void reload(ipc::ControlState& control, DisplayScheduler& displays);

    [[nodiscard]] std::uint64_t reloads() const { return m_reloads; }
    [[nodiscard]] std::uint64_t errors() const { return m_errors; }
    [[nodiscard]] const std::string& lastError() const { return m_last_error; }
    [[nodiscard]] std::string path() const { return m_path ? m_path->string() : std::string(); }

private:
    DaemonConfig& m_running;
    std::optional<std::filesystem::path> m_path;
    Log m_log;
    std::uint64_t m_reloads = 0, m_errors = 0;
    std::string m_last_error;
};

}  // namespace navmap::daemon
