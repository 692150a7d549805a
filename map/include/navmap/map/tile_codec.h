// SPDX-License-Identifier: Apache-2.0
#pragma once
// Binary encoding of one Tile (the payload of a tile blob in the store, before compression).
// Coordinates are quantized to centimetres relative to the tile origin and delta/zigzag
// varint coded; heights to decimetres. Little-endian. See docs/tile-store.md.

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "navmap/map/store_info.h"
#include "navmap/map/tile.h"

namespace navmap::map {

inline constexpr std::uint32_t kTilePayloadMagic = 0x324C544E;  // "NTL2" (with the ortho layers)
inline constexpr double kCoordQuantum = 0.01;                   // metres
inline constexpr double kHeightQuantum = 0.1;                   // metres

/// Encodes a tile's payload ("NTL2").
std::vector<std::uint8_t> encodeTile(const Tile& tile);

/// Decodes a payload; on malformed input returns false with a description in `error` (never
/// throws, never reads out of bounds: this runs on untrusted bytes and is fuzzed).
bool decodeTile(std::span<const std::uint8_t> bytes, Tile& out, std::string& error);

}  // namespace navmap::map
