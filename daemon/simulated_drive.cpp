// SPDX-License-Identifier: Apache-2.0
#include "simulated_drive.h"

#include <algorithm>
#include <cmath>

namespace navmap::daemon {

namespace {
constexpr double kAccel = 1.5;  // m/s^2
constexpr double kBrake = 2.5;  // m/s^2
}  // namespace

SimulatedDrive::SimulatedDrive(render::PlannedDrive drive, double cruise_mps)
    : m_drive(std::move(drive)), m_cruise(cruise_mps) {}

void SimulatedDrive::advance(double dt) {
    const double remaining = length() - m_measure;
    // Brake so that v^2 = 2 a d reaches zero at the end of the route.
    const double stop_speed = std::sqrt(std::max(0.0, 2.0 * kBrake * remaining));
    const double target = std::min(m_cruise, stop_speed);
    if (m_speed < target) m_speed = std::min(target, m_speed + kAccel * dt);
    else m_speed = std::max(target, m_speed - kBrake * dt);
    m_measure = std::min(length(), m_measure + m_speed * dt);
}

}  // namespace navmap::daemon
