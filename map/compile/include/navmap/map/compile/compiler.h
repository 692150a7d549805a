// SPDX-License-Identifier: Apache-2.0
#pragma once
// navmap-compile's engine: OpenStreetMap PBF + SRTM DEM -> tile store (docs/tile-store.md).
// Reads the OSM file in one libosmium pass of small handlers (roads, buildings, areas,
// labels, graph; multipolygon relations are collected in a first relations-only pass),
// projects to the store frame, builds the quadtree pyramid level by level and writes it.
// With a memory limit the features spill to disk and the pyramid is built one band of tile
// columns at a time (docs/tile-store.md "Bounded memory"); the store is the same.

#include <array>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "navmap/map/compile/shard.h"

namespace navmap::map {

namespace ortho {
struct GlobalInputs;
}

/// Raised when the input cannot be compiled; the message names the file and the problem.
class CompileError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

/// Ranges of the numeric options (navmap-compile's usage errors quote them).
inline constexpr double kMinLeafTileM = 10.0, kMaxLeafTileM = 1e6;
inline constexpr int kMaxDemSamples = 1025;  ///< 0 (no DEM grid) or 2..kMaxDemSamples
inline constexpr float kMaxBuildingHeightM = 1000.0f;

struct CompileOptions {
    std::filesystem::path osm;                ///< .osm.pbf (or any format libosmium reads)
    std::vector<std::filesystem::path> dems;  ///< SRTM .hgt tiles, any number (may be empty)
    std::filesystem::path out;                ///< store file to write
    double leaf_tile_m = 2000.0;              ///< edge of the finest tiles
    int dem_samples = 33;                     ///< DEM samples per tile side, every level
    float default_building_height_m = 8.0f;
    /// Progress and warnings, one line each; null = silent.
    std::function<void(const std::string&)> log;
    /// The global inputs of the synthetic orthoimages (seed 6.5), asked for once the data's bounds
    /// (south, west, north, east, degrees) are known; every tile then gets its ortho layers
    /// (docs/tile-store.md). Null: none. An exception it throws becomes a CompileError with its
    /// message.
    std::function<std::shared_ptr<const ortho::GlobalInputs>(const std::array<double, 4>& bounds)> ortho_inputs;
    /// Shard k of N (shard.h, docs/sharded-compile.md): only the tiles of that column band, the
    /// road graph only in shard 0, and `<out>.shard.json` beside the store. Default: the whole store.
    ShardSpec shard;
    /// 0: everything in memory. Otherwise the bounded-memory compile (docs/tile-store.md "Bounded
    /// memory"): the node-location index in a file, the features in spill files, and the tiles
    /// built in as many column bands as keep one band's features within this many MiB.
    std::uint64_t memory_limit_mib = 0;
    /// Where the bounded compile makes its scratch folder (removed at the end); empty: the
    /// folder of `out`.
    std::filesystem::path spill_dir;
};

struct CompileStats {
    std::size_t roads = 0, road_vertices = 0;
    std::size_t buildings = 0, areas = 0;
    std::size_t place_labels = 0, poi_labels = 0, road_labels = 0, area_labels = 0;
    std::size_t graph_nodes = 0, graph_edges = 0;
    std::size_t dem_files = 0, dem_voids_filled = 0, tiles_without_dem = 0;
    /// natural=coastline ways read; sea rings and islands assembled; gaps closed; ways of broken
    /// coastlines left out (coastline.h).
    std::size_t coast_ways = 0, sea_rings = 0, islands = 0, coast_gaps_closed = 0, coast_ways_left_out = 0;
    /// Relation members left out as repeats of an earlier member of the same relation (each
    /// reaches the multipolygon assembly once; docs/tile-store.md "Limits").
    std::size_t repeated_members = 0;
    /// Turn lanes (docs/tile-store.md "Turn lanes"): road-graph ways with some; values not
    /// understood (ignored); tags not used (too many lanes, or a two-way road's plain turn:lanes
    /// whose lane counts do not say its direction).
    std::size_t turn_lane_ways = 0, turn_lane_values_ignored = 0, turn_lane_tags_dropped = 0;
    std::size_t tiles = 0;
    /// Bounded compile (CompileOptions::memory_limit_mib): the features each band of tile columns
    /// tiled, west to east (a feature over several bands counts in each: the work, not the
    /// input); empty when unbounded. Tests assert it grows with the input, not faster.
    std::vector<std::size_t> features_per_band;
    std::size_t tiles_with_ortho = 0;  ///< tiles with ortho layers (CompileOptions::ortho_inputs)
    double ortho_seconds = 0;          ///< reading the global inputs and sampling the layers
    std::vector<std::size_t> tiles_per_level;
    std::uint64_t store_bytes = 0;
    double read_seconds = 0, total_seconds = 0;
    std::vector<std::string> warnings;
};

/// Compiles; throws CompileError (bad options, bad OSM input, a way or relation beyond the caps of
/// docs/tile-store.md "Limits", bad DEM, nothing to compile) or
/// StoreError (cannot write: the folder of `out` missing, another process writing it, ...). Holds
/// the store's StoreLock from the start. A DEM that does not cover part of the data is a warning:
/// flat terrain.
CompileStats compileStore(const CompileOptions& options);

/// Human-readable multi-line summary (counts per layer, tiles, bytes, seconds).
std::string formatSummary(const CompileStats& stats);

}  // namespace navmap::map
