// SPDX-License-Identifier: Apache-2.0
#pragma once
// VehicleDecoder: CAN frames -> VehicleSample updates, through one or more DBC databases and a
// SignalMap. Out-of-range values (outside the DBC's [min|max], outside the quantity's plausible
// range, NaN/inf) are rejected and counted per mapping; a gap in the GNSS message counter is
// counted as lost frames. Single-threaded: run it on the input thread and publish the merged
// latest() as an immutable snapshot.

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <unordered_map>
#include <vector>

#include "navmap/ipc/can/can_frame.h"
#include "navmap/ipc/can/dbc_database.h"
#include "navmap/ipc/can/signal_map.h"
#include "navmap/ipc/can/vehicle_sample.h"
#include "navmap/ipc/net/result.h"

namespace navmap::ipc {

struct DecoderCounters {
    std::uint64_t frames = 0;          ///< frames offered to decode()
    std::uint64_t matched_frames = 0;  ///< frames of a mapped message
    std::uint64_t values = 0;          ///< quantities accepted
    std::uint64_t rejected = 0;        ///< quantities rejected (range, NaN, missing sign bit)
    std::uint64_t short_frames = 0;    ///< mapped frames too short for a mapped signal
    std::uint64_t ignored_frames = 0;  ///< error and remote frames
    std::uint64_t counter_gaps = 0;    ///< frames missing according to the GNSS counter
};

/// Per-mapping statistics, in SignalMap order.
struct MappingStats {
    std::uint64_t accepted = 0;
    std::uint64_t rejected = 0;
    std::string last_rejection;  ///< why the newest rejection happened
};

class VehicleDecoder {
public:
    /// Resolves every mapping against `databases` (searched in order). Fails naming the mapping
    /// whose message/signal does not exist or whose unit cannot be converted.
    static Result<VehicleDecoder> create(std::vector<std::shared_ptr<const DbcDatabase>> databases,
                                         const SignalMap& map);

    /// Decodes one frame. Returns true and fills `update` (cleared first) when the frame produced at
    /// least one accepted quantity; `update.source_time` is the frame's timestamp. Also merges it into
    /// latest().
    bool decode(const CanFrame& frame, VehicleSample& update);

    /// Everything decoded so far, newest value of each quantity.
    const VehicleSample& latest() const noexcept { return m_latest; }
    const DecoderCounters& counters() const noexcept { return m_counters; }
    const std::vector<MappingStats>& mappingStats() const noexcept { return m_stats; }
    /// Frame keys (CanFrame::key()) of all mapped messages, sorted: feed to CAN_RAW_FILTER.
    std::vector<std::uint32_t> frameKeys() const;

private:
    struct Plan {
        const DbcMessage* message = nullptr;
        const DbcSignal* signal = nullptr;
        const DbcSignal* sign_signal = nullptr;
        VssSignal target = VssSignal::Speed;
        double unit_factor = 1.0;
        double scale = 1.0;
        double bias = 0.0;
        std::size_t mapping_index = 0;
    };
    void reject(const Plan& plan, std::string why);

    std::vector<std::shared_ptr<const DbcDatabase>> m_databases;
    std::unordered_map<std::uint32_t, std::vector<Plan>> m_plans;
    std::vector<MappingStats> m_stats;
    DecoderCounters m_counters;
    VehicleSample m_latest;
    std::optional<std::uint64_t> m_last_counter;
};

}  // namespace navmap::ipc
