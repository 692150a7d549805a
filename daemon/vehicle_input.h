// SPDX-License-Identifier: Apache-2.0
#pragma once
// The input thread: CAN frames from one CanSource (a candump replay, the in-process simulator or
// SocketCAN, can_sources.h) go through the DBC decoder into the vehicle state estimator, which
// publishes immutable snapshots; the render thread reads the newest one (never waits). The
// active route arrives as an immutable RouteLine (RouteState converts the control socket's route
// once) and is applied on this thread, the estimator's only owner.

#include <atomic>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "config.h"
#include "navmap/daemon/vehicle/route_line.h"
#include "navmap/daemon/vehicle/vehicle_state.h"
#include "navmap/daemon/vehicle/vehicle_state_estimator.h"
#include "navmap/ipc/can/can_source.h"
#include "navmap/ipc/can/vehicle_decoder.h"
#include "navmap/ipc/control/control_state.h"
#include "navmap/map/projection.h"
#include "navmap/map/road_graph.h"

namespace navmap::daemon {

struct VehicleInputStats {
    std::string source;        ///< "replay <file>", "sim <from> -> <to>", "socketcan can0"
    std::uint64_t frames = 0;  ///< CAN frames received
    ipc::DecoderCounters decoder;
    VehicleStateCounters estimator;
    std::uint64_t can_error_frames = 0, can_bus_off = 0, can_kernel_drops = 0;
    std::string can_state;  ///< "open", "retrying: bind(can0): No such device", ...
    std::uint64_t replay_loops = 0;
    std::uint64_t replay_malformed_lines = 0;  ///< skipped lines of the replayed log (all passes)
    std::uint64_t replay_time_errors = 0;      ///< frames whose time did not fit the clock
    std::uint64_t dbc_skipped_entries = 0;     ///< broken entries of the DBC files, skipped at start
    /// Why this input gives no (more) positions: "replay stopped: ...", "the simulator cannot
    /// plan a route: road graph unavailable: ..."; empty while it works.
    std::string error;
};

/// The light around the vehicle as the CAN bus last reported it (the DBC signals mapped to
/// Vehicle.Body.Lights.Beam.Low.IsOn and Vehicle.Exterior.LightIntensity; docs/can-input.md),
/// each with its receive time. Empty while nothing of it was decoded.
struct AmbientLight {
    std::optional<bool> low_beam;
    ipc::CanTime low_beam_time{};
    std::optional<double> intensity_pct;
    ipc::CanTime intensity_time{};
};

/// What opening the decoder skipped (VehicleInput::openDecoder).
struct DecoderSetup {
    /// One line per DBC file with broken entries: "<file>: 3 broken DBC entries skipped (first:
    /// <file>:<line>: <problem>)".
    std::vector<std::string> warnings;
    std::uint64_t dbc_skipped_entries = 0;
};

/// A new map frame for the input thread (VehicleInput::rebase; FrameRecentring says when).
struct FrameRebase {
    std::uint32_t epoch = 0;  ///< EstimatedPose::frame_epoch in the new frame
    map::Projection frame{0.0, 0.0};
    map::FrameTransform to_frame;  ///< the new frame's points from the previous frame's
    /// The road graph to match onto and the transform into the new frame: the input thread builds
    /// its matcher (copy and spatial index, off the render thread).
    std::shared_ptr<const map::RoadGraph> graph;
    map::FrameTransform graph_to_frame;
    double max_distance_from_origin_m = 0.0;  ///< fixes farther from the new origin are rejected
};

class VehicleInput {
public:
    /// Opens the DBC files, the signal map (openDecoder) and the source; throws
    /// std::runtime_error naming the file or interface on failure. `projection` and `store_path`: the map's store (the
    /// simulator plans on it). In sim mode the simulated route is set on `control`; without a
    /// road graph (`graph_problem` says why, map::MapScene::graph_problem) or without a
    /// `simulator` (can_sources.h) the input runs without a source and says so (stats().error).
    /// `graph`: the road graph the map matcher snaps to (the scene's, moved out of it: one copy;
    /// empty: no map matching, the pose is the raw fix). `map_reach_m`: how far from the map
    /// frame's origin the mounted stores reach (map::MapScene::reachM); fixes are accepted up to
    /// that plus the estimator's default range.
    VehicleInput(const DaemonConfig& config, const map::Projection& projection, const std::filesystem::path& store_path,
                 const std::string& graph_problem, std::shared_ptr<const map::RoadGraph> graph,
                 const std::shared_ptr<ipc::ControlState>& control, const std::filesystem::path& data_dir,
                 const ipc::SimulatorFactory& simulator = {}, double map_reach_m = 0.0);
    ~VehicleInput();
    VehicleInput(const VehicleInput&) = delete;
    VehicleInput& operator=(const VehicleInput&) = delete;

