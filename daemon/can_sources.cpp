// SPDX-License-Identifier: Apache-2.0
#include "can_sources.h"

#include <cstdio>
#include <stdexcept>
#include <variant>

#include "navmap/ipc/can/replay_input.h"
#include "navmap/ipc/can/socketcan_input.h"
#include "navmap/ipc/control/control_protocol.h"

namespace navmap::daemon {

namespace {

OpenedCanSource openSimulator(const DaemonConfig& config, const CanSourceSite& site, ipc::ControlState& control,
                              const ipc::SimulatorFactory& simulator) {
    OpenedCanSource opened;
    opened.name = "sim " + config.sim_from + " -> " + config.sim_to;
    // The map still renders without a source; the simulated car has no road to drive on.
    if (!simulator)
        opened.error = "this program has no drive simulator (input source \"sim\")";
    else if (!site.graph_problem.empty())
        opened.error = "the simulator cannot plan a route: road graph unavailable: " + site.graph_problem;
    if (!opened.error.empty()) {
        std::fprintf(stderr, "<4>navmapd: %s: %s\n", opened.name.c_str(), opened.error.c_str());
        return opened;
    }
    ipc::SimulatedDriveSpec spec;
    spec.store = site.store_path;
    spec.dbc = site.data_dir / "navmap.dbc";
    spec.from = config.sim_from;
    spec.to = config.sim_to;
    spec.speed_factor = config.sim_speed_factor;
    ipc::SimulatedSource sim = simulator(spec);
    // The simulated HMI sets the route it drives with its manoeuvres: the set_route line it would
    // send over the control socket, through the same parser (docs/simulator.md).
    const ipc::ControlParse parsed = ipc::parseControlLine(sim.set_route_line);
    if (!parsed.command) throw std::runtime_error("simulated route: " + parsed.error);
    const auto& route = std::get<ipc::SetRouteCommand>(parsed.command->body);
    if (auto st = control.setRoute(route); !st) throw std::runtime_error("simulated route: " + st.message());
    opened.source = std::move(sim.source);
    return opened;
}

}  // namespace

OpenedCanSource openCanSource(const DaemonConfig& config, const CanSourceSite& site, ipc::ControlState& control,
                              const ipc::SimulatorFactory& simulator) {
    OpenedCanSource opened;
    switch (config.input) {
        case InputSource::Replay:
            opened.source =
                std::make_unique<ipc::ReplayInput>(config.replay_log, config.replay_speed, config.replay_loop);
            break;
        case InputSource::Sim: return openSimulator(config, site, control, simulator);
        case InputSource::SocketCan:
            opened.source = std::make_unique<ipc::SocketCanInput>(config.can_interface, site.frame_keys);
            break;
    }
    opened.name = opened.source->name();
    return opened;
}

}  // namespace navmap::daemon
