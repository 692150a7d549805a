// SPDX-License-Identifier: Apache-2.0
#pragma once
// CanSource: where navmapd's input thread takes its CAN frames from: SocketCAN, a candump replay
// or the drive simulator (sim/can_source). Each hands over plain CAN frames, which the one DBC
// decoder (VehicleDecoder) turns into vehicle samples for the estimator, so the input thread
// treats them all alike. A source is owned and called by the input thread only. The interface
// lives with the CAN input it abstracts: SocketCanInput and ReplayInput here, the simulator in
// sim/ (without including the daemon), and navmapd's composition root picks one.

#include <chrono>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <string>

#include "navmap/ipc/can/can_frame.h"
#include "navmap/ipc/can/replayer.h"  // FrameSink

namespace navmap::ipc {

/// What a source reports for status and /metrics; fields a source has no part in stay zero.
struct CanSourceStatus {
    std::uint64_t can_error_frames = 0, can_bus_off = 0, can_kernel_drops = 0;
    std::string can_state;  ///< "open", "retrying: bind(can0): No such device"
    std::uint64_t replay_loops = 0;
    std::uint64_t replay_malformed_lines = 0;  ///< skipped lines of the replayed log (all passes)
    std::uint64_t replay_time_errors = 0;      ///< frames whose time did not fit the clock
    std::string error;                         ///< why the source gives no (more) frames; empty while it works
};

class CanSource {
public:
    virtual ~CanSource() = default;

    /// What status calls it: "replay <file>", "sim <from> -> <to>", "socketcan can0".
    [[nodiscard]] virtual std::string name() const = 0;
    /// The input thread starts: a replay's first frame is due at `now`.
    virtual void start(CanTime now) = 0;
    /// Passes the frames that are due at `now` (or have arrived) to `sink`, oldest first; never blocks.
    virtual void poll(CanTime now, const FrameSink& sink) = 0;
    /// Sleeps until frames may be ready, at most `timeout`.
    virtual void wait(std::chrono::milliseconds timeout) = 0;
    /// Updates `status` with the source's counters; a problem is logged the first time it shows.
    virtual void report(CanSourceStatus& status) = 0;
};

/// A simulated drive, as [input] source = "sim" configures it.
struct SimulatedDriveSpec {
    std::filesystem::path store;  ///< compiled tile store (the drive is planned on its road graph)
    std::filesystem::path dbc;    ///< navmap.dbc, the frames' layout
    std::string from;             ///< "lat,lon" or a place name
    std::string to;
    double speed_factor = 1.0;  ///< playback speed (2 = twice as fast)
};

/// A simulated drive's source and the set_route line a simulated HMI sends for it.
struct SimulatedSource {
    std::unique_ptr<CanSource> source;
    std::string set_route_line;
};

/// Opens a simulated drive; throws naming the problem (store, DBC, unknown place, no route). The
/// simulator (sim/can_source: sim::openSimulatedDrive) implements it and the navmapd program
/// hands it to the daemon (RunOptions::simulator), so the daemon's library neither includes nor
/// links the simulator.
using SimulatorFactory = std::function<SimulatedSource(const SimulatedDriveSpec&)>;

}  // namespace navmap::ipc
