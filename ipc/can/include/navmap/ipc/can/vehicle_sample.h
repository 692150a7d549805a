// SPDX-License-Identifier: Apache-2.0
#pragma once
// VehicleSample: vehicle quantities decoded from CAN, named after COVESA VSS, each with the receive
// time of the frame it came from. Used both for one decoded update (only the quantities that frame
// carried are present) and for the merged latest state.

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string_view>

#include "navmap/ipc/can/can_frame.h"

namespace navmap::ipc {

/// Quantities the decoder can produce. Units are the VSS units listed in vssUnit().
enum class VssSignal : std::uint8_t {
    Latitude,            ///< Vehicle.CurrentLocation.Latitude, degrees (WGS84)
    Longitude,           ///< Vehicle.CurrentLocation.Longitude, degrees (WGS84)
    Altitude,            ///< Vehicle.CurrentLocation.Altitude, m
    Heading,             ///< Vehicle.CurrentLocation.Heading, degrees clockwise from north, [0, 360]
    FixType,             ///< Vehicle.CurrentLocation.GNSSReceiver.FixType, numeric code (see docs/can-input.md)
    Speed,               ///< Vehicle.Speed, km/h
    YawRate,             ///< Vehicle.AngularVelocity.Yaw, degrees/s
    SteeringWheelAngle,  ///< Vehicle.Chassis.SteeringWheel.Angle, degrees
    AccelLongitudinal,   ///< Vehicle.Acceleration.Longitudinal, m/s^2
    AccelLateral,        ///< Vehicle.Acceleration.Lateral, m/s^2
    GnssCounter,         ///< NavMap.GnssMessageCounter (project extension, not VSS): rolling counter
    LowBeam,             ///< Vehicle.Body.Lights.Beam.Low.IsOn: 1 on, 0 off (day and night, docs/can-input.md)
    LightIntensity,      ///< Vehicle.Exterior.LightIntensity, percent: 0 dark .. 100 full daylight
};
inline constexpr std::size_t kVssSignalCount = 13;

/// "Vehicle.Speed" etc.
std::string_view vssName(VssSignal s) noexcept;
/// "km/h", "degrees", "degrees/s", "m", "m/s^2", "percent" or "" (dimensionless).
std::string_view vssUnit(VssSignal s) noexcept;
/// Plausible range of each quantity; values outside are rejected.
double vssMinimum(VssSignal s) noexcept;
double vssMaximum(VssSignal s) noexcept;
std::optional<VssSignal> vssFromName(std::string_view name) noexcept;

struct VehicleSample {
    /// Receive time of the newest frame that contributed.
    CanTime source_time{};
    std::array<std::optional<double>, kVssSignalCount> values{};
    std::array<CanTime, kVssSignalCount> times{};

    std::optional<double> get(VssSignal s) const noexcept { return values[static_cast<std::size_t>(s)]; }
    CanTime timeOf(VssSignal s) const noexcept { return times[static_cast<std::size_t>(s)]; }
    void set(VssSignal s, double value, CanTime t) noexcept {
        values[static_cast<std::size_t>(s)] = value;
        times[static_cast<std::size_t>(s)] = t;
        if (t > source_time) {
            source_time = t;
        }
    }
    bool empty() const noexcept {
        for (const auto& v : values) {
            if (v) {
                return false;
            }
        }
        return true;
    }
    /// Copies every quantity present in `update` into this sample.
    void merge(const VehicleSample& update) noexcept {
        for (std::size_t i = 0; i < kVssSignalCount; ++i) {
            if (update.values[i]) {
                values[i] = update.values[i];
                times[i] = update.times[i];
            }
        }
        if (update.source_time > source_time) {
            source_time = update.source_time;
        }
    }
};

}  // namespace navmap::ipc