    void start();
    void stop();

    /// The route the estimator matches the pose onto (null: none); thread-safe, applied by the
    /// input thread within a few milliseconds.
    void setRoute(std::shared_ptr<const RouteLine> route);

    /// Moves the estimator into another frame, with `route` (the active route in that frame);
    /// applied by the input thread within a few milliseconds. Call from one thread, the one that
    /// calls poseAt().
    void rebase(const FrameRebase& rebase, std::shared_ptr<const RouteLine> route);
    /// Whether the input thread has yet to take the latest rebase().
    [[nodiscard]] bool rebasePending() const { return m_state.load()->parts().frame_epoch != m_epoch; }
    /// The pose at `t` in the newest frame given to rebase(): a snapshot from before the input
    /// thread took it is re-expressed.
    [[nodiscard]] EstimatedPose poseAt(ipc::CanTime t) const;

    /// The newest estimator snapshot (never null), in the frame of its parts().frame_epoch.
    [[nodiscard]] std::shared_ptr<const VehicleState> state() const { return m_state.load(); }
    [[nodiscard]] VehicleInputStats stats() const;
    /// The newest light signals (never null; empty when none is mapped or none came yet).
    /// Thread-safe, lock-free for the reader.
    [[nodiscard]] std::shared_ptr<const AmbientLight> ambientLight() const { return m_light.load(); }
    /// What the setup skipped (DecoderSetup::warnings), for the log.
    [[nodiscard]] const std::vector<std::string>& setupWarnings() const { return m_setup_warnings; }

    /// The decoder of `config`: its DBC files (none: `data_dir`/navmap.dbc) and its signal map
    /// ([[can.signal]], else navmap.dbc's). Throws std::runtime_error naming the file or the
    /// mapping: a file that cannot be read, a DBC file without any message, a mapping to a signal
    /// none of them has. Broken entries of a usable DBC file are skipped and reported in `setup`.
    /// navmapd --check-config runs it too.
    static ipc::VehicleDecoder openDecoder(const DaemonConfig& config, const std::filesystem::path& data_dir,
                                           DecoderSetup* setup);

private:
    void run();
    void consume(const ipc::CanFrame& frame);
    void applyRoute();

    // A route handed over by setRoute() or rebase(): a new object per call, so that "no route" is
    // a change too. Each carries the latest rebase, so that a later route cannot hide it.
    struct RouteUpdate {
        std::shared_ptr<const RouteLine> line;
        std::shared_ptr<const FrameRebase> rebase;
    };

    std::unique_ptr<ipc::VehicleDecoder> m_decoder;
    std::unique_ptr<VehicleStateEstimator> m_estimator;
    std::unique_ptr<ipc::CanSource> m_source;  // null: no source (m_stats.error says why)
    ipc::CanSourceStatus m_source_status;
    std::atomic<std::shared_ptr<const VehicleState>> m_state;
    std::atomic<std::shared_ptr<const AmbientLight>> m_light{std::make_shared<const AmbientLight>()};
    std::atomic<std::shared_ptr<const RouteUpdate>> m_route_update;
    std::shared_ptr<const RouteUpdate> m_applied_route;
    std::shared_ptr<const FrameRebase> m_applied_rebase;  // input thread
    std::shared_ptr<const FrameRebase> m_rebase;          // the caller's thread: the latest rebase()
    std::uint32_t m_epoch = 0;                            // the caller's thread
    std::atomic<bool> m_running{false};
    std::thread m_thread;
    mutable std::mutex m_stats_mutex;
    VehicleInputStats m_stats;
    std::vector<std::string> m_setup_warnings;
    ipc::VehicleSample m_update;
};

}  // namespace navmap::daemon
