// SPDX-License-Identifier: Apache-2.0
#pragma once
// The in-process stand-in for vehicle input used by the demo: the vehicle follows a planned
// route with a simple speed profile (accelerate, cruise by road, brake to a stop).

#include "navmap/render/map_scene.h"

namespace navmap::daemon {

class SimulatedDrive {
public:
    SimulatedDrive(render::PlannedDrive drive, double cruise_mps = 14.0);

    /// Advances simulated time by dt seconds.
    void advance(double dt);
    [[nodiscard]] double measure() const { return m_measure; }
    [[nodiscard]] double speed() const { return m_speed; }
    [[nodiscard]] bool finished() const { return m_measure >= length(); }
    [[nodiscard]] double length() const { return m_drive.line.empty() ? 0.0 : m_drive.line.back().measure_m; }
    [[nodiscard]] const render::PlannedDrive& drive() const { return m_drive; }
    [[nodiscard]] render::PlannedDrive& drive() { return m_drive; }

private:
    render::PlannedDrive m_drive;
    double m_cruise;
    double m_measure = 0.0;
    double m_speed = 0.0;
};

}  // namespace navmap::daemon
