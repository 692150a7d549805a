// SPDX-License-Identifier: Apache-2.0
#pragma once
// Sharded compile (docs/sharded-compile.md): a compile split into independent jobs by tile
// range, and the merge of their stores into the one store a single compile writes.
//
// Shard k of N owns, at every level, the tiles whose centre lies in the k-th of N equal
// columns (west to east) of the data: of the leaf columns the data's bounding box covers
// (ShardGrid), since the root square, a world tile, may be much wider than the data. Every job reads the whole input,
// so that all agree on the projection, the bounds and the tile scheme, and builds only its own tiles (the DEM grids,
// clipping and encoding, the bulk of the work); shard 0 also builds the road graph. Each job writes a store with its
// tiles and, beside it, a manifest
// (`<store>.shard.json`) naming its place (k of N), its tile count and a fingerprint of its
// input and options. mergeShards() checks that the manifests form one complete set of one
// compile and writes the tiles in the single compile's order: the merged store equals the
// single-process store byte for byte.

#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "navmap/map/geometry.h"
#include "navmap/map/projection.h"
#include "navmap/map/store_info.h"
#include "navmap/map/tile.h"

namespace navmap::map {

inline constexpr int kMaxShards = 4096;

struct ShardSpec {
    int index = 0;  ///< k in [0, count)
    int count = 1;  ///< N; 1: not sharded
    [[nodiscard]] bool sharded() const { return count > 1; }
};

/// The columns the bands divide: the leaf columns first..last (inclusive) of the data.
struct ShardGrid {
    int leaf_level = 0;
    std::uint32_t first = 0, last = 0;
};
/// The data's box in a store frame: the four corners of its lat/lon bounds projected (the box the
/// compiler tiles; Mercator maps a lat/lon box to an axis-aligned one).
Box dataBox(const Projection& frame, double south, double west, double north, double east);
/// The grid of a scheme over a data box.
ShardGrid shardGridOf(const TileScheme& scheme, const Box& data_box);
/// The grid of a store, from its header.
ShardGrid shardGridOf(const StoreInfo& info);

/// The shard owning a tile: the band of its centre among N equal bands of the grid's columns,
/// in [0, shard_count) (columns west of the data go to the first band, east of it to the last).
int tileShard(TileId id, int shard_count, const ShardGrid& grid);
/// The tile columns of `level` that shard `spec` owns, inclusive; first > second when none.
std::pair<std::uint32_t, std::uint32_t> shardColumns(int level, ShardSpec spec, const ShardGrid& grid);
/// The columns of bands first..last (inclusive) of `count`, together; first > second when none.
std::pair<std::uint32_t, std::uint32_t> bandColumns(int level, int first, int last, int count, const ShardGrid& grid);
/// Parses "K/N" (navmap-compile --shard); throws CompileError naming the text otherwise.
ShardSpec parseShardSpec(const std::string& text);

/// What a shard job writes beside its store.
struct ShardManifest {
    ShardSpec shard;
    std::uint64_t tiles = 0;  ///< tiles in the shard's store
    bool graph = false;       ///< the store carries the road graph (shard 0)
    /// Input and options of the compile: size and CRC32 of each input file and the options
    /// that shape tiles; every shard of one compile has the same.
    std::string fingerprint;
};

/// `<store>.shard.json`.
std::filesystem::path shardManifestPath(const std::filesystem::path& store);
/// Writes atomically (temporary file, rename); throws CompileError naming the file.
void writeShardManifest(const std::filesystem::path& path, const ShardManifest& manifest);
/// Throws CompileError naming the file and the problem ("x.shard.json: no such file",
/// "x.shard.json: not a shard manifest: ...").
ShardManifest readShardManifest(const std::filesystem::path& path);

struct MergeStats {
    std::size_t shards = 0;
    std::size_t tiles = 0;
    std::uint64_t store_bytes = 0;
    double seconds = 0;
};

/// Merges the stores of every shard of one compile into `out`. Throws CompileError when the set
/// is not one whole compile (a shard missing or given twice, shards of another compile or
/// another N, a tile in the wrong shard, a damaged shard store), naming the file; StoreError
/// when `out` cannot be written. `log` gets progress lines (may be null).
MergeStats mergeShards(const std::vector<std::filesystem::path>& stores, const std::filesystem::path& out,
                       const std::function<void(const std::string&)>& log);

}  // namespace navmap::map
