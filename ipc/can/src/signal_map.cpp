// SPDX-License-Identifier: Apache-2.0
#include "navmap/ipc/can/signal_map.h"

#include <algorithm>
#include <cctype>
#include <fstream>
#include <numbers>
#include <optional>
#include <sstream>

#include <toml++/toml.h>

#include "navmap/common/untrusted_file.h"

namespace navmap::ipc {
namespace {

// A signal map is a few KiB of TOML; bounded like the daemon's config.
constexpr FileKind kSignalMapFile{"signal map", std::uint64_t{4} << 20};

enum class Dim { None, Speed, Angle, AngularRate, Length, Accel };

Dim dimensionOf(VssSignal s) {
    switch (s) {
        case VssSignal::Latitude:
        case VssSignal::Longitude:
        case VssSignal::Heading:
        case VssSignal::SteeringWheelAngle: return Dim::Angle;
        case VssSignal::Altitude: return Dim::Length;
        case VssSignal::Speed: return Dim::Speed;
        case VssSignal::YawRate: return Dim::AngularRate;
        case VssSignal::AccelLongitudinal:
        case VssSignal::AccelLateral: return Dim::Accel;
        case VssSignal::FixType:
        case VssSignal::GnssCounter:
        case VssSignal::LowBeam:
        case VssSignal::LightIntensity: return Dim::None;
    }
    return Dim::None;
}

struct UnitEntry {
    std::string_view name;  // lower case
    Dim dim;
    double to_canonical;  // km/h, degrees, degrees/s, m, m/s^2
};

constexpr double kRadToDeg = 180.0 / std::numbers::pi;

constexpr UnitEntry kUnits[] = {
    {"km/h", Dim::Speed, 1.0},
    {"kph", Dim::Speed, 1.0},
    {"kmh", Dim::Speed, 1.0},
    {"unit_kilometerperhour", Dim::Speed, 1.0},
    {"m/s", Dim::Speed, 3.6},
    {"mps", Dim::Speed, 3.6},
    {"unit_meterpersecond", Dim::Speed, 3.6},
    {"mph", Dim::Speed, 1.609344},
    {"deg", Dim::Angle, 1.0},
    {"degree", Dim::Angle, 1.0},
    {"degrees", Dim::Angle, 1.0},
    {"\xc2\xb0", Dim::Angle, 1.0},
    {"unit_degreofarc", Dim::Angle, 1.0},
    {"rad", Dim::Angle, kRadToDeg},
    {"deg/s", Dim::AngularRate, 1.0},
    {"degrees/s", Dim::AngularRate, 1.0},
    {"\xc2\xb0/s", Dim::AngularRate, 1.0},
    {"unit_degreofarcpersecon", Dim::AngularRate, 1.0},
    {"unit_degreofarcpersecond", Dim::AngularRate, 1.0},
    {"rad/s", Dim::AngularRate, kRadToDeg},
    {"unit_radianpersecond", Dim::AngularRate, kRadToDeg},
    {"m", Dim::Length, 1.0},
    {"cm", Dim::Length, 0.01},
    {"mm", Dim::Length, 0.001},
    {"km", Dim::Length, 1000.0},
    {"unit_meter", Dim::Length, 1.0},
    {"m/s^2", Dim::Accel, 1.0},
    {"m/s2", Dim::Accel, 1.0},
    {"m/s\xc2\xb2", Dim::Accel, 1.0},
    {"unit_meterpersecondsquar", Dim::Accel, 1.0},
    {"g", Dim::Accel, 9.80665},
};

}  // namespace

std::optional<double> unitConversion(std::string_view dbc_unit, VssSignal target) {
    const Dim want = dimensionOf(target);
    if (want == Dim::None) {
        return 1.0;  // counters and codes: the unit does not matter
    }
    std::string lower;
    for (const char c : dbc_unit) {
        if (c != ' ') {
            lower.push_back(static_cast<char>(std::tolower(static_cast<unsigned char>(c))));
        }
    }
    for (const auto& u : kUnits) {
        if (u.name == lower) {
            if (u.dim != want) {
                return std::nullopt;
            }
            return u.to_canonical;
        }
    }
    return std::nullopt;
}

Result<SignalMap> SignalMap::fromToml(std::string_view text, std::string_view source_name, std::string_view array_key) {
    const std::string src(source_name);
    toml::table root;
    try {
        root = toml::parse(text, src);
    } catch (const toml::parse_error& e) {
        const auto& b = e.source().begin;
        return Error{src + ":" + std::to_string(b.line) + ":" + std::to_string(b.column) + ": " +
                     std::string(e.description())};
    }
    SignalMap map;
    const toml::node_view<toml::node> node = root.at_path(array_key);
    if (!node) {
        return Error{src + ": no [[" + std::string(array_key) + "]] entries"};
    }
    const toml::array* arr = node.as_array();
    if (arr == nullptr) {
        return Error{src + ": '" + std::string(array_key) + "' must be an array of tables ([[" +
                     std::string(array_key) + "]])"};
    }
    std::size_t index = 0;
    for (const toml::node& entry : *arr) {
        ++index;
        const toml::table* t = entry.as_table();
        const auto where = [&](const toml::node& n) {
            const auto line = n.source().begin.line;
            return src + ":" + std::to_string(line) + ": " + std::string(array_key) + " #" + std::to_string(index);
        };
        if (t == nullptr) {
            return Error{where(entry) + ": entry is not a table"};
        }
        SignalMapping m;
        for (const auto& [key, value] : *t) {
            const std::string_view k = key.str();
            if (k == "vss" || k == "message" || k == "signal" || k == "dbc" || k == "unit" || k == "sign_signal") {
                const auto s = value.value<std::string>();
                if (!s) {
                    return Error{where(value) + ": '" + std::string(k) + "' must be a string"};
                }
                if (k == "vss") {
                    const auto v = vssFromName(*s);
                    if (!v) {
                        return Error{where(value) + ": unknown VSS name '" + *s + "'"};
                    }
                    m.target = *v;
                } else if (k == "message") {
                    m.message = *s;
                } else if (k == "signal") {
                    m.signal = *s;
                } else if (k == "dbc") {
                    m.dbc = *s;
                } else if (k == "unit") {
                    m.unit = *s;
                } else {
                    m.sign_signal = *s;
                }
            } else if (k == "scale" || k == "bias") {
                const auto d = value.value<double>();
                if (!d) {
                    return Error{where(value) + ": '" + std::string(k) + "' must be a number"};
                }
                (k == "scale" ? m.scale : m.bias) = *d;
            } else {
                return Error{where(value) + ": unknown key '" + std::string(k) + "'"};
            }
        }
        if (!t->contains("vss") || m.message.empty() || m.signal.empty()) {
            return Error{where(entry) + ": 'vss', 'message' and 'signal' are required"};
        }
        map.add(std::move(m));
    }
    return map;
}

Result<SignalMap> SignalMap::loadToml(const std::filesystem::path& path, std::string_view array_key) {
    // Regular files only, opened without blocking, at most kSignalMapFile.max_bytes read.
    std::string problem;
    const std::optional<std::string> text = UntrustedFile::readText(path, kSignalMapFile, problem);
    if (!text) {
        return Error{problem};
    }
    return fromToml(*text, path.string(), array_key);
}

SignalMap SignalMap::navmapDefaults() {
    SignalMap m;
    m.add({VssSignal::Latitude, "NAV_Position", "NAV_Latitude", {}, {}, 1.0, 0.0, {}});
    m.add({VssSignal::Longitude, "NAV_Position", "NAV_Longitude", {}, {}, 1.0, 0.0, {}});
    m.add({VssSignal::Heading, "NAV_Motion", "NAV_Heading", {}, {}, 1.0, 0.0, {}});
    m.add({VssSignal::Speed, "NAV_Motion", "NAV_Speed", {}, {}, 1.0, 0.0, {}});
    m.add({VssSignal::YawRate, "NAV_Motion", "NAV_YawRate", {}, {}, 1.0, 0.0, {}});
    m.add({VssSignal::FixType, "NAV_Motion", "NAV_FixType", {}, {}, 1.0, 0.0, {}});
    m.add({VssSignal::GnssCounter, "NAV_Motion", "NAV_Counter", {}, {}, 1.0, 0.0, {}});
    m.add({VssSignal::Altitude, "NAV_Info", "NAV_Altitude", {}, {}, 1.0, 0.0, {}});
    return m;
}

}  // namespace navmap::ipc
