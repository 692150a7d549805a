// SPDX-License-Identifier: Apache-2.0
// compileStore: the stages of compile_stages.h run in order, and the compile's summary.
#include "navmap/map/compile/compiler.h"

#include <unistd.h>
#include <zlib.h>

#include <cerrno>
#include <cmath>
#include <cstring>
#include <iomanip>
#include <sstream>

#include "compile_stages.h"
#include "navmap/common/untrusted_file.h"

namespace navmap::map {

using namespace detail;  // NOLINT: private implementation file

namespace {

// ---- sharded compile: what every shard of one compile has in common ----

// Name, size and CRC32 of an input file.
std::string fileFingerprint(const std::filesystem::path& path, const FileKind& kind) {
    // Regular files only, opened without blocking: a FIFO never holds the compile (checked again
    // by what reads the file).
    UntrustedFile file = UntrustedFile::open(path, kind);
    if (!file.ok()) throw CompileError(file.error());
    uLong crc = ::crc32(0L, Z_NULL, 0);
    std::uint64_t size = 0;
    std::vector<char> buffer(std::size_t{1} << 20);
    for (;;) {
        const ssize_t got = ::read(file.fd(), buffer.data(), buffer.size());
        if (got < 0 && errno == EINTR) continue;
        if (got < 0) throw CompileError("read(" + path.string() + "): " + std::strerror(errno));
        if (got == 0) break;
        const auto n = static_cast<std::size_t>(got);
        crc = ::crc32(crc, reinterpret_cast<const Bytef*>(buffer.data()), static_cast<uInt>(n));
        size += n;
    }
    std::ostringstream out;
    out << path.filename().string() << " " << size << " B crc32 " << std::hex << std::setw(8) << std::setfill('0')
        << crc;
    return out.str();
}

// The inputs and the options that shape tiles (ShardManifest::fingerprint).
std::string compileFingerprint(const CompileOptions& opt) {
    std::ostringstream out;
    out << std::setprecision(17) << "osm " << fileFingerprint(opt.osm, kOsmInput);
    for (const auto& dem : opt.dems) out << "; dem " << fileFingerprint(dem, FileKind{"DEM file", 0});
    out << "; leaf " << opt.leaf_tile_m << " m; dem samples " << opt.dem_samples << "; building "
        << opt.default_building_height_m << " m; ortho " << (opt.ortho_inputs ? "yes" : "no");
    return out.str();
}

void checkOptions(const CompileOptions& opt) {
    // Written so that NaN fails too (every comparison with NaN is false).
    if (!(opt.leaf_tile_m >= kMinLeafTileM && opt.leaf_tile_m <= kMaxLeafTileM) || opt.dem_samples < 0 ||
        opt.dem_samples == 1 || opt.dem_samples > kMaxDemSamples ||
        !(opt.default_building_height_m >= 0.0f && opt.default_building_height_m <= kMaxBuildingHeightM)) {
        throw CompileError(
            "invalid options: leaf tile size must be in [10, 1000000] m, DEM samples 0 or 2..1025, "
            "default building height in [0, 1000] m");
    }
    if (opt.shard.count < 1 || opt.shard.count > kMaxShards || opt.shard.index < 0 ||
        opt.shard.index >= opt.shard.count) {
        throw CompileError("invalid options: shard " + std::to_string(opt.shard.index) + " of " +
                           std::to_string(opt.shard.count) + " (N in [1, " + std::to_string(kMaxShards) +
                           "], K in [0, N))");
    }
    if (!opt.out.has_filename())
        throw CompileError("invalid options: output path \"" + opt.out.string() + "\" names no file");
}

/// Bounded memory (docs/tile-store.md "Bounded memory"): the node index in a file and the
/// features in spill files, compiled band by band; the DEM grids read back from there.
std::unique_ptr<Spill> openSpill(const CompileOptions& opt, DemInput& dem, CompileLog& log) {
    const std::filesystem::path parent =
        opt.spill_dir.empty() ? std::filesystem::absolute(opt.out).parent_path() : opt.spill_dir;
    auto spill = std::make_unique<Spill>(parent, opt.log);
    log.log("memory limit " + std::to_string(opt.memory_limit_mib) + " MiB: spilling to " + spill->dir.path().string());
    dem.dems.setScratchDir(spill->dir.path());  // filled DEM grids dropped and needed again come back from there
    return spill;
}

/// The global inputs of the ortho layers for the frame's bounds (CompileOptions::ortho_inputs).
std::shared_ptr<const ortho::GlobalInputs> readOrthoInputs(const CompileOptions& opt, const Frame& frame,
                                                           CompileStats& stats, CompileLog& log) {
    if (!opt.ortho_inputs) return nullptr;
    const double t_ortho = log.elapsed();
    std::shared_ptr<const ortho::GlobalInputs> inputs;
    try {
        const LatLonBounds& b = frame.bounds;
        inputs = opt.ortho_inputs({b.south, b.west, b.north, b.east});
    } catch (const std::exception& e) {
        throw CompileError(e.what());
    }
    stats.ortho_seconds += log.elapsed() - t_ortho;
    log.log("read the global orthoimage inputs");
    return inputs;
}

void logFrame(const Frame& frame, const CompileLog& log) {
    const TileScheme& scheme = frame.scheme;
    log.log("frame origin " + std::to_string(frame.proj.originLat()) + ", " + std::to_string(frame.proj.originLon()) +
            "; " + std::to_string(scheme.levelCount()) + " levels under world tile " + scheme.worldRoot().toString() +
            ", root " + std::to_string(static_cast<long>(scheme.rootSize() / 1000)) + " km, leaves " +
            std::to_string(static_cast<long>(std::lround(scheme.tileSize(scheme.leafLevel())))) + " m");
}

void writeManifest(const CompileOptions& opt, const CompileStats& stats, const std::string& fingerprint,
                   const CompileLog& log) {
    ShardManifest manifest;
    manifest.shard = opt.shard;
    manifest.tiles = stats.tiles;
    manifest.graph = opt.shard.index == 0;
    manifest.fingerprint = fingerprint;
    writeShardManifest(shardManifestPath(opt.out), manifest);
    log.log("wrote " + shardManifestPath(opt.out).string());
}

}  // namespace

CompileStats compileStore(const CompileOptions& opt) {
    checkOptions(opt);
    CompileStats stats;
    CompileLog log(opt.log, stats.warnings);
    // The one writer of opt.out from here on: a second compile to the same store fails now, not
    // after reading its input (StoreError "<out> is being written by another process (pid N)").
    StoreLock lock(opt.out);
    const std::string fingerprint = opt.shard.sharded() ? compileFingerprint(opt) : std::string{};
    const bool bounded = opt.memory_limit_mib > 0;
    // The road graph is the whole network's: shard 0 builds it, the other shards none.
    const bool with_graph = opt.shard.index == 0;

    // read: the DEM, then the OSM file (its handlers classify the tags as it streams)
    DemInput dem = readDems(opt.dems, opt.memory_limit_mib, log);
    stats.dem_voids_filled = dem.voids_filled;
    stats.dem_files = dem.dems.size();
    checkOsmFile(opt.osm);
    const std::unique_ptr<Spill> spill = bounded ? openSpill(opt, dem, log) : nullptr;
    OsmInput osm = readOsm(opt.osm, {opt.default_building_height_m, with_graph, spill.get()}, log);
    stats.repeated_members = osm.repeated_members;
    stats.turn_lane_ways = osm.turn_lane_ways;
    stats.turn_lane_values_ignored = osm.turn_lane_values_ignored;
    stats.turn_lane_tags_dropped = osm.turn_lane_tags_dropped;
    stats.read_seconds = log.elapsed();

    // frame: projection and tile scheme of the data's bounds
    const Frame frame = frameOf(osm.bounds, osm.coast, opt.leaf_tile_m);
    const std::shared_ptr<const ortho::GlobalInputs> ortho_inputs = readOrthoInputs(opt, frame, stats, log);
    logFrame(frame, log);

    // assemble: the sea from the coastlines (the road graph where the write needs it)
    const std::optional<PArea> sea = assembleSea(std::move(osm.coast), frame, stats, log);

    // band, project, tile, write
    const StoreInfo info = storeInfoOf(frame, opt.dem_samples);
    stats.tiles_per_level.assign(static_cast<std::size_t>(frame.scheme.levelCount()), 0);
    TilingContext ctx{frame.proj,
                      frame.scheme,
                      frame.data_bounds,
                      frame.grid,
                      dem.dems,
                      dem.spacing_m,
                      opt.dem_samples,
                      ortho_inputs.get(),
                      sea ? &*sea : nullptr,
                      opt.shard,
                      BandRange{},
                      {},
                      {}};
    stats.store_bytes = bounded ? writeBounded(std::move(lock), info, *spill, dem, opt.memory_limit_mib, with_graph,
                                               frame, ctx, stats, log)
                                : writeInMemory(std::move(lock), info, osm.features, with_graph, ctx, stats, log);
    warnDemCoverage(stats, dem, log);
    if (opt.shard.sharded()) writeManifest(opt, stats, fingerprint, log);
    stats.total_seconds = log.elapsed();
    log.log("wrote " + opt.out.string());
    return stats;
}

std::string formatSummary(const CompileStats& s) {
    std::ostringstream o;
    o << "roads:      " << s.roads << " polylines, " << s.road_vertices << " vertices\n"
      << "buildings:  " << s.buildings << "\n"
      << "areas:      " << s.areas << "\n"
      << "coast:      " << s.coast_ways << " coastline ways, " << s.sea_rings << " sea rings, " << s.islands
      << " islands, " << s.coast_gaps_closed << " gaps closed, " << s.coast_ways_left_out << " ways left out\n"
      << "labels:     " << s.place_labels << " places, " << s.poi_labels << " POIs, " << s.road_labels << " roads, "
      << s.area_labels << " areas\n"
      << "road graph: " << s.graph_nodes << " nodes, " << s.graph_edges << " directed edges; turn lanes on "
      << s.turn_lane_ways << " ways (" << s.turn_lane_values_ignored << " unknown values ignored, "
      << s.turn_lane_tags_dropped << " tags not used)\n"
      << "DEM:        " << s.dem_files << " files, " << s.dem_voids_filled << " void samples filled, "
      << s.tiles_without_dem << " leaf tiles not fully covered\n"
      << (s.tiles_with_ortho > 0 ? "ortho:      " + std::to_string(s.tiles_with_ortho) +
                                       " tiles with orthoimage layers, " + std::to_string(s.ortho_seconds) + " s\n"
                                 : std::string())
      << "tiles:      " << s.tiles << " (per level:";
    for (auto n : s.tiles_per_level) o << ' ' << n;
    o << ")\n"
      << "store:      " << s.store_bytes << " bytes\n"
      << "time:       " << s.read_seconds << " s reading, " << s.total_seconds << " s total\n";
    if (!s.warnings.empty()) o << "warnings:   " << s.warnings.size() << "\n";
    return o.str();
}

}  // namespace navmap::map
