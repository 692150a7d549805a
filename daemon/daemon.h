// SPDX-License-Identifier: Apache-2.0
#pragma once
// navmapd's main loop (docs/architecture.md "Data flow"): vehicle input -> pose at frame time -> one scene
// state per tick -> one render per display profile in use -> frame server. The render loop
// runs on the calling thread and never waits for a client, the control socket or CAN input:
// those run on their own threads and hand over immutable snapshots.

#include <chrono>
#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <string>

#include "config.h"
#include "navmap/ipc/can/can_source.h"

namespace navmap::daemon {

struct RunOptions {
    std::optional<double> run_for_s;                   ///< stop after this long (tests, demo); else until SIGTERM
    std::optional<std::filesystem::path> config_path;  ///< re-read on SIGHUP
    std::filesystem::path data_dir;                    ///< navmap.dbc and the shipped data
    bool noop_renderer = false;                        ///< no GL (tests of the loop itself)
    bool render_all_profiles = false;                  ///< render profiles without clients too
    /// The drive simulator for [input] source = "sim" (navmapd passes sim::openSimulatedDrive);
    /// empty: sim mode runs without a source and says so.
    ipc::SimulatorFactory simulator;
    /// The time of day the sun is worked out for in [style] mode = "auto" (tests simulate one);
    /// empty: the system clock.
    std::function<std::chrono::system_clock::time_point()> wall_clock;
};

/// Runs the daemon until SIGTERM/SIGINT (or run_for_s). Returns the process exit status.
/// Setup failures are reported as one clear error line and return 1.
int runDaemon(DaemonConfig config, const RunOptions& options);

}  // namespace navmap::daemon
