// SPDX-License-Identifier: Apache-2.0
#pragma once
// PoseEvents: what the control socket's subscribers hear about the vehicle: position lost and
// regained (logged too), and route progress about once a second while the pose is on the route.
// Render thread only.

#include <chrono>

#include "log.h"
#include "navmap/daemon/vehicle/vehicle_state.h"
#include "navmap/ipc/control/control_server.h"
#include "route_state.h"

namespace navmap::daemon {

class PoseEvents {
public:
    PoseEvents(ipc::ControlServer& server, Log log) : m_server(server), m_log(log) {}

    /// Publishes the events that `pose` (taken at `now`) gives rise to.
    void update(const EstimatedPose& pose, const RouteState& route, std::chrono::steady_clock::time_point now);

private:
    ipc::ControlServer& m_server;
    Log m_log;
    bool m_was_stale = false;
    std::chrono::steady_clock::time_point m_last_progress{};
};

}  // namespace navmap::daemon
