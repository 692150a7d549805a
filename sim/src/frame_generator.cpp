// SPDX-License-Identifier: Apache-2.0
#include "navmap/sim/frame_generator.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <numbers>
#include <string>

namespace navmap::sim {

namespace {

using Values = std::map<std::string, double, std::less<>>;

// FixType codes (VSS order, docs/can-input.md).
constexpr double kFixNone = 0.0;
constexpr double kFixThreeD = 5.0;

// Broken invariant (values are clamped before encoding, so encode() cannot fail): abort loudly.
ipc::CanFrame encodeChecked(const ipc::DbcMessage& msg, const Values& values) {
    auto r = msg.encode(values);
    if (!r.ok()) {
        std::fprintf(stderr, "navmap_sim: BUG: encoding %s failed: %s\n", msg.name.c_str(), r.error().message.c_str());
        std::abort();
    }
    return std::move(r).value();
}

ipc::Result<std::int64_t> periodUs(double hz, const char* what) {
    if (!(hz > 0.0) || hz > 1000.0) {
        return ipc::Error{std::string(what) + " rate " + std::to_string(hz) + " Hz is outside (0, 1000]"};
    }
    return static_cast<std::int64_t>(std::llround(1e6 / hz));
}

ipc::Status needSignals(const ipc::DbcMessage* msg, const char* name, std::initializer_list<const char*> signals) {
    if (msg == nullptr) return ipc::Error{std::string("navmap DBC has no message ") + name};
    for (const char* s : signals) {
        if (msg->findSignal(s) == nullptr) {
            return ipc::Error{std::string("navmap DBC message ") + name + " has no signal " + s};
        }
    }
    return {};
}

}  // namespace

const char* frameKindName(FrameKind kind) noexcept {
    switch (kind) {
        case FrameKind::Position: return "NAV_Position";
        case FrameKind::Motion: return "NAV_Motion";
        case FrameKind::Info: return "NAV_Info";
        case FrameKind::BadDlc: return "bad: wrong DLC";
        case FrameKind::BadGarbage: return "bad: garbage bytes";
        case FrameKind::BadOutOfRange: return "bad: out of range";
    }
    return "?";
}

ipc::Result<FrameGenerator> FrameGenerator::create(std::shared_ptr<const ipc::DbcDatabase> dbc,
                                                   std::shared_ptr<const SpeedProfile> profile,
                                                   map::Projection projection, FrameOptions options,
                                                   HeightFunction height) {
    if (!dbc || !profile) return ipc::Error{"frame generator needs a DBC and a speed profile"};
    FrameGenerator g;
    g.m_position = dbc->findMessage("NAV_Position");
    g.m_motion = dbc->findMessage("NAV_Motion");
    g.m_info = dbc->findMessage("NAV_Info");
    if (auto st = needSignals(g.m_position, "NAV_Position", {"NAV_Latitude", "NAV_Longitude"}); !st) {
        return ipc::Error{st.message()};
    }
    if (auto st =
            needSignals(g.m_motion, "NAV_Motion",
                        {"NAV_Heading", "NAV_Speed", "NAV_YawRate", "NAV_FixType", "NAV_Counter", "NAV_NumSatellites"});
        !st) {
        return ipc::Error{st.message()};
    }
    if (auto st = needSignals(g.m_info, "NAV_Info", {"NAV_InfoPage", "NAV_Altitude", "NAV_Hdop", "NAV_UtcTime"}); !st) {
        return ipc::Error{st.message()};
    }
    auto pos = periodUs(options.position_hz, "position");
    if (!pos) return pos.error();
    auto mot = periodUs(options.motion_hz, "motion");
    if (!mot) return mot.error();
    if (options.info_hz < 0.0) return ipc::Error{"info rate must be >= 0 Hz"};
    if (options.info_hz > 0.0) {
        auto inf = periodUs(options.info_hz, "info");
        if (!inf) return inf.error();
        g.m_info_period_us = inf.value();
    }
    if (!(options.noise_m >= 0.0) || options.noise_m > 1000.0) return ipc::Error{"noise must be within 0..1000 m"};
    if (options.dropouts < 0 || options.bad_bursts < 0 || options.burst_frames < 1 || !(options.dropout_s > 0.0)) {
        return ipc::Error{"dropouts and bursts must be >= 0, burst size >= 1, dropout length > 0 s"};
    }
    if (!(options.standstill_s >= 0.0) || !(options.max_duration_s >= 0.0)) {
        return ipc::Error{"standstill and duration must be >= 0 s"};
    }
    g.m_position_period_us = pos.value();
    g.m_motion_period_us = mot.value();
    g.m_dbc = std::move(dbc);
    g.m_profile = std::move(profile);
    g.m_projection.emplace(projection);
    g.m_options = options;
    g.m_height = std::move(height);
    g.m_rng.seed(options.seed);

    double total = g.m_profile->duration() + 2.0 * options.standstill_s;
    if (options.max_duration_s > 0.0) total = std::min(total, options.max_duration_s);
    g.m_total_us = static_cast<std::int64_t>(std::llround(total * 1e6));
    g.m_total_s = static_cast<double>(g.m_total_us) * 1e-6;

    // Faults are planned up front from the seed: one dropout / burst per equal share of the
    // drive, at a random place inside its share, so they are spread and never overlap.
    if (options.dropouts > 0) {
        const double share = g.m_total_s / options.dropouts;
        const double len = std::min(options.dropout_s, 0.8 * share);
        for (int i = 0; i < options.dropouts; ++i) {
            const double begin = i * share + g.uniform() * (share - len);
            g.m_dropouts.push_back({begin, begin + len});
        }
    }
    if (options.bad_bursts > 0) {
        const double share = g.m_total_s / options.bad_bursts;
        const double burst_len = options.burst_frames * 1e-3;
        for (int i = 0; i < options.bad_bursts; ++i) {
            g.m_bursts.push_back(i * share + g.uniform() * std::max(0.0, share - burst_len));
        }
    }
    if (!g.m_bursts.empty()) g.m_next_bad_us = static_cast<std::int64_t>(std::llround(g.m_bursts[0] * 1e6));
    return g;
}

double FrameGenerator::uniform() {
    return static_cast<double>(m_rng() >> 11) * 0x1.0p-53;  // [0, 1), same on every platform
}

double FrameGenerator::gaussian() {
    // Box-Muller written out: std::normal_distribution differs between standard libraries.
    if (m_has_spare) {
        m_has_spare = false;
        return m_spare;
    }
    const double u1 = 1.0 - uniform();  // (0, 1]
    const double u2 = uniform();
    const double r = std::sqrt(-2.0 * std::log(u1));
    m_spare = r * std::sin(2.0 * std::numbers::pi * u2);
    m_has_spare = true;
    return r * std::cos(2.0 * std::numbers::pi * u2);
}

VehicleState FrameGenerator::truthAt(double t_s) const {
    const double drive_t = std::clamp(t_s - m_options.standstill_s, 0.0, m_profile->duration());
    VehicleState st = m_profile->stateAt(drive_t);
    if (t_s < m_options.standstill_s || t_s > m_options.standstill_s + m_profile->duration()) {
        st.speed_mps = 0.0;
        st.accel_mps2 = 0.0;
        st.yaw_rate_dps = 0.0;
    }
    st.t_s = t_s;
    return st;
}

bool FrameGenerator::inDropout(double t_s) const {
    return std::any_of(m_dropouts.begin(), m_dropouts.end(),
                       [t_s](const Interval& d) { return t_s >= d.begin_s && t_s < d.end_s; });
}

ipc::CanTime FrameGenerator::stamp(std::int64_t us) const {
    return m_options.start_time + std::chrono::microseconds(us);
}

ipc::CanFrame FrameGenerator::positionFrame(double t_s) {
    const VehicleState st = truthAt(t_s);
    map::PlanarPoint p = st.position;
    if (m_options.noise_m > 0.0) {
        p.x += gaussian() * m_options.noise_m;
        p.y += gaussian() * m_options.noise_m;
    }
    double lat = 0.0;
    double lon = 0.0;
    m_projection->reverse(p, lat, lon);
    return encodeChecked(*m_position, {{"NAV_Latitude", lat}, {"NAV_Longitude", lon}});
}

ipc::CanFrame FrameGenerator::motionFrame(double t_s) {
    const VehicleState st = truthAt(t_s);
    const bool fix = !inDropout(t_s);
    double heading = std::round(st.heading_deg * 100.0) / 100.0;
    if (heading >= 360.0) heading -= 360.0;
    const ipc::CanFrame f = encodeChecked(
        *m_motion, {{"NAV_Heading", heading},
                    {"NAV_Speed", std::clamp(st.speed_mps * 3.6, 0.0, 655.0)},
                    {"NAV_YawRate", std::clamp(st.yaw_rate_dps, -327.0, 327.0)},
                    {"NAV_FixType", fix ? kFixThreeD : kFixNone},
                    {"NAV_Counter", static_cast<double>(m_counter)},
                    {"NAV_NumSatellites", fix ? static_cast<double>(std::clamp(m_options.satellites, 0, 255)) : 0.0}});
    m_counter = static_cast<std::uint8_t>((m_counter + 1) & 0x0F);  // 4-bit rolling counter, +1 per epoch
    return f;
}

ipc::CanFrame FrameGenerator::infoFrame(double t_s) {
    const std::uint64_t page = m_info_count++ % 2;
    if (page == 0) {
        const VehicleState st = truthAt(t_s);
        const double alt = m_height ? m_height(st.position) : 0.0;
        return encodeChecked(*m_info, {{"NAV_InfoPage", 0.0},
                                       {"NAV_Altitude", std::clamp(alt, -1000.0, 10000.0)},
                                       {"NAV_Hdop", std::clamp(m_options.hdop, 0.0, 655.0)}});
    }
    const double utc = std::chrono::duration<double>(m_options.start_time.time_since_epoch()).count() + t_s;
    return encodeChecked(*m_info,
                         {{"NAV_InfoPage", 1.0}, {"NAV_UtcTime", std::max(0.0, std::round(utc * 1000.0) / 1000.0)}});
}

ipc::CanFrame FrameGenerator::badFrame(double t_s, FrameKind& kind) {
    const auto pick = m_rng() % 3;
    const bool on_position = (m_rng() & 1U) == 0;
    ipc::CanFrame f;
    if (pick == 0) {
        // A truncated frame: a node with the wrong DLC configured, or a gateway cutting bytes.
        kind = FrameKind::BadDlc;
        f = on_position ? positionFrame(t_s)
                        : encodeChecked(*m_motion, {{"NAV_Counter", static_cast<double>(m_counter)}});
        // Always short enough to cut a decoded signal (motion: NAV_FixType/NAV_Counter end in byte 7).
        f.len = static_cast<std::uint8_t>(1 + m_rng() % (on_position ? 7 : 6));
        std::fill(f.data.begin() + f.len, f.data.end(), 0);
    } else if (pick == 1) {
        kind = FrameKind::BadGarbage;
        f.id = on_position ? m_position->id : m_motion->id;
        f.len = 8;
        const std::uint64_t bytes = m_rng();
        for (int i = 0; i < 8; ++i) f.data[static_cast<std::size_t>(i)] = static_cast<std::uint8_t>(bytes >> (8 * i));
    } else {
        // Fits the bits but not the DBC range: latitude beyond 90 deg or heading beyond 360 deg.
        kind = FrameKind::BadOutOfRange;
        if (on_position) {
            const double sign = (m_rng() & 1U) != 0 ? 1.0 : -1.0;
            f = encodeChecked(*m_position,
                              {{"NAV_Latitude", sign * (100.0 + 100.0 * uniform())}, {"NAV_Longitude", 1.5}});
        } else {
            f = encodeChecked(*m_motion, {{"NAV_Heading", 361.0 + 250.0 * uniform()},
                                          {"NAV_Speed", 0.0},
                                          {"NAV_FixType", kFixThreeD},
                                          {"NAV_Counter", static_cast<double>(m_counter)}});
        }
    }
    return f;
}

std::optional<double> FrameGenerator::nextTime() const {
    std::int64_t best = INT64_MAX;
    if (m_next_position_us <= m_total_us) best = std::min(best, m_next_position_us);
    if (m_next_motion_us <= m_total_us) best = std::min(best, m_next_motion_us);
    if (m_info_period_us > 0 && m_next_info_us <= m_total_us) best = std::min(best, m_next_info_us);
    if (m_next_burst < m_bursts.size() && m_next_bad_us <= m_total_us) best = std::min(best, m_next_bad_us);
    if (best == INT64_MAX) return std::nullopt;
    return static_cast<double>(best) * 1e-6;
}

bool FrameGenerator::next(ipc::CanFrame& frame, FrameKind* kind_out) {
    for (;;) {
        // Ties: position, then motion of the same epoch, then info, then a bad frame.
        enum { kNone, kPos, kMot, kInf, kBad } which = kNone;
        std::int64_t best = INT64_MAX;
        auto consider = [&](std::int64_t t, bool on, auto tag) {
            if (on && t <= m_total_us && t < best) {
                best = t;
                which = tag;
            }
        };
        consider(m_next_position_us, true, kPos);
        consider(m_next_motion_us, true, kMot);
        consider(m_next_info_us, m_info_period_us > 0, kInf);
        consider(m_next_bad_us, m_next_burst < m_bursts.size(), kBad);
        if (which == kNone) return false;
        const double t = static_cast<double>(best) * 1e-6;
        FrameKind kind = FrameKind::Position;
        switch (which) {
            case kPos:
                m_next_position_us += m_position_period_us;
                if (inDropout(t)) continue;  // GNSS outage: no fix, no position frame
                frame = positionFrame(t);
                kind = FrameKind::Position;
                break;
            case kMot:
                m_next_motion_us += m_motion_period_us;
                frame = motionFrame(t);
                kind = FrameKind::Motion;
                break;
            case kInf:
                m_next_info_us += m_info_period_us;
                frame = infoFrame(t);
                kind = FrameKind::Info;
                break;
            case kBad:
                frame = badFrame(t, kind);
                if (++m_burst_done >= m_options.burst_frames) {
                    m_burst_done = 0;
                    ++m_next_burst;
                    if (m_next_burst < m_bursts.size()) {
                        m_next_bad_us = static_cast<std::int64_t>(std::llround(m_bursts[m_next_burst] * 1e6));
                    }
                } else {
                    m_next_bad_us += 1000;  // 1 ms apart inside a burst
                }
                break;
            case kNone: return false;
        }
        frame.timestamp = stamp(best);
        ++m_stats.frames;
        ++m_stats.by_kind[static_cast<std::size_t>(kind)];
        m_stats.duration_s = t;
        m_stats.distance_m = truthAt(t).measure_m;
        if (kind_out != nullptr) *kind_out = kind;
        return true;
    }
}

}  // namespace navmap::sim
