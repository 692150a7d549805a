// SPDX-License-Identifier: Apache-2.0
#include "navmap/ipc/can/vehicle_sample.h"

namespace navmap::ipc {
namespace {

struct VssInfo {
    std::string_view name;
    std::string_view unit;
    double minimum;
    double maximum;
};

// Ranges: the VSS ranges where VSS gives one (latitude, longitude, heading), otherwise generous
// physical limits for a road vehicle so that only garbage is rejected.
constexpr std::array<VssInfo, kVssSignalCount> kInfo{{
    {"Vehicle.CurrentLocation.Latitude", "degrees", -90.0, 90.0},
    {"Vehicle.CurrentLocation.Longitude", "degrees", -180.0, 180.0},
    {"Vehicle.CurrentLocation.Altitude", "m", -1000.0, 10000.0},
    {"Vehicle.CurrentLocation.Heading", "degrees", 0.0, 360.0},
    {"Vehicle.CurrentLocation.GNSSReceiver.FixType", "", 0.0, 15.0},
    {"Vehicle.Speed", "km/h", -300.0, 600.0},
    {"Vehicle.AngularVelocity.Yaw", "degrees/s", -720.0, 720.0},
    {"Vehicle.Chassis.SteeringWheel.Angle", "degrees", -3600.0, 3600.0},
    {"Vehicle.Acceleration.Longitudinal", "m/s^2", -100.0, 100.0},
    {"Vehicle.Acceleration.Lateral", "m/s^2", -100.0, 100.0},
    {"NavMap.GnssMessageCounter", "", 0.0, 4294967295.0},
    {"Vehicle.Body.Lights.Beam.Low.IsOn", "", 0.0, 1.0},
    {"Vehicle.Exterior.LightIntensity", "percent", 0.0, 100.0},
}};

}  // namespace

std::string_view vssName(VssSignal s) noexcept { return kInfo[static_cast<std::size_t>(s)].name; }
std::string_view vssUnit(VssSignal s) noexcept { return kInfo[static_cast<std::size_t>(s)].unit; }
double vssMinimum(VssSignal s) noexcept { return kInfo[static_cast<std::size_t>(s)].minimum; }
double vssMaximum(VssSignal s) noexcept { return kInfo[static_cast<std::size_t>(s)].maximum; }

std::optional<VssSignal> vssFromName(std::string_view name) noexcept {
    for (std::size_t i = 0; i < kInfo.size(); ++i) {
        if (kInfo[i].name == name) {
            return static_cast<VssSignal>(i);
        }
    }
    return std::nullopt;
}

}  // namespace navmap::ipc
