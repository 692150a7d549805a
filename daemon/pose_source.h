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
};

class PoseSource {
public:
    using StateProvider = std::function<std::shared_ptr<const VehicleState>()>;

    /// `state`: the newest estimator snapshot (never null); `map_middle`: where the camera looks
    /// before the first fix.
    PoseSource(StateProvider state, std::shared_ptr<map::TileCache> cache, map::PlanarPoint map_middle)
        : m_state(std::move(state)), m_ground(std::move(cache)), m_middle(map_middle) {}

    /// The pose at CAN time `t`.
    [[nodiscard]] FramePose at(ipc::CanTime t) const;
    [[nodiscard]] const GroundHeight& ground() const { return m_ground; }

private:
    StateProvider m_state;
    GroundHeight m_ground;
    map::PlanarPoint m_middle;
};

}  // namespace navmap::daemon
