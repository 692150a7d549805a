// SPDX-License-Identifier: Apache-2.0
#pragma once
// StatusReporter: about once a second, gathers a StatusSample from the daemon's parts and
// publishes it as the status object (DaemonStatus), the /metrics families (DaemonMetrics) and
// systemd's STATUS= line. Render thread only.

#include <chrono>
#include <string>

#include "config_reloader.h"
#include "daemon_metrics.h"
#include "daemon_status.h"
#include "day_night.h"
#include "display_scheduler.h"
#include "frame_recentring.h"
#include "lifecycle.h"
#include "navmap/ipc/control/control_server.h"
#include "navmap/ipc/stream/frame_server.h"
#include "navmap/map/map_scene.h"
#include "navmap/map/tile_cache.h"
#include "route_state.h"
#include "vehicle_input.h"

namespace navmap::daemon {

class StatusReporter {
public:
    using Clock = std::chrono::steady_clock;

    /// The parts reported on; all outlive the reporter.
    struct Parts {
        const DaemonConfig& config;
        const ConfigReloader& reloader;
        const VehicleInput& input;
        std::string road_graph;  ///< "ok" or "unavailable: <why>"
        const RouteState& route;
        const DisplayScheduler& displays;
        const ipc::FrameServer& frames;
        const ipc::ControlServer& control;
        const map::TileCache& cache;
        const map::MapScene& scene;    ///< the mounted stores
        const FrameRecentring& frame;  ///< the map frame
        const DayNight& day_night;     ///< the style drawn
    };

    StatusReporter(Parts parts, DaemonStatus& status, DaemonMetrics& metrics, SystemdNotifier& systemd,
                   Clock::time_point started)
        : m_parts(std::move(parts)), m_status(status), m_metrics(metrics), m_systemd(systemd), m_started(started) {}

    /// Publishes when a second has passed since the last time (or after refresh()).
    void update(Clock::time_point now, const EstimatedPose& pose);
    /// The next update() publishes (after a reload: status and metrics show it at once).
    void refresh() { m_last = {}; }

private:
    Parts m_parts;
    DaemonStatus& m_status;
    DaemonMetrics& m_metrics;
    SystemdNotifier& m_systemd;
    Clock::time_point m_started;
    Clock::time_point m_last{};
};

}  // namespace navmap::daemon
