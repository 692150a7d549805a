// SPDX-License-Identifier: Apache-2.0
#pragma once
// SimulatedCanSource: navmapd's in-process simulator as a daemon CanSource. The simulated drive
// (route, speed profile) is encoded by the GNSS node emulation (FrameGenerator) into navmap.dbc
// frames: position, and speed and yaw rate in NAV_Motion, the same frames a real GNSS node puts
// on the bus. They are played with real timing, looping, and go through the daemon's DBC decoder
// like frames of any other source. Input thread only (after construction).

#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "navmap/common/geo_coordinate.h"
#include "navmap/ipc/can/can_source.h"

namespace navmap::ipc {
class Replayer;
}

namespace navmap::sim {

using SimulatedDriveRequest = ipc::SimulatedDriveSpec;

class SimulatedCanSource final : public ipc::CanSource {
public:
    /// Plans the drive and generates its frames. Throws SimError naming the problem (store, DBC,
    /// unknown place, no route).
    explicit SimulatedCanSource(const SimulatedDriveRequest& request);
    ~SimulatedCanSource() override;

    /// The drive's route points, WGS84 degrees.
    [[nodiscard]] const std::vector<GeoCoordinate>& routePoints() const { return m_route; }
    /// The set_route line a simulated HMI sends for this drive: the route with its manoeuvres
    /// (map/guidance: turn classes, roundabout exits, street names), docs/simulator.md.
    [[nodiscard]] const std::string& setRouteLine() const { return m_set_route; }

    [[nodiscard]] std::string name() const override { return m_name; }
    void start(ipc::CanTime now) override;
    void poll(ipc::CanTime now, const ipc::FrameSink& sink) override;
    void wait(std::chrono::milliseconds timeout) override;
    void report(ipc::CanSourceStatus& status) override;

private:
    std::string m_name;
    std::vector<GeoCoordinate> m_route;
    std::string m_set_route;
    std::unique_ptr<ipc::Replayer> m_replayer;
};

/// The simulator as navmapd's daemon::SimulatorFactory: a SimulatedCanSource with its set_route line.
ipc::SimulatedSource openSimulatedDrive(const ipc::SimulatedDriveSpec& spec);

}  // namespace navmap::sim
