// SPDX-License-Identifier: Apache-2.0
#pragma once
// The stages of compileStore (docs/tile-store.md "Compiler stages"), each a function from an
// explicit input to an explicit output, run in this order:
//   read      DEM files -> DemInput; the OSM file -> OsmInput (raw features in WGS84, kept in
//             memory or spilled). The libosmium handlers classify the tags as the file streams
//             (osm_handlers.h, tag_rules.h): classification is part of this pass, not a pass of
//             its own.
//   frame     the data's bounds -> Frame (projection, tile scheme, the data's tile columns).
//   assemble  coastline ways -> the sea area (coastline.h); graph ways -> the road graph
//             (graph_build.h, run where the write needs it).
//   band      bounded memory only: the spilled features -> BandPlan (runs of tile columns whose
//             features fit the limit) and one spill file per band.
//   project   raw features (of the input or of a band) -> ProjectedFeatures in the store frame,
//             with their labels and level-of-detail classes.
//   tile      projected features -> the tiles of one level (LevelTiles), level by level, with
//             DEM grids and ortho layers, handed to a sink in key order.
//   write     tiles and road graph -> the store file, then the warnings and the shard manifest.
// Private to navmap_map_compile; the stage tests include it.

#include <chrono>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

#include "feature_spill.h"
#include "navmap/common/untrusted_file.h"
#include "navmap/map/compile/compiler.h"
#include "navmap/map/compile/dem_mosaic.h"
#include "navmap/map/compile/shard.h"
#include "navmap/map/compile/spill_file.h"
#include "navmap/map/compile/store_writer.h"
#include "navmap/map/compile/triangulator.h"
#include "navmap/map/geometry.h"
#include "navmap/map/projection.h"
#include "navmap/map/road_graph.h"
#include "navmap/map/tile.h"
#include "navmap/map/tile_scheme.h"
#include "osm_handlers.h"
#include "spill_dir.h"

namespace navmap::map::ortho {
struct GlobalInputs;
}

