// SPDX-License-Identifier: Apache-2.0
#pragma once
// PoseSource: the vehicle pose a frame is rendered with: the newest estimator snapshot evaluated
// at the frame's time, standing on the ground (GroundHeight), or the middle of the map while there
// is no fix yet. Every display takes its pose from here, so all of them see the same height.
// Render thread only.

#include <functional>
#include <memory>
#include <optional>

#include "ground_height.h"
#include "navmap/daemon/vehicle/vehicle_state.h"
#include "navmap/map/projection.h"
#include "navmap/render/camera_rig.h"
#include "navmap/render/map_frame.h"

namespace navmap::daemon {

/// One frame's pose.
struct FramePose {
    render::VehiclePose vehicle;                ///< position z = ground height
    std::optional<render::MarkerState> marker;  ///< drawn when the position is known
    ipc::CanTime source_time{};                 ///< CAN time of the newest sample behind it
    EstimatedPose estimate;                     ///< the estimator's pose it was made from
    /// The speed limit on the matched road in the driving direction, km/h; 0: unknown or the
    /// match uncertain (EstimatedPose::speed_limit_kmh). The frame's speed limit sign shows it.
    int speed_limit_kmh = 0;
};

class PoseSource {
public:
    /// The estimated pose at a CAN time, in the daemon's current map frame (VehicleInput::poseAt).
    using PoseProvider = std::function<EstimatedPose(ipc::CanTime)>;
    /// `pose`: the estimator's pose; `map_middle`: where the camera looks before the first fix.
    PoseSource(PoseProvider pose, std::shared_ptr<map::TileCache> cache, map::PlanarPoint map_middle)
        : m_pose(std::move(pose)), m_ground(std::move(cache)), m_middle(map_middle) {}
    /// Re-expresses what it keeps in the frame (the map's middle) after the daemon re-centred it.
    void rebase(const map::FrameTransform& to_frame) {
        m_middle = {to_frame.scale * m_middle.x + to_frame.offset_x, to_frame.scale * m_middle.y + to_frame.offset_y};
    }
    /// The pose at CAN time `t`.
    [[nodiscard]] FramePose at(ipc::CanTime t) const;
    [[nodiscard]] const GroundHeight& ground() const { return m_ground; }

private:
    PoseProvider m_pose;
    GroundHeight m_ground;
    map::PlanarPoint m_middle;
};

}  // namespace navmap::daemon
