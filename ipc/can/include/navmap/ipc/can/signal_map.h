// SPDX-License-Identifier: Apache-2.0
#pragma once
// SignalMap: configuration saying which DBC signal feeds which vehicle quantity (VSS name), so that
// a vehicle's own DBC (e.g. Ford speed and yaw rate) can be combined with navmap.dbc's GNSS node.
// TOML form (an array of tables, by default named "signal"):
//
//   [[signal]]
//   vss = "Vehicle.Speed"            # required, see VssSignal
//   message = "BrakeSysFeatures"     # required: message name, or id ("0x415", "1045")
//   signal = "Veh_V_ActlBrk"         # required
//   dbc = "ford_lincoln_base_pt.dbc" # optional: only this database (file name suffix)
//   unit = "km/h"                    # optional: overrides the DBC's unit for conversion
//   scale = 1.0                      # optional: extra factor after unit conversion
//   bias = 0.0                       # optional: extra offset after scale
//   sign_signal = "ESP_VZ_Gierrate"  # optional: 1-bit signal in the same message, 1 = negative

#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "navmap/ipc/can/vehicle_sample.h"
#include "navmap/ipc/net/result.h"

namespace navmap::ipc {

struct SignalMapping {
    VssSignal target = VssSignal::Speed;
    std::string message;
    std::string signal;
    std::string dbc;
    std::string unit;
    double scale = 1.0;
    double bias = 0.0;
    std::string sign_signal;
};

class SignalMap {
public:
    /// Parses TOML text; `arrayKey` is a dotted path to the array of tables ("signal", "can.signal").
    static Result<SignalMap> fromToml(std::string_view text, std::string_view source_name,
                                      std::string_view array_key = "signal");
    /// Reads a regular file of at most 4 MiB (opened without blocking) and parses it.
    static Result<SignalMap> loadToml(const std::filesystem::path& path, std::string_view array_key = "signal");
    /// The mapping for the project's own data/navmap.dbc (GNSS node).
    static SignalMap navmapDefaults();

    void add(SignalMapping mapping) { m_mappings.push_back(std::move(mapping)); }
    const std::vector<SignalMapping>& mappings() const& noexcept { return m_mappings; }
    /// On a temporary (e.g. `for (auto& m : SignalMap::navmapDefaults().mappings())`) return by value.
    std::vector<SignalMapping> mappings() && { return std::move(m_mappings); }

private:
    std::vector<SignalMapping> m_mappings;
};

/// Multiplier from a DBC unit string to the canonical unit of `target` (e.g. "rad/s" -> degrees/s
/// = 57.29...). Case-insensitive; knows SI-style spellings and the Vector "Unit_..." names.
/// nullopt when the unit is unknown or of the wrong dimension.
std::optional<double> unitConversion(std::string_view dbc_unit, VssSignal target);

}  // namespace navmap::ipc