namespace navmap::map::detail {

/// Progress lines (timed from the compile's start) and warnings (also kept in `warnings`).
class CompileLog {
public:
    CompileLog(std::function<void(const std::string&)> sink, std::vector<std::string>& warnings);
    [[nodiscard]] double elapsed() const;
    void log(const std::string& msg) const;
    void warn(const std::string& msg);
    [[nodiscard]] const std::function<void(const std::string&)>& sink() const { return m_sink; }

private:
    std::function<void(const std::string&)> m_sink;
    std::vector<std::string>& m_warnings;
    std::chrono::steady_clock::time_point m_start;
};

/// "12.3 MiB".
std::string mib(std::uint64_t bytes);

// ---- level-of-detail rules (docs/tile-store.md "Tile scheme": lower levels carry simplified geometry) ----

inline constexpr double kAlways = 1e300;
/// Largest tile edge (m) at which a road class still appears; the leaf level has everything.
double roadMaxTile(RoadClass c);
/// Largest tile edge (m) at which a place label of the class still appears.
double placeMaxTile(PlaceClass c);
/// The same for a point label (places by class, peaks to 16 km, other POIs leaf only).
double pointLabelMaxTile(const RawPointLabel& l);
inline constexpr double kBuildingKeepArea = 1500.0;  // m^2: buildings kept one level above the leaf
/// Coastline ends this close are joined, and ends this close to the data's border are closed
/// along it (osmcoastline's default gap distance is of the same order).
inline constexpr double kCoastCloseM = 1000.0;

// ---- read ----

/// The DEM files, loaded (in memory) or probed to be read when first sampled (bounded).
struct DemInput {
    DemMosaic dems;
    double spacing_m = 90.0;                      ///< of the last file
    std::vector<std::filesystem::path> all_void;  ///< files whose every sample is a void (warned)
    std::size_t voids_filled = 0;                 ///< when loaded now
};

/// Reads (memory_limit_mib 0) or probes the files; warns about files of voids only and about no
/// file at all. Throws DemError naming a bad file.
DemInput readDems(const std::vector<std::filesystem::path>& files, std::uint64_t memory_limit_mib, CompileLog& log);
/// Records `path` as all voids and warns.
void noteAllVoidDem(DemInput& dem, const std::filesystem::path& path, std::size_t samples, CompileLog& log);

/// The scratch folder of a bounded compile with the spill files the read writes.
struct Spill {
    Spill(const std::filesystem::path& parent, const std::function<void(const std::string&)>& log);
    SpillDir dir;
    std::optional<SpillWriter> features, graph;
};

/// Lat/lon bounds, grown point by point (empty: south > north).
struct LatLonBounds {
    double south = 90, north = -90, west = 180, east = -180;
    void grow(const GeoCoordinate& p);
};

struct OsmReadOptions {
    float default_building_height_m = 8.0f;
    bool with_graph = true;  ///< keep the ways of the road graph
    Spill* spill = nullptr;  ///< null: the features stay in memory
};

/// The OSM file's features, per kind in input order, in memory (or in `Spill` when bounded).
struct OsmInput {
    RawFeatures features;  ///< empty when spilled
    std::vector<RawCoastWay> coast;
    std::size_t roads = 0, buildings = 0, areas = 0, points = 0, places = 0;  ///< read, kept or spilled
    LatLonBounds bounds;                                                      ///< of the features, not the coast
    std::size_t repeated_members = 0;
    std::size_t turn_lane_ways = 0, turn_lane_values_ignored = 0, turn_lane_tags_dropped = 0;  ///< CompileStats'
};

/// The OSM input: libosmium streams it (no size cap), but only from a regular file
/// (docs/architecture.md "Untrusted files").
inline constexpr FileKind kOsmInput{"OSM input", 0};

/// Checks that `osm` is a regular file; CompileError otherwise.
void checkOsmFile(const std::filesystem::path& osm);
/// One relations pass for the multipolygons, then one pass of the handlers; throws CompileError
/// naming the file when it cannot be read or has no map features.
OsmInput readOsm(const std::filesystem::path& osm, const OsmReadOptions& options, CompileLog& log);

// ---- frame ----

/// Where the data lies and how it is tiled.
struct Frame {
    LatLonBounds bounds;  ///< the features' and the coastlines'
    Projection proj;
    Box data_bounds;
    TileScheme scheme;
    ShardGrid grid;  ///< the data's leaf columns, which shards and bands divide
};

Frame frameOf(LatLonBounds features, const std::vector<RawCoastWay>& coast, double leaf_tile_m);
/// The store header's fields of the frame.
StoreInfo storeInfoOf(const Frame& frame, int dem_samples);

// ---- projected features ----

struct PPoly {
    std::vector<std::vector<PlanarPoint>> outers, inners;  // outers CCW, inners CW
    Box bounds;
    double area = 0;
    PlanarPoint barycenter;
    std::int64_t id = 0;
};

struct PRoad {
    const RawRoad* raw;
    std::vector<PlanarPoint> pts;
    Box bounds;
};

struct PBuilding {
    PPoly poly;
    Triangulation tri;
    std::vector<std::uint32_t> ring_ends;
    float height = 0, min_height = 0;
};

struct PArea {
    PPoly poly;
    AreaClass cls;
    const std::string* name;
};

struct PLabel {
    LabelKind kind;
    std::uint8_t subclass;
    const std::string* name;
    PlanarPoint anchor, s0, s1;
    float importance;
    std::int64_t id;
    double max_tile;  // appears at levels with tiles up to this size
    double min_area;  // areas: polygon area, compared against the tile size
};

std::vector<PlanarPoint> project(const Projection& proj, const std::vector<GeoCoordinate>& pts);
PPoly projectPolygon(const Projection& proj, const RawPolygon& raw);

// ---- assemble ----

/// The sea of the coastlines (coastline.h): one area, odd winding with its islands; none without
/// coastlines or when nothing assembles. Counts the coast in `stats` (and the sea in its areas).
std::optional<PArea> assembleSea(std::vector<RawCoastWay> coast, const Frame& frame, CompileStats& stats,
                                 CompileLog& log);
/// The road graph of ways in memory.
RoadGraph assembleGraph(const std::vector<RawGraphWay>& ways, const Projection& proj);

// ---- project ----

/// The features of a tiling pass in the store frame, with the labels they carry.
struct ProjectedFeatures {
    std::vector<PRoad> roads;  ///< by class, input order within a class
    std::vector<PBuilding> buildings;
    std::vector<PArea> areas;    ///< land areas; the sea comes after them
    const PArea* sea = nullptr;  ///< null: no coastline in the input
    std::vector<PLabel> labels;  ///< area, point, place, road labels in that order
};

/// Projects `raw` (which must outlive the result); adds the features that count to `stats`.
ProjectedFeatures projectFeatures(const RawFeatures& raw, const Projection& proj, const PArea* sea,
                                  CompileStats& stats);

// ---- tile ----

/// Bands first..last of `count` equal bands of the data's columns, together ({0, 0, 1}: all).
struct BandRange {
    int first = 0, last = 0, count = 1;
};

/// What every band of one compile shares.
struct TilingContext {
    const Projection& proj;
    const TileScheme& scheme;
    Box data_bounds;
    ShardGrid grid;
    const DemMosaic& dems;
    double dem_spacing_m;
    int dem_samples;
    const ortho::GlobalInputs* ortho_inputs;  // null: no ortho layers
    const PArea* sea;                         // null: no coastline in the input
    ShardSpec shard;                          // the job's columns (--shard)
    BandRange band;                           // of those, this pass's band (all by default)
    std::function<void(const Tile&)> emit;    // each finished tile: level by level, by key
    std::function<void(int level, double size, std::size_t tiles)> level_done;  // may be null
};

/// The tiles of one level that a pass builds: those of the context's columns.
class LevelTiles {
public:
    LevelTiles(const TilingContext& ctx, int level);
    [[nodiscard]] bool owned(std::uint32_t x) const { return x >= m_own.first && x <= m_own.second; }
    /// The tile, made empty on first use.
    Tile& at(TileId id);
    [[nodiscard]] int level() const { return m_level; }
    [[nodiscard]] double size() const { return m_size; }
    [[nodiscard]] bool isLeaf() const { return m_leaf; }
    /// Simplification tolerance (0 at the leaf level).
    [[nodiscard]] double tolerance() const { return m_leaf ? 0.0 : m_size / 1024.0; }
    std::map<std::uint64_t, Tile> tiles;  ///< ordered: stable file layout
    /// The sea's rings clipped to each tile: its DEM samples there are at sea level.
    std::unordered_map<std::uint64_t, std::vector<std::vector<PlanarPoint>>> sea_rings;

private:
    const TileScheme& m_scheme;
    int m_level;
    double m_size;
    bool m_leaf;
    std::pair<std::uint32_t, std::uint32_t> m_own;
};

/// The tiles of one level: every tile over the data (each gets a DEM grid), the features shown
/// there (simplified above the leaf level, clipped to the tiles), the DEM grids and ortho
/// layers, each tile's roads by class and labels by importance. Counts tiles without full DEM
/// and ortho tiles in `stats`.
LevelTiles tileLevel(const ProjectedFeatures& features, const TilingContext& ctx, int level, CompileStats& stats);
/// Projects `raw` and builds its tiles level by level into ctx.emit; adds the features it counts
/// and the tiles it built to `stats`.
void tileFeatures(const RawFeatures& raw, const TilingContext& ctx, CompileStats& stats);

// ---- band (bounded memory) ----

/// Bytes of memory a band needs per byte of its spilled features: the raw features, their
/// projection, triangulations, simplified copies and the level's tiles (measured on 100 copies
/// of Andorra: about 5).
inline constexpr double kMemoryPerSpilledByte = 5.0;
/// The fine bands the bands are made of (at most one open spill file each while the features
/// are distributed).
inline constexpr int kMaxBands = 256;

/// Runs of the fine bands whose features fit `budget` (see compile_band.cpp).
std::vector<BandRange> bandsWithin(const std::vector<std::uint64_t>& from, const std::vector<std::uint64_t>& to,
                                   std::uint64_t budget);
/// The ranges of `bands` fine bands that build a tile holding the feature `one` holds.
std::vector<std::pair<int, int>> featureBands(const RawFeatures& one, const Projection& proj, const TileScheme& scheme,
                                              const ShardGrid& grid, int bands);

/// Decodes a spill record of `reader` into `out`; throws SpillError naming the file.
void decodeRecord(const SpillReader& reader, std::span<const std::uint8_t> record, RawFeatures& out);
/// Features of all kinds in `f` (graph ways aside).
std::size_t featureCount(const RawFeatures& f);

/// The bands of a bounded compile.
struct BandPlan {
    std::vector<BandRange> bands;
    std::vector<char> used;    ///< per band: holds columns of this job
    std::vector<int> band_of;  ///< fine band -> band
    std::uint64_t budget = 0;  ///< spilled bytes per band
};

/// Measures the spilled features (features.spill -> feature-bands.spill) and plans the bands of
/// `limit_bytes` of memory for the job `shard`.
BandPlan planBands(const SpillDir& spill, const Frame& frame, ShardSpec shard, std::uint64_t limit_bytes);
/// Distributes features.spill into band-<k>.spill per used band (a feature counts in its first
/// band only) and removes features.spill and feature-bands.spill.
void splitIntoBands(const SpillDir& spill, const BandPlan& plan);
/// Reads band k's spill file (and removes it).
RawFeatures readBand(const SpillDir& spill, int k, std::uint64_t& bytes);

/// The tiles of all bands, encoded in per-band spill files: where each tile is.
struct BandTiles {
    struct Ref {
        std::uint64_t key;
        int band;
        std::uint64_t offset;
    };
    std::vector<Ref> refs;  ///< in key order once tileBands returns
    std::vector<std::unique_ptr<SpillReader>> files;
};

/// Tiles band after band (project + tile of each) into tiles-<k>.spill.
BandTiles tileBands(const SpillDir& spill, const BandPlan& plan, TilingContext& ctx, CompileStats& stats,
                    CompileLog& log);

// ---- write ----

/// In memory: the road graph (with_graph), then the tiles of `all` straight into the store.
std::uint64_t writeInMemory(StoreLock lock, const StoreInfo& info, RawFeatures& all, bool with_graph,
                            TilingContext& ctx, CompileStats& stats, CompileLog& log);
/// Bounded: band plan, bands, tiles of each band, DEM released, road graph on disk, then the
/// band's tiles merged into the store in key order.
std::uint64_t writeBounded(StoreLock lock, const StoreInfo& info, Spill& spill, DemInput& dem, std::uint64_t limit_mib,
                           bool with_graph, const Frame& frame, TilingContext& ctx, CompileStats& stats,
                           CompileLog& log);
/// The store of band tiles (key order) and the graph's encoding (may be null).
std::uint64_t writeBandTiles(StoreLock lock, const StoreInfo& info, const BandTiles& tiles,
                             const std::function<void(const StoreWriter::ByteSink&)>& graph, CompileLog& log);
/// Warns about leaf tiles the DEM does not cover, naming DEM files of voids only.
void warnDemCoverage(const CompileStats& stats, const DemInput& dem, CompileLog& log);

}  // namespace navmap::map::detail
