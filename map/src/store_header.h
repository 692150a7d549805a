// SPDX-License-Identifier: Apache-2.0
#pragma once
// Serialization of the store header and index (private to navmap_map).

#include <zlib.h>

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <span>
#include <string>
#include <vector>

#include "byte_io.h"
#include "navmap/map/store_info.h"

namespace navmap::map::detail {

inline constexpr std::size_t kHeaderSize = 144;
inline constexpr std::size_t kIndexEntrySize = 29;

/// Format limits, checked before anything is allocated (docs/tile-store.md "Sizes"): the tiles a
/// store may hold (its index is read whole at open: 29 bytes a tile, so at most 116 MiB; 32 times
/// the 129,332 tiles of the largest store measured), the raw (inflated) size of one tile, and of
/// the road graph.
inline constexpr std::uint32_t kMaxStoreTiles = std::uint32_t{1} << 22;
inline constexpr std::uint32_t kMaxTileRawBytes = std::uint32_t{256} << 20;
inline constexpr std::uint64_t kMaxGraphRawBytes = std::uint64_t{4} << 30;

inline std::uint32_t crc32Of(std::span<const std::uint8_t> bytes) {
    uLong crc = ::crc32(0L, Z_NULL, 0);
    // zlib takes uInt lengths; feed in chunks.
    std::size_t pos = 0;
    while (pos < bytes.size()) {
        const std::size_t n = std::min<std::size_t>(bytes.size() - pos, 1u << 30);
        crc = ::crc32(crc, bytes.data() + pos, static_cast<uInt>(n));
        pos += n;
    }
    return static_cast<std::uint32_t>(crc);
}

inline std::vector<std::uint8_t> encodeHeader(const StoreInfo& info) {
    ByteWriter w;
    w.raw(kStoreMagic, 8);
    w.u32(info.format_version);
    w.u32(static_cast<std::uint32_t>(kHeaderSize));
    w.f64(info.origin_lat);
    w.f64(info.origin_lon);
    const WorldTileId root = info.scheme.worldRoot();
    w.u32(static_cast<std::uint32_t>(root.z));
    w.u32(root.x);
    w.u32(root.y);
    for (int i = 0; i < 3; ++i) w.u32(0);  // reserved
    w.u32(static_cast<std::uint32_t>(info.scheme.levelCount()));
    w.u32(info.dem_samples);
    w.f64(info.south);
    w.f64(info.west);
    w.f64(info.north);
    w.f64(info.east);
    w.u32(info.tile_count);
    w.u64(info.index_offset);
    w.u32(info.index_crc);
    w.u64(info.graph_offset);
    w.u64(info.graph_stored_size);
    w.u64(info.graph_raw_size);
    w.u32(info.graph_crc);
    if (w.size() + 4 != kHeaderSize) std::abort();  // broken invariant: layout and size disagree
    w.u32(crc32Of(w.bytes()));
    return std::move(w.bytes());
}

/// Decodes a header; on failure returns false with a problem description (without file name).
inline bool decodeHeader(std::span<const std::uint8_t> bytes, StoreInfo& info, std::string& error) {
    if (bytes.size() < 16 || std::memcmp(bytes.data(), kStoreMagic, 8) != 0) {
        error = "not a navmap tile store (bad magic)";
        return false;
    }
    ByteReader r(bytes.subspan(8));
    info.format_version = r.u32();
    if (info.format_version != kStoreFormatVersion) {
        error = "tile store format version " + std::to_string(info.format_version) + ", this build reads version " +
                std::to_string(kStoreFormatVersion) +
                (info.format_version < kStoreFormatVersion
                     ? " (versions before 3 have no world tile addresses; recompile the store with this navmap-compile)"
                     : " (recompile the store with this navmap-compile)");
        return false;
    }
    const std::uint32_t size = r.u32();
    if (size != kHeaderSize || bytes.size() < kHeaderSize) {
        error = "truncated or malformed header";
        return false;
    }
    const std::uint32_t expected = crc32Of(bytes.subspan(0, kHeaderSize - 4));
    ByteReader tail(bytes.subspan(kHeaderSize - 4, 4));
    if (tail.u32() != expected) {
        error = "header checksum mismatch";
        return false;
    }
    info.origin_lat = r.f64();
    info.origin_lon = r.f64();
    WorldTileId root;
    root.z = static_cast<int>(r.u32());
    root.x = r.u32();
    root.y = r.u32();
    for (int i = 0; i < 3; ++i) r.u32();  // reserved
    const std::uint32_t levels = r.u32();
    info.dem_samples = r.u32();
    info.south = r.f64();
    info.west = r.f64();
    info.north = r.f64();
    info.east = r.f64();
    info.tile_count = r.u32();
    info.index_offset = r.u64();
    info.index_crc = r.u32();
    info.graph_offset = r.u64();
    info.graph_stored_size = r.u64();
    info.graph_raw_size = r.u64();
    info.graph_crc = r.u32();
    if (r.failed()) return false;
    if (!root.valid() || levels == 0 || levels > 28 || root.z + static_cast<int>(levels) - 1 > kMaxWorldZoom ||
        !std::isfinite(info.origin_lat) || !std::isfinite(info.origin_lon) || std::abs(info.origin_lat) > 85.0) {
        error = "implausible tile scheme in header";
        return false;
    }
    info.scheme = TileScheme(Projection(info.origin_lat, info.origin_lon), root, static_cast<int>(levels));
    return true;
}

}  // namespace navmap::map::detail
