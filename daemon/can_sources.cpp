// SPDX-License-Identifier: Apache-2.0
#include "can_sources.h"

#include <cstdio>
#include <stdexcept>
#include <variant>

#include "navmap/ipc/control_protocol.h"

#include "navmap/sim/simulated_can_source.h"
#include "replay_input.h"
#include "socketcan_input.h"

namespace navmap::daemon {

namespace {

OpenedCanSource openSimulator(const DaemonConfig& config, const CanSourceSite& site, ipc::ControlState& control) {
    OpenedCanSource opened;
    opened.name = "sim " + config.sim_from + " -> " + config.sim_to;
    if (!site.graph_problem.empty()) {
        // The map still renders; the simulated car has no road to drive on.
        opened.error = "the simulator cannot plan a route: road graph unavailable: " + site.graph_problem;
        std::fprintf(stderr, "<4>navmapd: %s: %s\n", opened.name.c_str(), opened.error.c_str());
        return opened;
    }
    sim::SimulatedDriveRequest request;
    request.store = site.store_path;
    request.dbc = site.data_dir / "navmap.dbc";
    request.from = config.sim_from;
    request.to = config.sim_to;
    request.speed_factor = config.sim_speed_factor;
    auto simulator = std::make_unique<sim::SimulatedCanSource>(request);
    // The simulated HMI sets the route it drives with its manoeuvres: the set_route line it would
    // send over the control socket, through the same parser (docs/simulator.md).
    const ipc::ControlParse parsed = ipc::parseControlLine(simulator->setRouteLine());
    if (!parsed.command) throw std::runtime_error("simulated route: " + parsed.error);
    const auto& route = std::get<ipc::SetRouteCommand>(parsed.command->body);
    if (auto st = control.setRoute(route); !st) throw std::runtime_error("simulated route: " + st.message());
    opened.source = std::move(simulator);
    return opened;
}

}  // namespace

OpenedCanSource openCanSource(const DaemonConfig& config, const CanSourceSite& site, ipc::ControlState& control) {
    OpenedCanSource opened;
    switch (config.input) {
        case InputSource::Replay:
            opened.source = std::make_unique<ReplayInput>(config.replay_log, config.replay_speed, config.replay_loop);
            break;
        case InputSource::Sim: return openSimulator(config, site, control);
        case InputSource::SocketCan:
            opened.source = std::make_unique<SocketCanInput>(config.can_interface, site.frame_keys);
            break;
    }
    opened.name = opened.source->name();
    return opened;
}

}  // namespace navmap::daemon
