// SPDX-License-Identifier: Apache-2.0
#include "navmap/sim/simulated_can_source.h"

#include <thread>

#include "navmap/sim/drive_simulator.h"
#include "navmap/sim/route_message.h"

namespace navmap::sim {

SimulatedCanSource::SimulatedCanSource(const SimulatedDriveRequest& request)
    : m_name("sim " + request.from + " -> " + request.to) {
    DriveRequest drive;
    drive.store = request.store;
    drive.dbc = request.dbc;
    drive.from = request.from;
    drive.to = request.to;
    const DriveSimulator simulator = DriveSimulator::create(drive);
    ipc::ReplayOptions replay;
    replay.loop = true;
    replay.restamp = true;
    replay.speed = request.speed_factor;
    m_replayer = simulator.replayer(replay);
    const map::Projection projection = simulator.projection();
    m_route.reserve(simulator.route().line.size());
    for (const auto& p : simulator.route().line) {
        GeoCoordinate point;
        projection.reverse(p.position, point.lat_deg, point.lon_deg);
        m_route.push_back(point);
    }
    m_set_route = setRouteMessage(simulator.route(), projection, "sim");
}

SimulatedCanSource::~SimulatedCanSource() = default;

void SimulatedCanSource::start(ipc::CanTime now) { m_replayer->reset(now); }

void SimulatedCanSource::poll(ipc::CanTime now, const ipc::FrameSink& sink) { m_replayer->advanceTo(now, sink); }

void SimulatedCanSource::wait(std::chrono::milliseconds timeout) { std::this_thread::sleep_for(timeout); }

void SimulatedCanSource::report(ipc::CanSourceStatus& status) {
    status.replay_loops = m_replayer->loops();
    status.replay_time_errors = m_replayer->timeErrors();
}

ipc::SimulatedSource openSimulatedDrive(const ipc::SimulatedDriveSpec& spec) {
    auto source = std::make_unique<SimulatedCanSource>(spec);
    std::string line = source->setRouteLine();
    return {std::move(source), std::move(line)};
}

}  // namespace navmap::sim
