// SPDX-License-Identifier: Apache-2.0
#include "pose_events.h"

namespace navmap::daemon {

void PoseEvents::update(const EstimatedPose& pose, const RouteState& route, std::chrono::steady_clock::time_point now) {
    if (pose.valid && pose.stale != m_was_stale) {
        ipc::ControlEvent e;
        e.kind = pose.stale ? ipc::ControlEventKind::PositionLost : ipc::ControlEventKind::PositionRegained;
        e.since_s = pose.since_fix_s;
        m_server.publish(e);
        if (pose.stale)
            m_log(Log::kWarning, "position lost (%.1f s without a fix)", pose.since_fix_s);
        else
            m_log(Log::kInfo, "position regained");
        m_was_stale = pose.stale;
    }
    if (!route.id().empty() && pose.on_route && now - m_last_progress > std::chrono::seconds(1)) {
        ipc::ControlEvent e;
        e.kind = ipc::ControlEventKind::RouteProgress;
        e.route_id = route.id();
        e.driven_m = route.drivenM();
        e.remaining_m = route.remainingM();
        m_server.publish(e);
        m_last_progress = now;
    }
}

}  // namespace navmap::daemon
