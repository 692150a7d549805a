// SPDX-License-Identifier: Apache-2.0
#include "navmap/map/compile/speed_limit_tags.h"

#include <array>
#include <charconv>
#include <cmath>

namespace navmap::map {

namespace {

struct ImplicitLimit {
    std::string_view code;
    std::uint16_t kmh;  ///< 0: listed, but no fixed limit (e.g. German motorways)
};

// The implicit maxspeed values ("CC:context") of European countries for cars, from the
// OpenStreetMap wiki page "Default speed limits"
// (https://wiki.openstreetmap.org/wiki/Default_speed_limits, CC BY-SA 2.0), as parsed into
// legal_default_speeds.json by osm-legal-default-speeds
// (https://github.com/westnordost/osm-legal-default-speeds, demo/distribution/, commit 97ce687
// of 2023-10-21: wiki revision 2607051 of 2023-10-21). Each value is that file's `maxspeed` of
// the country's road type: "urban", "rural" (AD, IT: the country's general limit, the file has no
// "rural" row), "motorway" (CZ, NL: "rural motorway"; IT: "Autostrada"); trunk is the
// "motorroad" (AT, CH, GR, HR, HU, PT, RS; NL: "rural motorroad"), FR: "rural dual carriageway",
// IT: "Strada extraurbana principale", RO: express and European national roads, SI: "trunk";
// PL:expressway the dual-carriageway "motorroad"; IE:national "National road"; GB:nsl_restricted,
// nsl_single, nsl_dual the "restricted road", "rural" and "dual carriageway"; living_street,
// pedestrian_zone, bicycle_road the "living street", "pedestrian zone", "cycle street". BE:motorway
// is the value of all three Belgian regions. Miles per hour converted and rounded. Contexts with
// no fixed number (a German motorway, a living street at walking pace) are listed with 0: known
// codes, unknown limits.
constexpr std::array kImplicitLimits{
    ImplicitLimit{"AD:urban", 50},          ImplicitLimit{"AD:rural", 60},
    ImplicitLimit{"AD:motorway", 120},      ImplicitLimit{"AL:urban", 40},
    ImplicitLimit{"AL:rural", 80},          ImplicitLimit{"AL:motorway", 110},
    ImplicitLimit{"AT:urban", 50},          ImplicitLimit{"AT:rural", 100},
    ImplicitLimit{"AT:trunk", 100},         ImplicitLimit{"AT:motorway", 130},
    ImplicitLimit{"BA:urban", 50},          ImplicitLimit{"BA:rural", 80},
    ImplicitLimit{"BA:motorway", 130},      ImplicitLimit{"BE:motorway", 120},
    ImplicitLimit{"BE-BRU:urban", 30},      ImplicitLimit{"BE-BRU:rural", 70},
    ImplicitLimit{"BE-BRU:motorway", 120},  ImplicitLimit{"BE-VLG:urban", 50},
    ImplicitLimit{"BE-VLG:rural", 70},      ImplicitLimit{"BE-VLG:motorway", 120},
    ImplicitLimit{"BE-WAL:urban", 50},      ImplicitLimit{"BE-WAL:rural", 90},
    ImplicitLimit{"BE-WAL:motorway", 120},  ImplicitLimit{"BG:urban", 50},
    ImplicitLimit{"BG:rural", 90},          ImplicitLimit{"BG:motorway", 140},
    ImplicitLimit{"BY:urban", 60},          ImplicitLimit{"BY:rural", 90},
    ImplicitLimit{"BY:motorway", 110},      ImplicitLimit{"CH:urban", 50},
    ImplicitLimit{"CH:rural", 80},          ImplicitLimit{"CH:trunk", 100},
    ImplicitLimit{"CH:motorway", 120},      ImplicitLimit{"CZ:urban", 50},
    ImplicitLimit{"CZ:rural", 90},          ImplicitLimit{"CZ:motorway", 130},
    ImplicitLimit{"CZ:living_street", 20},  ImplicitLimit{"CZ:pedestrian_zone", 20},
    ImplicitLimit{"DE:urban", 50},          ImplicitLimit{"DE:rural", 100},
    ImplicitLimit{"DE:motorway", 0},        ImplicitLimit{"DE:living_street", 0},
    ImplicitLimit{"DE:bicycle_road", 30},   ImplicitLimit{"DK:urban", 50},
    ImplicitLimit{"DK:rural", 80},          ImplicitLimit{"DK:motorway", 130},
    ImplicitLimit{"EE:urban", 50},          ImplicitLimit{"EE:rural", 90},
    ImplicitLimit{"ES:urban", 30},          ImplicitLimit{"ES:rural", 90},
    ImplicitLimit{"ES:motorway", 120},      ImplicitLimit{"ES:living_street", 20},
    ImplicitLimit{"FI:urban", 50},          ImplicitLimit{"FI:rural", 100},
    ImplicitLimit{"FR:urban", 50},          ImplicitLimit{"FR:rural", 80},
    ImplicitLimit{"FR:trunk", 110},         ImplicitLimit{"FR:motorway", 130},
    ImplicitLimit{"GB:nsl_restricted", 48}, ImplicitLimit{"GB:nsl_single", 97},
    ImplicitLimit{"GB:nsl_dual", 113},      ImplicitLimit{"GB:motorway", 113},
    ImplicitLimit{"GR:urban", 50},          ImplicitLimit{"GR:rural", 90},
    ImplicitLimit{"GR:trunk", 110},         ImplicitLimit{"GR:motorway", 130},
    ImplicitLimit{"HR:urban", 50},          ImplicitLimit{"HR:rural", 90},
    ImplicitLimit{"HR:trunk", 110},         ImplicitLimit{"HR:motorway", 130},
    ImplicitLimit{"HU:urban", 50},          ImplicitLimit{"HU:rural", 90},
    ImplicitLimit{"HU:trunk", 110},         ImplicitLimit{"HU:motorway", 130},
    ImplicitLimit{"IE:urban", 50},          ImplicitLimit{"IE:rural", 80},
    ImplicitLimit{"IE:national", 100},      ImplicitLimit{"IE:motorway", 120},
    ImplicitLimit{"IS:urban", 50},          ImplicitLimit{"IS:rural", 80},
    ImplicitLimit{"IT:urban", 50},          ImplicitLimit{"IT:rural", 90},
    ImplicitLimit{"IT:trunk", 110},         ImplicitLimit{"IT:motorway", 130},
    ImplicitLimit{"LI:urban", 50},          ImplicitLimit{"LI:rural", 80},
    ImplicitLimit{"LT:urban", 50},          ImplicitLimit{"LT:rural", 90},
    ImplicitLimit{"LT:motorway", 130},      ImplicitLimit{"LU:urban", 50},
    ImplicitLimit{"LU:rural", 90},          ImplicitLimit{"LU:motorway", 130},
    ImplicitLimit{"LV:urban", 50},          ImplicitLimit{"LV:rural", 90},
    ImplicitLimit{"MD:urban", 50},          ImplicitLimit{"MD:rural", 90},
    ImplicitLimit{"MK:urban", 50},          ImplicitLimit{"MK:rural", 90},
    ImplicitLimit{"MK:motorway", 130},      ImplicitLimit{"MT:urban", 50},
    ImplicitLimit{"MT:rural", 80},          ImplicitLimit{"NL:urban", 50},
    ImplicitLimit{"NL:rural", 80},          ImplicitLimit{"NL:trunk", 100},
    ImplicitLimit{"NL:motorway", 130},      ImplicitLimit{"NO:urban", 50},
    ImplicitLimit{"NO:rural", 80},          ImplicitLimit{"NO:motorway", 110},
    ImplicitLimit{"PL:urban", 50},          ImplicitLimit{"PL:rural", 90},
    ImplicitLimit{"PL:expressway", 120},    ImplicitLimit{"PL:motorway", 140},
    ImplicitLimit{"PT:urban", 50},          ImplicitLimit{"PT:rural", 90},
    ImplicitLimit{"PT:trunk", 100},         ImplicitLimit{"PT:motorway", 120},
    ImplicitLimit{"RO:urban", 50},          ImplicitLimit{"RO:rural", 90},
    ImplicitLimit{"RO:trunk", 100},         ImplicitLimit{"RO:motorway", 130},
    ImplicitLimit{"RS:urban", 50},          ImplicitLimit{"RS:rural", 80},
    ImplicitLimit{"RS:trunk", 100},         ImplicitLimit{"RS:motorway", 120},
    ImplicitLimit{"RU:urban", 60},          ImplicitLimit{"RU:rural", 90},
    ImplicitLimit{"RU:motorway", 110},      ImplicitLimit{"RU:living_street", 20},
    ImplicitLimit{"SE:urban", 50},          ImplicitLimit{"SE:rural", 70},
    ImplicitLimit{"SE:motorway", 110},      ImplicitLimit{"SI:urban", 50},
    ImplicitLimit{"SI:rural", 90},          ImplicitLimit{"SI:trunk", 110},
    ImplicitLimit{"SI:motorway", 130},      ImplicitLimit{"SK:urban", 50},
    ImplicitLimit{"SK:rural", 90},          ImplicitLimit{"SK:motorway", 130},
    ImplicitLimit{"UA:urban", 50},          ImplicitLimit{"UA:rural", 90},
    ImplicitLimit{"UA:motorway", 130},      ImplicitLimit{"XK:urban", 50},
    ImplicitLimit{"XK:rural", 80},          ImplicitLimit{"XK:motorway", 130},
};

std::string_view trim(std::string_view s) {
    while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
    while (!s.empty() && (s.back() == ' ' || s.back() == '\t')) s.remove_suffix(1);
    return s;
}

bool isDigit(char c) { return c >= '0' && c <= '9'; }

/// "50", "30 mph", "10 knots", "90 km/h", "50kmh" -> km/h; 0 for anything else.
std::uint16_t numericLimitKmh(std::string_view text) {
    std::size_t i = 0;
    while (i < text.size() && (isDigit(text[i]) || text[i] == '.')) ++i;
    double v = 0;
    const auto res = std::from_chars(text.data(), text.data() + i, v);
    if (res.ec != std::errc{} || res.ptr != text.data() + i || !(v > 0.0)) return 0;
    const std::string_view unit = trim(text.substr(i));
    double factor = 0.0;
    if (unit.empty() || unit == "km/h" || unit == "kmh" || unit == "kph")
        factor = 1.0;
    else if (unit == "mph")
        factor = 1.609344;
    else if (unit == "knots")
        factor = 1.852;
    const double kmh = v * factor;
    // Above 300 km/h no road has a limit: a typo or a unit that is not one.
    if (!(kmh >= 1.0 && kmh <= 300.0)) return 0;
    return static_cast<std::uint16_t>(std::lround(kmh));
}

/// "22:00-06:00", "07:00-09:00,16:00-18:00": time-of-day ranges and nothing else.
bool isTimeOfDayOnly(std::string_view condition) {
    if (condition.empty()) return false;
    while (!condition.empty()) {
        const std::size_t comma = condition.find(',');
        const std::string_view range = trim(condition.substr(0, comma));
        if (range.size() != 11 || range[2] != ':' || range[5] != '-' || range[8] != ':') return false;
        for (const std::size_t k : {0, 1, 3, 4, 6, 7, 9, 10}) {
            if (!isDigit(range[k])) return false;
        }
        if (comma == std::string_view::npos) break;
        condition.remove_prefix(comma + 1);
    }
    return true;
}

}  // namespace

std::optional<std::uint16_t> implicitSpeedLimitKmh(std::string_view code) {
    for (const ImplicitLimit& l : kImplicitLimits) {
        if (l.code == code) return l.kmh;
    }
    return std::nullopt;
}

std::uint16_t parseSpeedLimitKmh(std::string_view text) {
    text = trim(text);
    if (text.empty()) return 0;
    // "50;30" (lanes or times that differ): no single limit to show.
    if (text.find(';') != std::string_view::npos) return 0;
    if (isDigit(text.front())) return numericLimitKmh(text);
    // "none", "walk", "signals", "variable" and unknown codes: no number.
    return implicitSpeedLimitKmh(text).value_or(0);
}

std::vector<ConditionalSpeedLimit> parseConditionalSpeedLimits(std::string_view text) {
    std::vector<ConditionalSpeedLimit> out;
    // Entries are separated by ';' outside parentheses.
    int depth = 0;
    std::size_t start = 0;
    for (std::size_t i = 0; i <= text.size(); ++i) {
        const char c = i < text.size() ? text[i] : ';';
        if (c == '(') ++depth;
        if (c == ')' && depth > 0) --depth;
        if (c != ';' || depth > 0) continue;
        const std::string_view entry = trim(text.substr(start, i - start));
        start = i + 1;
        const std::size_t at = entry.find('@');
        if (at == std::string_view::npos) continue;
        ConditionalSpeedLimit l;
        l.kmh = parseSpeedLimitKmh(entry.substr(0, at));
        std::string_view condition = trim(entry.substr(at + 1));
        if (condition.size() >= 2 && condition.front() == '(' && condition.back() == ')')
            condition = trim(condition.substr(1, condition.size() - 2));
        l.condition = condition;
        l.time_of_day_only = isTimeOfDayOnly(condition);
        out.push_back(l);
    }
    return out;
}

DirectionalSpeedLimits speedLimitsFromTags(const TagLookup& tags) {
    const auto limit = [&](const char* key) -> std::optional<std::uint16_t> {
        const char* v = tags(key);
        if (v == nullptr) return std::nullopt;
        return parseSpeedLimitKmh(v);
    };
    const std::uint16_t both = limit("maxspeed").value_or(0);
    DirectionalSpeedLimits d;
    d.forward_kmh = limit("maxspeed:forward").value_or(both);
    d.backward_kmh = limit("maxspeed:backward").value_or(both);
    return d;
}

}  // namespace navmap::map
