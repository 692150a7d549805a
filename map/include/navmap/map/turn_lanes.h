// SPDX-License-Identifier: Apache-2.0
#pragma once
// The arrows painted on a road's lanes (OSM `turn:lanes`, docs/tile-store.md "Turn lanes"), as
// the road graph keeps them per direction of travel: one bit set per lane, left to right, 0 for a
// lane without arrows (`none`). Plain values, thread-safe.

#include <cstddef>
#include <cstdint>

namespace navmap::map {

namespace lane_arrow {
inline constexpr std::uint16_t kLeft = 1U << 0;
inline constexpr std::uint16_t kSlightLeft = 1U << 1;
inline constexpr std::uint16_t kSharpLeft = 1U << 2;
inline constexpr std::uint16_t kThrough = 1U << 3;
inline constexpr std::uint16_t kSlightRight = 1U << 4;
inline constexpr std::uint16_t kRight = 1U << 5;
inline constexpr std::uint16_t kSharpRight = 1U << 6;
inline constexpr std::uint16_t kReverse = 1U << 7;
inline constexpr std::uint16_t kMergeToLeft = 1U << 8;
inline constexpr std::uint16_t kMergeToRight = 1U << 9;
/// Every bit above; a stored lane with another bit is damage.
inline constexpr std::uint16_t kKnown = (1U << 10) - 1;
}  // namespace lane_arrow

/// The most lanes one direction of a road keeps (the frame metadata's limit too); a way tagged
/// with more keeps none.
inline constexpr std::size_t kMaxTurnLanes = 16;

}  // namespace navmap::map
