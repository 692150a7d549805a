// SPDX-License-Identifier: Apache-2.0
#include "navmap/ipc/client/frame_meta.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <tuple>
#include <utility>

#include "navmap/ipc/client/frame_header.h"

namespace navmap::ipc {
namespace {

constexpr const char* kManeuverNames[kMetaManeuverTypes] = {
    "depart",      "arrive", "straight",  "turn_left",  "turn_right", "slight_left", "slight_right", "sharp_left",
    "sharp_right", "u_turn", "keep_left", "keep_right", "roundabout", "exit",        "merge",
};

// Block flags (offset 8).
enum : std::uint16_t {
    kMetaPose = 1U << 0,
    kMetaNext = 1U << 1,
    kMetaRemaining = 1U << 2,
    kMetaLanes = 1U << 3,
};
constexpr std::uint16_t kMetaFlagsKnown = 0x0F;

void putU(std::vector<std::uint8_t>& out, std::size_t off, std::uint64_t v, std::size_t bytes) {
    for (std::size_t i = 0; i < bytes; ++i) {
        out[off + i] = static_cast<std::uint8_t>(v >> (8 * i));
    }
}

std::uint64_t getU(const std::uint8_t* in, std::size_t off, std::size_t bytes) {
    std::uint64_t v = 0;
    for (std::size_t i = 0; i < bytes; ++i) {
        v |= static_cast<std::uint64_t>(in[off + i]) << (8 * i);
    }
    return v;
}

void putF(std::vector<std::uint8_t>& out, std::size_t off, double v) {
    std::uint64_t bits = 0;
    std::memcpy(&bits, &v, sizeof(bits));
    putU(out, off, bits, 8);
}

double getF(const std::uint8_t* in, std::size_t off) {
    const std::uint64_t bits = getU(in, off, 8);
    double v = 0.0;
    std::memcpy(&v, &bits, sizeof(v));
    return v;
}

bool finite(double v) { return std::isfinite(v); }

std::string number(double v) {
    char buf[40];
    std::snprintf(buf, sizeof(buf), "%.17g", v);
    return buf;
}

// A present number must be finite and in [lo, hi) (hi_open) or [lo, hi].
Status checkRange(const char* name, double v, double lo, double hi, bool hi_open = false) {
    if (!std::isfinite(v) || v < lo || (hi_open ? v >= hi : v > hi)) {
        return Error{std::string("metadata: \"") + name + "\" " + number(v) + " outside [" + number(lo) + ", " +
                     number(hi) + (hi_open ? ")" : "]")};
    }
    return {};
}

Status checkZero(const char* name, double v) {
    std::uint64_t bits = 0;
    std::memcpy(&bits, &v, sizeof(bits));
    if (bits != 0) {
        return Error{std::string("metadata: \"") + name + "\" must be 0 when absent"};
    }
    return {};
}

struct Layout {
    std::size_t lanes = 0, next_street = 0, current_street = 0;
};

Status decodePose(const std::uint8_t* d, std::uint16_t flags, FrameMeta* m) {
    m->has_pose = (flags & kMetaPose) != 0;
    m->lat_deg = getF(d, 16);
    m->lon_deg = getF(d, 24);
    m->heading_deg = getF(d, 32);
    m->pose_time_ns = static_cast<std::int64_t>(getU(d, 40, 8));
    if (!m->has_pose) {
        for (const auto& [name, v] : {std::pair{"lat", m->lat_deg}, {"lon", m->lon_deg}, {"heading", m->heading_deg}}) {
            if (auto s = checkZero(name, v); !s) {
                return s;
            }
        }
        if (m->pose_time_ns != 0) {
            return Error{"metadata: \"pose_time\" must be 0 without a pose"};
        }
        return {};
    }
    if (auto s = checkRange("lat", m->lat_deg, -90.0, 90.0); !s) {
        return s;
    }
    if (auto s = checkRange("lon", m->lon_deg, -180.0, 180.0); !s) {
        return s;
    }
    if (auto s = checkRange("heading", m->heading_deg, 0.0, 360.0, true); !s) {
        return s;
    }
    if (m->pose_time_ns < 0) {
        return Error{"metadata: \"pose_time\" is negative"};
    }
    return {};
}

Status decodeRoute(const std::uint8_t* d, std::uint16_t flags, FrameMeta* m) {
    m->has_next = (flags & kMetaNext) != 0;
    m->next_type = d[10];
    m->next_exit = d[11];
    m->next_distance_m = getF(d, 48);
    if (m->has_next) {
        if (metaManeuverName(m->next_type) == nullptr) {
            return Error{"metadata: unknown manoeuvre type " + std::to_string(m->next_type)};
        }
        if (auto s = checkRange("next_distance", m->next_distance_m, 0.0, 1e8); !s) {
            return s;
        }
    } else if (m->next_type != 0 || m->next_exit != 0) {
        return Error{"metadata: manoeuvre type and exit must be 0 without a next manoeuvre"};
    } else if (auto s = checkZero("next_distance", m->next_distance_m); !s) {
        return s;
    }
    m->has_remaining = (flags & kMetaRemaining) != 0;
    m->remaining_m = getF(d, 56);
    m->remaining_s = getF(d, 64);
    if (m->has_remaining) {
        if (auto s = checkRange("remaining_m", m->remaining_m, 0.0, 1e8); !s) {
            return s;
        }
        return checkRange("remaining_s", m->remaining_s, 0.0, 1e8);
    }
    if (auto s = checkZero("remaining_m", m->remaining_m); !s) {
        return s;
    }
    return checkZero("remaining_s", m->remaining_s);
}

Status decodeStrings(const std::uint8_t* d, std::size_t size, std::uint16_t flags, const Layout& l, FrameMeta* m) {
    std::size_t off = kFrameMetaFixedBytes;
    m->lanes_known = (flags & kMetaLanes) != 0;
    if (m->lanes_known != (l.lanes != 0)) {
        return Error{"metadata: lane count " + std::to_string(l.lanes) + (m->lanes_known ? " with" : " without") +
                     " known lanes"};
    }
    if (l.lanes > kMaxLanes) {
        return Error{"metadata: " + std::to_string(l.lanes) + " lanes (limit " + std::to_string(kMaxLanes) + ")"};
    }
    for (std::size_t i = 0; i < l.lanes; ++i) {
        if ((d[off + i] & ~kLaneBitsKnown) != 0) {
            return Error{"metadata: lane " + std::to_string(i) + " has unknown bits"};
        }
    }
    m->lanes.assign(d + off, d + off + l.lanes);
    off += l.lanes;
    for (auto [name, len, out] : {std::tuple{"next_street", l.next_street, &m->next_street},
                                  std::tuple{"current_street", l.current_street, &m->current_street}}) {
        if (auto s = validateTextPayload(FrameKind::Status, d + off, len); !s) {
            return Error{std::string("metadata: \"") + name + "\": " + s.message().substr(s.message().find(':') + 2)};
        }
        out->assign(reinterpret_cast<const char*>(d + off), len);
        off += len;
    }
    if (off != size) {
        return Error{"metadata: " + std::to_string(size) + " bytes, the fields take " + std::to_string(off)};
    }
    return {};
}

}  // namespace

const char* metaManeuverName(std::uint8_t code) noexcept {
    return code < kMetaManeuverTypes ? kManeuverNames[code] : nullptr;
}

std::string validityText(const FrameValidity& v) {
    if (v.version == 0) {
        return "unknown";
    }
    if (v.flags == 0) {
        return "fresh";
    }
    std::string out;
    for (const auto& [bit, name] : {std::pair{kValidityStalePose, "stale_pose"},
                                    {kValidityDegraded, "degraded"},
                                    {kValidityOffRoute, "off_route"}}) {
        if ((v.flags & bit) != 0) {
            out += (out.empty() ? "" : "+") + std::string(name);
        }
    }
    return out;
}

std::string degradedText(std::uint16_t reasons) {
    std::string out;
    for (const auto& [bit, name] : {std::pair{kDegradedTilesMissing, "tiles_missing"},
                                    {kDegradedTilesFailed, "tiles_failed"},
                                    {kDegradedRoadGraphOff, "road_graph_off"},
                                    {kDegradedOrthoimageOff, "orthoimage_off"}}) {
        if ((reasons & bit) != 0) {
            out += (out.empty() ? "" : "+") + std::string(name);
        }
    }
    return out;
}

Status validateFrameValidity(const FrameValidity& v) {
    if (v.version == 0) {
        if (v.flags != 0 || v.degraded != 0 || v.pose_age_ms != 0) {
            return Error{"frame header: validity fields set without a validity version"};
        }
        return {};
    }
    if (v.version != kFrameValidityVersion) {
        return Error{"frame header: unsupported validity version " + std::to_string(v.version)};
    }
    if ((v.flags & ~kValidityFlagsKnown) != 0) {
        return Error{"frame header: unknown validity flags " + std::to_string(v.flags)};
    }
    if ((v.degraded & ~kDegradedReasonsKnown) != 0) {
        return Error{"frame header: unknown degraded reasons " + std::to_string(v.degraded)};
    }
    if (((v.flags & kValidityDegraded) != 0) != (v.degraded != 0)) {
        return Error{"frame header: degraded flag and reasons disagree"};
    }
    return {};
}

std::string boundedUtf8(std::string_view text, std::size_t max_bytes) {
    std::string out;
    std::size_t i = 0;
    while (i < text.size()) {
        // The length of one well-formed character at i, or 0.
        std::size_t len = 1;
        const auto b = static_cast<std::uint8_t>(text[i]);
        if (b >= 0x80) {
            len = b >= 0xF0 ? 4 : b >= 0xE0 ? 3 : 2;
            if (i + len > text.size() ||
                !validateTextPayload(FrameKind::Status, reinterpret_cast<const std::uint8_t*>(text.data() + i), len)) {
                len = 0;
            }
        }
        const std::string_view piece = len == 0 ? std::string_view("?") : text.substr(i, len);
        if (out.size() + piece.size() > max_bytes) {
            break;
        }
        out += piece;
        i += len == 0 ? 1 : len;
    }
    return out;
}

// Layout (little-endian), docs/frame-protocol.md "Metadata block":
//  0 magic u32 | 4 version u16 | 6 block bytes u16 | 8 flags u16 | 10 next type u8 | 11 next exit u8
// 12 speed limit km/h u16 | 14 next street bytes u8 | 15 current street bytes u8 | 16 lat f64
// 24 lon f64 | 32 heading f64 | 40 pose time ns i64 | 48 next distance m f64 | 56 remaining m f64
// 64 remaining s f64 | 72 lane count u8 | 73..80 reserved (0) | 80 lanes, next street, current street
std::vector<std::uint8_t> encodeFrameMeta(const FrameMeta& m) {
    const bool pose = m.has_pose && finite(m.lat_deg) && finite(m.lon_deg) && finite(m.heading_deg);
    const bool next = m.has_next && m.next_type < kMetaManeuverTypes && finite(m.next_distance_m);
    const bool remaining = m.has_remaining && finite(m.remaining_m) && finite(m.remaining_s);
    const std::size_t lanes = m.lanes_known ? std::min(m.lanes.size(), kMaxLanes) : 0;
    const std::string next_street = next ? boundedUtf8(m.next_street, kMaxStreetBytes) : std::string();
    const std::string current_street = boundedUtf8(m.current_street, kMaxStreetBytes);
    std::vector<std::uint8_t> out(kFrameMetaFixedBytes + lanes + next_street.size() + current_street.size(), 0);
    putU(out, 0, kFrameMetaMagic, 4);
    putU(out, 4, kFrameMetaVersion, 2);
    putU(out, 6, out.size(), 2);
    const std::uint16_t flags = (pose ? kMetaPose : 0) | (next ? kMetaNext : 0) | (remaining ? kMetaRemaining : 0) |
                                (lanes > 0 ? kMetaLanes : 0);
    putU(out, 8, flags, 2);
    out[10] = next ? m.next_type : 0;
    out[11] = next ? m.next_exit : 0;
    putU(out, 12, m.speed_limit_kmh, 2);
    out[14] = static_cast<std::uint8_t>(next_street.size());
    out[15] = static_cast<std::uint8_t>(current_street.size());
    if (pose) {
        putF(out, 16, m.lat_deg);
        putF(out, 24, m.lon_deg);
        putF(out, 32, std::fmod(std::fmod(m.heading_deg, 360.0) + 360.0, 360.0));
        putU(out, 40, static_cast<std::uint64_t>(std::max<std::int64_t>(m.pose_time_ns, 0)), 8);
    }
    if (next) {
        putF(out, 48, std::max(0.0, m.next_distance_m));
    }
    if (remaining) {
        putF(out, 56, std::max(0.0, m.remaining_m));
        putF(out, 64, std::max(0.0, m.remaining_s));
    }
    out[72] = static_cast<std::uint8_t>(lanes);
    std::size_t off = kFrameMetaFixedBytes;
    for (std::size_t i = 0; i < lanes; ++i) {
        out[off++] = m.lanes[i] & kLaneBitsKnown;
    }
    std::memcpy(out.data() + off, next_street.data(), next_street.size());
    off += next_street.size();
    std::memcpy(out.data() + off, current_street.data(), current_street.size());
    return out;
}

Result<FrameMeta> decodeFrameMeta(const std::uint8_t* d, std::size_t size) {
    if (size < kFrameMetaFixedBytes || size > kMaxFrameMetaBytes) {
        return Error{"metadata: " + std::to_string(size) + " bytes (" + std::to_string(kFrameMetaFixedBytes) + ".." +
                     std::to_string(kMaxFrameMetaBytes) + ")"};
    }
    if (getU(d, 0, 4) != kFrameMetaMagic) {
        return Error{"metadata: bad magic (not a metadata block)"};
    }
    if (getU(d, 4, 2) != kFrameMetaVersion) {
        return Error{"metadata: unsupported version " + std::to_string(getU(d, 4, 2))};
    }
    if (getU(d, 6, 2) != size) {
        return Error{"metadata: block says " + std::to_string(getU(d, 6, 2)) + " bytes, header says " +
                     std::to_string(size)};
    }
    const auto flags = static_cast<std::uint16_t>(getU(d, 8, 2));
    if ((flags & ~kMetaFlagsKnown) != 0) {
        return Error{"metadata: unknown flags " + std::to_string(flags)};
    }
    for (std::size_t i = 73; i < kFrameMetaFixedBytes; ++i) {
        if (d[i] != 0) {
            return Error{"metadata: reserved byte " + std::to_string(i) + " is not 0"};
        }
    }
    FrameMeta m;
    m.speed_limit_kmh = static_cast<std::uint16_t>(getU(d, 12, 2));
    if (m.speed_limit_kmh > 400) {
        return Error{"metadata: speed limit " + std::to_string(m.speed_limit_kmh) + " km/h"};
    }
    if (auto s = decodePose(d, flags, &m); !s) {
        return Error{s.message()};
    }
    if (auto s = decodeRoute(d, flags, &m); !s) {
        return Error{s.message()};
    }
    const Layout l{d[72], d[14], d[15]};
    if (!m.has_next && l.next_street != 0) {
        return Error{"metadata: a next street without a next manoeuvre"};
    }
    if (kFrameMetaFixedBytes + l.lanes + l.next_street + l.current_street != size) {
        return Error{"metadata: " + std::to_string(size) + " bytes, the fields take " +
                     std::to_string(kFrameMetaFixedBytes + l.lanes + l.next_street + l.current_street)};
    }
    if (auto s = decodeStrings(d, size, flags, l, &m); !s) {
        return Error{s.message()};
    }
    return m;
}

}  // namespace navmap::ipc
