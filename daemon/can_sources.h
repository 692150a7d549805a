// SPDX-License-Identifier: Apache-2.0
#pragma once
// The input's CAN source as [input] source says: SocketCAN, a candump replay or the in-process
// simulator (which also sets the route it drives on the control state, as an HMI would). The
// simulator comes in as a SimulatorFactory (navmap/ipc/can/can_source.h): the navmapd
// program passes sim::openSimulatedDrive, the daemon's code does not include the simulator.

#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "config.h"
#include "navmap/ipc/can/can_source.h"
#include "navmap/ipc/control/control_state.h"

namespace navmap::daemon {

/// What the sources need besides the configuration.
struct CanSourceSite {
    std::filesystem::path store_path;       ///< the compiled store (the simulator plans on its graph)
    std::filesystem::path data_dir;         ///< navmap.dbc for the simulator's frames
    std::string graph_problem;              ///< why the road graph is unusable; empty: it is fine
    std::vector<std::uint32_t> frame_keys;  ///< the decoder's frames (SocketCAN filters)
};

struct OpenedCanSource {
    std::unique_ptr<ipc::CanSource> source;  ///< null when the input has no source (error says why)
    std::string name;                        ///< "replay <file>", "sim <from> -> <to>", "socketcan can0"
    std::string error;
};

/// Opens the configured source; throws std::runtime_error naming the file or route problem.
/// Sim mode without a road graph, or without a `simulator` (a program built without it), gives
/// no source, an error, and a warning on stderr.
OpenedCanSource openCanSource(const DaemonConfig& config, const CanSourceSite& site, ipc::ControlState& control,
                              const ipc::SimulatorFactory& simulator);

}  // namespace navmap::daemon
