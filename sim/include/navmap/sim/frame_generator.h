// SPDX-License-Identifier: Apache-2.0
#pragma once
// GNSS node emulation: turns a SpeedProfile into navmap.dbc frames at realistic rates
// (NAV_Position 0x6A0 at 5/10 Hz, NAV_Motion 0x6A1 at 50 Hz, NAV_Info 0x6A2 at 1 Hz with
// alternating pages), with optional seeded faults: Gaussian position noise, dropouts (intervals
// without position fixes; motion continues with fix type NONE) and bursts of bad frames (wrong
// DLC, garbage bytes, out-of-range values). Deterministic: the same inputs and seed give the same
// frames bit for bit (own RNG transforms, no std:: distributions; integer microsecond schedule).
//
// Pull interface: next() yields frames in time order, so hours of driving need no memory.

#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <random>
#include <vector>

#include "navmap/ipc/can/can_frame.h"
#include "navmap/ipc/can/dbc_database.h"
#include "navmap/ipc/net/result.h"
#include "navmap/map/projection.h"
#include "navmap/sim/speed_profile.h"

namespace navmap::sim {

/// What a generated frame is, for statistics and tests (the CAN bus itself carries no such tag).
enum class FrameKind : std::uint8_t {
    Position = 0,
    Motion,
    Info,
    BadDlc,         ///< a navmap id with a too-short payload
    BadGarbage,     ///< a navmap id with random bytes
    BadOutOfRange,  ///< well-formed frame whose value is outside the DBC / plausible range
};
inline constexpr std::size_t kFrameKindCount = 6;
const char* frameKindName(FrameKind kind) noexcept;

struct Interval {
    double begin_s = 0.0;
    double end_s = 0.0;
};

struct FrameOptions {
    double position_hz = 10.0;  ///< NAV_Position rate (GNSS epoch), 1..50, must divide 1e6 us
    double motion_hz = 50.0;    ///< NAV_Motion rate
    double info_hz = 1.0;       ///< NAV_Info rate (pages 0/1 alternate); 0 = none
    double noise_m = 0.0;       ///< sigma of the Gaussian position error per axis, metres
    int dropouts = 0;           ///< number of GNSS dropouts spread over the drive
    double dropout_s = 5.0;     ///< length of each dropout
    int bad_bursts = 0;         ///< number of bad-frame bursts
    int burst_frames = 5;       ///< bad frames per burst (1 ms apart)
    std::uint64_t seed = 1;
    /// Time of the first frame (realtime clock); also the UTC time in NAV_Info page 1.
    ipc::CanTime start_time = ipc::CanTime(std::chrono::seconds(1618394400));  // 2021-04-14T10:00:00Z
    /// Stop after this many seconds of drive time (0 = the whole drive, to the full stop).
    double max_duration_s = 0.0;
    /// Seconds standing still at the start and the end (frames keep coming, speed 0).
    double standstill_s = 2.0;
    int satellites = 11;
    double hdop = 0.9;
};

/// Counters of one generation run.
struct FrameStats {
    std::uint64_t frames = 0;
    std::uint64_t by_kind[kFrameKindCount] = {};
    double duration_s = 0.0;  ///< time of the last frame after the start
    double distance_m = 0.0;
};

/// Terrain height (metres above sea level) at a store-frame position, for NAV_Altitude.
using HeightFunction = std::function<double(map::PlanarPoint)>;

class FrameGenerator {
public:
    /// Resolves the three navmap.dbc messages in `dbc`; fails naming a missing message/signal or
    /// an invalid option (rates, negative noise).
    static ipc::Result<FrameGenerator> create(std::shared_ptr<const ipc::DbcDatabase> dbc,
                                              std::shared_ptr<const SpeedProfile> profile, map::Projection projection,
                                              FrameOptions options, HeightFunction height = {});

    /// Next frame in time order (timestamp set); false when the drive is over.
    bool next(ipc::CanFrame& frame, FrameKind* kind = nullptr);
    /// Time of the next frame after the start, seconds (nullopt when over).
    [[nodiscard]] std::optional<double> nextTime() const;

    [[nodiscard]] const FrameStats& stats() const { return m_stats; }
    [[nodiscard]] const std::vector<Interval>& dropouts() const { return m_dropouts; }
    /// Start times of the bad-frame bursts, seconds after the start.
    [[nodiscard]] const std::vector<double>& burstTimes() const { return m_bursts; }
    /// Total simulated time: standstill + drive (+ standstill), or max_duration_s.
    [[nodiscard]] double totalDuration() const { return m_total_s; }
    /// Ground truth at time t after the start (standstill handled).
    [[nodiscard]] VehicleState truthAt(double t_s) const;

private:
    FrameGenerator() = default;
    double uniform();
    double gaussian();
    ipc::CanFrame positionFrame(double t_s);
    ipc::CanFrame motionFrame(double t_s);
    ipc::CanFrame infoFrame(double t_s);
    ipc::CanFrame badFrame(double t_s, FrameKind& kind);
    [[nodiscard]] bool inDropout(double t_s) const;
    [[nodiscard]] ipc::CanTime stamp(std::int64_t us) const;

    std::shared_ptr<const ipc::DbcDatabase> m_dbc;
    std::shared_ptr<const SpeedProfile> m_profile;
    const ipc::DbcMessage* m_position = nullptr;
    const ipc::DbcMessage* m_motion = nullptr;
    const ipc::DbcMessage* m_info = nullptr;
    std::optional<map::Projection> m_projection;
    FrameOptions m_options;
    HeightFunction m_height;
    std::mt19937_64 m_rng;
    bool m_has_spare = false;
    double m_spare = 0.0;

    std::int64_t m_total_us = 0;
    double m_total_s = 0.0;
    std::int64_t m_position_period_us = 0, m_motion_period_us = 0, m_info_period_us = 0;
    std::int64_t m_next_position_us = 0, m_next_motion_us = 0, m_next_info_us = 0;
    std::size_t m_next_burst = 0;
    int m_burst_done = 0;
    std::int64_t m_next_bad_us = 0;
    std::uint8_t m_counter = 0;
    std::uint64_t m_info_count = 0;
    std::vector<Interval> m_dropouts;
    std::vector<double> m_bursts;
    FrameStats m_stats;
};

}  // namespace navmap::sim
