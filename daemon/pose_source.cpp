// SPDX-License-Identifier: Apache-2.0
#include "pose_source.h"

namespace navmap::daemon {

FramePose PoseSource::at(ipc::CanTime t) const {
    const EstimatedPose pose = m_pose(t);
    FramePose frame;
    frame.source_time = pose.source_time;
    frame.estimate = pose;
    if (pose.valid) {
        frame.vehicle.position = {pose.x, pose.y, m_ground(pose.x, pose.y)};
        frame.vehicle.heading_deg = pose.heading_deg;
        frame.vehicle.speed_mps = pose.speed_mps;
        frame.marker = render::MarkerState{frame.vehicle.position, frame.vehicle.heading_deg, pose.stale};
        frame.speed_limit_kmh = pose.speed_limit_kmh;
    } else {
        // No fix yet: look at the middle of the map.
        frame.vehicle.position = {m_middle.x, m_middle.y, m_ground(m_middle.x, m_middle.y)};
    }
    return frame;
}

}  // namespace navmap::daemon
