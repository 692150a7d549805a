// SPDX-License-Identifier: Apache-2.0
#pragma once
// Guidance beside the pixels (docs/frame-protocol.md "Frame validity" and "Metadata block"):
// FrameValidity, which every frame header carries in its formerly reserved bytes (fresh,
// stale_pose with the pose's age, degraded with the reasons, off_route), and FrameMeta, the
// metadata block a client that asked for it ("meta":true) gets after each frame header: the pose
// used, the next manoeuvre, what is left of the route, the current street, the speed limit.
// Encoding and strict decoding; no I/O.

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "navmap/ipc/net/client_api.h"
#include "navmap/ipc/net/result.h"

namespace navmap::ipc {

/// Byte 68 of the frame header: 0 = the server says nothing about validity (a server from before
/// it was defined), 1 = bytes 69..76 hold the validity below.
inline constexpr std::uint8_t kFrameValidityVersion = 1;

/// Validity flags (header byte 69). None set = fresh.
enum FrameValidityFlag : std::uint8_t {
    kValidityStalePose = 1U << 0,  ///< no pose for more than the daemon's stale_pose_ms (or none yet)
    kValidityDegraded = 1U << 1,   ///< something under the camera is missing: see the reasons
    kValidityOffRoute = 1U << 2,   ///< guidance says the vehicle left its route
};
inline constexpr std::uint8_t kValidityFlagsKnown = 0x07;

/// Why a frame is degraded (header bytes 70..71).
enum FrameDegradedReason : std::uint16_t {
    kDegradedTilesMissing = 1U << 0,   ///< tiles wanted under the camera are not resident yet
    kDegradedTilesFailed = 1U << 1,    ///< tiles under the camera failed to load (damaged, unreadable)
    kDegradedRoadGraphOff = 1U << 2,   ///< no road graph: no map matching, no current street
    kDegradedOrthoimageOff = 1U << 3,  ///< the orthoimage ground was asked for and is not drawn
};
inline constexpr std::uint16_t kDegradedReasonsKnown = 0x0F;

/// Pose age when there has been no pose at all.
inline constexpr std::uint32_t kPoseAgeNone = 0xFFFFFFFFU;

struct FrameValidity {
    std::uint8_t version = 0;       ///< 0: not reported; kFrameValidityVersion: the fields below hold
    std::uint8_t flags = 0;         ///< FrameValidityFlag bits; 0 = fresh
    std::uint16_t degraded = 0;     ///< FrameDegradedReason bits; non-zero exactly when kValidityDegraded
    std::uint32_t pose_age_ms = 0;  ///< ms since the newest pose fix at render time; kPoseAgeNone: none yet

    bool known() const noexcept { return version != 0; }
    bool fresh() const noexcept { return version != 0 && flags == 0; }
};

/// "fresh", "stale_pose", "degraded", "off_route" joined with '+' ("stale_pose+off_route"), or
/// "unknown" for a header without validity.
NAVMAP_CLIENT_API std::string validityText(const FrameValidity& validity);
/// The degraded reasons joined with '+': "tiles_missing+orthoimage_off"; "" for none.
NAVMAP_CLIENT_API std::string degradedText(std::uint16_t reasons);
/// Checks the rules of docs/frame-protocol.md: known version, flags and reasons, reasons exactly
/// with the degraded flag, all zero with version 0.
Status validateFrameValidity(const FrameValidity& validity);

inline constexpr std::uint32_t kFrameMetaMagic = 0x444D4D4EU;  ///< "NMMD" as little-endian bytes
inline constexpr std::uint16_t kFrameMetaVersion = 1;
inline constexpr std::size_t kFrameMetaFixedBytes = 80;
inline constexpr std::size_t kMaxStreetBytes = 255;
inline constexpr std::size_t kMaxLanes = 16;
/// The largest block: fixed part, 16 lanes, two streets of 255 bytes.
inline constexpr std::size_t kMaxFrameMetaBytes = kFrameMetaFixedBytes + kMaxLanes + 2 * kMaxStreetBytes;

/// Manoeuvre types on the wire: the control protocol's (docs/ipc.md), in its order.
inline constexpr std::size_t kMetaManeuverTypes = 15;
/// "turn_left" etc. for a wire code; nullptr for an unknown code.
NAVMAP_CLIENT_API const char* metaManeuverName(std::uint8_t code) noexcept;

/// Lane bits (one byte per lane, left to right): the directions its arrows show, and whether the
/// route takes it.
enum MetaLaneBit : std::uint8_t {
    kLaneLeft = 1U << 0,
    kLaneSlightLeft = 1U << 1,
    kLaneStraight = 1U << 2,
    kLaneSlightRight = 1U << 3,
    kLaneRight = 1U << 4,
    kLaneUTurn = 1U << 5,
    kLaneRecommended = 1U << 7,
};
inline constexpr std::uint8_t kLaneBitsKnown = 0xBF;

struct FrameMeta {
    bool has_pose = false;  ///< the pose below is a fix (false: no fix yet; the fields are 0)
    double lat_deg = 0.0;
    double lon_deg = 0.0;
    double heading_deg = 0.0;       ///< clockwise from north, [0, 360)
    std::int64_t pose_time_ns = 0;  ///< CLOCK_REALTIME ns of the CAN data behind the pose

    bool has_next = false;            ///< a next manoeuvre is known
    std::uint8_t next_type = 0;       ///< wire code (metaManeuverName)
    std::uint8_t next_exit = 0;       ///< roundabout exit, 1..; 0 = none
    double next_distance_m = 0.0;     ///< to its junction along the route
    std::string next_street;          ///< the street it turns into; "" = unknown
    bool lanes_known = false;         ///< false: "unknown" (no lane data), lanes empty
    std::vector<std::uint8_t> lanes;  ///< MetaLaneBit per lane, left to right (1..16)

    bool has_remaining = false;  ///< a route is followed
    double remaining_m = 0.0;
    double remaining_s = 0.0;

    std::string current_street;         ///< the map-matched road's name; "" = unknown
    std::uint16_t speed_limit_kmh = 0;  ///< 0 = unknown
};

/// The wire form (little-endian, docs/frame-protocol.md "Metadata block"). Street names longer
/// than kMaxStreetBytes are cut at a UTF-8 character boundary, lanes beyond kMaxLanes dropped,
/// non-finite numbers sent as absent.
NAVMAP_CLIENT_API std::vector<std::uint8_t> encodeFrameMeta(const FrameMeta& meta);

/// Parses and validates a block of exactly `size` bytes: magic, version, the size it states,
/// known flags, finite numbers in range, well-formed UTF-8 street names, known lane bits, absent
/// fields zero. The error names the field ("metadata: \"lat\" 91 outside [-90, 90]").
NAVMAP_CLIENT_API Result<FrameMeta> decodeFrameMeta(const std::uint8_t* data, std::size_t size);

/// Cuts UTF-8 `text` to at most `max_bytes` at a character boundary (invalid bytes replaced by '?').
NAVMAP_CLIENT_API std::string boundedUtf8(std::string_view text, std::size_t max_bytes);

}  // namespace navmap::ipc
