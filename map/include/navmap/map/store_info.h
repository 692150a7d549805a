// SPDX-License-Identifier: Apache-2.0
#pragma once
// Header of a tile store file (format described in docs/tile-store.md).

#include <cstdint>
#include <stdexcept>

#include "navmap/map/tile_scheme.h"

namespace navmap::map {

inline constexpr char kStoreMagic[8] = {'N', 'A', 'V', 'M', 'A', 'P', 'T', 'S'};
/// Bumped on every incompatible change. Version 2 added the orthoimage input layers of the tiles
/// (seed 6.5); version 3 the world tile scheme (world_tiles.h: the frame is World Mercator, the
/// root a world tile). Readers read version 3 only and refuse the others naming the version.
inline constexpr std::uint32_t kStoreFormatVersion = 3;

/// Raised at setup when a store cannot be used; the message names the file and the problem.
class StoreError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

struct StoreInfo {
    std::uint32_t format_version = kStoreFormatVersion;
    double origin_lat = 0;  ///< the store frame's origin (Projection(origin_lat, origin_lon))
    double origin_lon = 0;
    TileScheme scheme;
    std::uint32_t dem_samples = 0;                    ///< DEM samples per tile side (0: no DEM)
    double south = 0, west = 0, north = 0, east = 0;  ///< data bounds, degrees
    std::uint32_t tile_count = 0;
    std::uint64_t graph_offset = 0, graph_stored_size = 0, graph_raw_size = 0;
    std::uint32_t graph_crc = 0;
    std::uint64_t index_offset = 0;
    std::uint32_t index_crc = 0;
};

}  // namespace navmap::map
