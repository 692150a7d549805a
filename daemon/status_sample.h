// SPDX-License-Identifier: Apache-2.0
#pragma once
// StatusSample: what navmapd reports about itself, gathered once a second on the render thread
// and turned into the get_status / GET /status object (DaemonStatus) and the /metrics families
// (DaemonMetrics).

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "display.h"
#include "navmap/daemon/vehicle/vehicle_state.h"
#include "navmap/ipc/control/control_server.h"
#include "navmap/ipc/stream/frame_server.h"
#include "navmap/map/tile_cache.h"
#include "navmap/render/dmabuf_probe.h"
#include "process_memory.h"
#include "vehicle_input.h"

namespace navmap::daemon {

/// One mounted store: its file, its tiles, the tiles loaded from it so far.
struct StoreStatus {
    std::string path;
    std::uint32_t tiles = 0;
    std::uint64_t loads = 0;
};

/// The map frame (FrameRecentring): its origin, how often it moved, its scale error at the vehicle.
struct FrameStatus {
    double origin_lat = 0.0;
    double origin_lon = 0.0;
    std::uint32_t recentred = 0;
    double scale_error = 0.0;  ///< frame metres per ground metre at the vehicle, minus one
    double vehicle_lat = 0.0;  ///< the pose's position, degrees (when the pose is valid)
    double vehicle_lon = 0.0;
};

/// The style drawn (DayNight): day or night, why, and where a fade stands.
struct StyleStatus {
    std::string mode = "day";  ///< the control state's: day, night or auto
    bool night = false;        ///< the style decided (a fade's target)
    std::string reason = "fixed";
    float night_weight = 0.0f;  ///< 0 day .. 1 night in the latest frame
    std::optional<double> sun_elevation_deg;
};

struct StatusSample {
    double uptime_s = 0.0;
    std::string config_path;           ///< empty: no file
    std::string config_style = "day";  ///< the configuration's mode: day, night or auto
    StyleStatus style;
    std::string ortho_problem;                     ///< DisplayScheduler::orthoProblem()
    std::uint64_t reloads = 0, reload_errors = 0;  ///< SIGHUP: applied / refused
    std::string last_reload_error;
    VehicleInputStats input;
    std::string road_graph;  ///< "ok" or "unavailable: <why>"
    EstimatedPose pose;
    std::string route_id;  ///< empty: no route
    double route_driven_m = 0.0;
    const std::vector<std::unique_ptr<Display>>* displays = nullptr;  ///< never null when published
    ipc::FrameServerStats stream;
    ipc::ControlServerStats control;
    map::TileCacheMetrics cache;
    std::vector<StoreStatus> stores;  ///< the first is the one the map frame starts in
    FrameStatus frame;
    ProcessMemory memory;
    render::DmabufCapability dmabuf;  ///< DisplayScheduler::dmabuf()
};

}  // namespace navmap::daemon
