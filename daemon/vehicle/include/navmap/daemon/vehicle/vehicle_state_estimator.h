// SPDX-License-Identifier: Apache-2.0
#pragma once
// VehicleStateEstimator: fuses GNSS fixes (1-10 Hz) with speed and yaw rate (50-100 Hz) from
// ipc::VehicleDecoder into a smooth pose at any requested time, map-matched onto the active route
// or the road graph, with a stale flag after a timeout. NaN, out-of-range, out-of-order and
// jumping fixes are rejected and counted. Runs on the input thread; publishes immutable
// VehicleState snapshots (snapshot()) for the render thread. Deterministic for the same input.

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "navmap/daemon/vehicle/map_matcher.h"
#include "navmap/daemon/vehicle/route_line.h"
#include "navmap/daemon/vehicle/vehicle_state.h"
#include "navmap/daemon/vehicle/vehicle_state_config.h"
#include "navmap/ipc/can/vehicle_sample.h"
#include "navmap/map/projection.h"

namespace navmap::daemon {

struct VehicleStateCounters {
    std::uint64_t fixes = 0;            ///< accepted GNSS fixes
    std::uint64_t motion_samples = 0;   ///< accepted speed/yaw-rate samples
    std::uint64_t rejected_nan = 0;     ///< not finite
    std::uint64_t rejected_range = 0;   ///< outside the plausible range or far from the map region
    std::uint64_t rejected_jump = 0;    ///< fix too far from the prediction
    std::uint64_t rejected_order = 0;   ///< older than data already used
    std::uint64_t rejected_no_fix = 0;  ///< GNSS fix type NONE
    std::uint64_t relocations = 0;      ///< re-initialised after consecutive jumps or a stale period
    std::string last_rejection;         ///< why the newest rejection happened
};

class VehicleStateEstimator {
public:
    /// `projection`: the store frame (TileStore::projection()). `matcher` may be null (no map matching).
    VehicleStateEstimator(map::Projection projection, std::shared_ptr<const MapMatcher> matcher,
                          VehicleStateConfig config = {});

    /// One decoded update (VehicleDecoder::decode output): the quantities it carries are used.
    void addSample(const ipc::VehicleSample& update);

    /// Sets the active route (store frame) for matching and progress; null clears it.
    void setRoute(std::shared_ptr<const RouteLine> route);

    /// Moves the estimator into another frame (the daemon re-centres its map frame on the
    /// vehicle): every position is re-expressed with `to_frame` (`frame`'s points from the
    /// current one's), `matcher` snaps in the new frame, fixes are accepted up to
    /// `max_distance_from_origin_m` from its origin, and snapshots carry `epoch` from now on. The
    /// route is cleared: set the route in the new frame after this.
    void rebase(const map::Projection& frame, const map::FrameTransform& to_frame,
                std::shared_ptr<const MapMatcher> matcher, double max_distance_from_origin_m, std::uint32_t epoch);
    /// The latest immutable snapshot (rebuilt lazily after input). Never null.
    [[nodiscard]] std::shared_ptr<const VehicleState> snapshot() const;
    /// Shorthand for snapshot()->poseAt(t).
    [[nodiscard]] EstimatedPose poseAt(ipc::CanTime t) const { return snapshot()->poseAt(t); }

    [[nodiscard]] const VehicleStateCounters& counters() const { return m_counters; }
    [[nodiscard]] const map::Projection& projection() const { return m_projection; }

private:
    void addMotion(const ipc::VehicleSample& update);
    void addFix(ipc::CanTime t, double lat, double lon, std::optional<double> heading, std::optional<double> fix_type);
    void reject(std::uint64_t& counter, std::string why);
    void prune();
    void updateMatch(ipc::CanTime t);
    void relocate(ipc::CanTime t, map::PlanarPoint p, std::optional<double> heading_deg);
    void changed() { m_snapshot.reset(); }

    map::Projection m_projection;
    VehicleState::Parts m_state;  // config, anchors, motion, matcher, route, matching state
    int m_consecutive_jumps = 0;
    std::optional<ipc::CanTime> m_last_yaw_time;
    // Latitude and longitude may come in separate frames: paired when close in time.
    std::optional<std::pair<double, ipc::CanTime>> m_lat, m_lon;
    std::optional<std::pair<double, ipc::CanTime>> m_heading, m_fix_type;
    VehicleStateCounters m_counters;
    mutable std::shared_ptr<const VehicleState> m_snapshot;
};

}  // namespace navmap::daemon
