// SPDX-License-Identifier: Apache-2.0
// The write stage of compileStore (compile_stages.h): the tiles and the road graph into the
// store, in memory straight from the tiling, bounded from the bands' tile files; and the
// warnings about what the DEM does not cover.
#include "compile_stages.h"
#include "graph_build.h"

namespace navmap::map::detail {

namespace {

void logGraph(std::size_t nodes, std::size_t edges, CompileStats& stats, const CompileLog& log,
              const std::string& more = {}) {
    stats.graph_nodes = nodes;
    stats.graph_edges = edges;
    log.log("road graph: " + std::to_string(stats.graph_nodes) + " nodes, " + std::to_string(stats.graph_edges) +
            " edges" + more);
}

/// The DEM grids are done with: their memory goes before the road graph's comes.
void releaseDem(DemInput& dem, CompileStats& stats, CompileLog& log) {
    stats.dem_voids_filled += dem.dems.voidsFilled();
    for (const auto& path : dem.dems.allVoidFiles()) {
        const HgtShape shape = probeHgt(path);
        noteAllVoidDem(dem, path, static_cast<std::size_t>(shape.side) * static_cast<std::size_t>(shape.side), log);
    }
    log.log("DEM: " + std::to_string(dem.dems.fileLoads()) + " reads of " + std::to_string(dem.dems.size()) +
            " files, " + std::to_string(dem.dems.scratchReads()) + " grids read back filled, at most " +
            mib(dem.dems.peakFileBytes()) + " held");
    dem.dems = DemMosaic{};
}

/// The road graph on disk (graph_build.h): node ids sorted in runs of a quarter of the limit,
/// nodes, edges and shape in scratch files, encoded into the store at the end.
std::unique_ptr<DiskGraph> assembleDiskGraph(const Spill& spill, const Projection& proj, std::uint64_t limit,
                                             CompileStats& stats, CompileLog& log) {
    auto graph = std::make_unique<DiskGraph>(
        [&](const std::function<void(const RawGraphWay&)>& f) {
            SpillReader in(spill.dir / "graph.spill");
            std::vector<std::uint8_t> record;
            RawFeatures one;
            while (in.next(record)) {
                one.graph_ways.clear();
                decodeRecord(in, record, one);
                for (const auto& w : one.graph_ways) f(w);
            }
        },
        proj, spill.dir.path(), limit / 4);
    logGraph(graph->nodes(), graph->edges(), stats, log,
             " (node ids sorted in " + std::to_string(graph->idRuns()) + " run(s), on disk until written)");
    return graph;
}

}  // namespace

std::uint64_t writeInMemory(StoreLock lock, const StoreInfo& info, RawFeatures& all, bool with_graph,
                            TilingContext& ctx, CompileStats& stats, CompileLog& log) {
    const RoadGraph graph = with_graph ? assembleGraph(all.graph_ways, ctx.proj) : RoadGraph{};
    logGraph(graph.nodes.size(), graph.edges.size(), stats, log);
    all.graph_ways.clear();
    all.graph_ways.shrink_to_fit();
    StoreWriter writer(std::move(lock), info);
    ctx.emit = [&](const Tile& t) { writer.addTile(t); };
    ctx.level_done = [&](int level, double size, std::size_t tiles) {
        log.log("level " + std::to_string(level) + " (" + std::to_string(static_cast<long>(size)) + " m tiles): " +
                std::to_string(tiles) + " tiles, store " + std::to_string(writer.tileBytes() / 1024) + " KiB");
    };
    tileFeatures(all, ctx, stats);
    if (with_graph) writer.setGraph(graph);
    return writer.finish();
}

std::uint64_t writeBounded(StoreLock lock, const StoreInfo& info, Spill& spill, DemInput& dem, std::uint64_t limit_mib,
                           bool with_graph, const Frame& frame, TilingContext& ctx, CompileStats& stats,
                           CompileLog& log) {
    const std::uint64_t limit = limit_mib * std::uint64_t{1048576};
    const BandPlan plan = planBands(spill.dir, frame, ctx.shard, limit);
    log.log("spilled " + std::to_string(spill.features->records()) + " features (" + mib(spill.features->bytes()) +
            "), at most " + mib(plan.budget) + " per band; " + std::to_string(plan.bands.size()) + " band(s)");
    splitIntoBands(spill.dir, plan);
    spill.features.reset();
    const BandTiles tiles = tileBands(spill.dir, plan, ctx, stats, log);
    releaseDem(dem, stats, log);
    std::unique_ptr<DiskGraph> graph;
    if (with_graph) {
        graph = assembleDiskGraph(spill, frame.proj, limit, stats, log);
    } else {
        logGraph(0, 0, stats, log);
    }
    std::filesystem::remove(spill.dir / "graph.spill");
    std::function<void(const StoreWriter::ByteSink&)> encode_graph;
    if (graph) encode_graph = [&](const StoreWriter::ByteSink& sink) { graph->encode(sink); };
    return writeBandTiles(std::move(lock), info, tiles, encode_graph, log);
}

std::uint64_t writeBandTiles(StoreLock lock, const StoreInfo& info, const BandTiles& tiles,
                             const std::function<void(const StoreWriter::ByteSink&)>& graph, CompileLog& log) {
    StoreWriter writer(std::move(lock), info);
    std::vector<std::uint8_t> payload, tile_bytes;
    std::size_t level_tiles = 0;
    const auto& refs = tiles.refs;
    for (std::size_t i = 0; i < refs.size(); ++i) {
        const BandTiles::Ref& r = refs[i];
        const TileId id{static_cast<std::uint8_t>(r.key >> 56), static_cast<std::uint32_t>((r.key >> 28) & 0xFFFFFFF),
                        static_cast<std::uint32_t>(r.key & 0xFFFFFFF)};
        const SpillReader& in = *tiles.files[static_cast<std::size_t>(r.band)];
        in.readAt(r.offset, payload);
        if (payload.size() < 8) throw SpillError(in.path().string() + ": damaged tile record");
        tile_bytes.assign(payload.begin() + 8, payload.end());
        writer.addRawTile(id, tile_bytes);
        ++level_tiles;
        if (i + 1 == refs.size() || (refs[i + 1].key >> 56) != (r.key >> 56)) {
            log.log("level " + std::to_string(id.level) + " (" +
                    std::to_string(static_cast<long>(info.scheme.tileSize(id.level))) +
                    " m tiles): " + std::to_string(level_tiles) + " tiles, store " +
                    std::to_string(writer.tileBytes() / 1024) + " KiB");
            level_tiles = 0;
        }
    }
    if (graph) writer.writeGraph(graph);
    return writer.finish();
}

void warnDemCoverage(const CompileStats& stats, const DemInput& dem, CompileLog& log) {
    if (stats.tiles_without_dem == 0 || stats.dem_files == 0) return;
    const std::string tiles =
        std::to_string(stats.tiles_without_dem) + " of " + std::to_string(stats.tiles_per_level.back());
    std::string names;
    for (const auto& path : dem.all_void) names += (names.empty() ? "" : ", ") + path.filename().string();
    if (dem.all_void.size() == stats.dem_files) {
        log.warn(tiles + " leaf tiles have no heights: the DEM is all voids (" + names + "); terrain is flat (0 m)");
    } else if (!dem.all_void.empty()) {
        log.warn(tiles + " leaf tiles lie partly outside the DEM or on DEM files that are all voids (" + names +
                 "); missing areas are flat (0 m)");
    } else {
        log.warn(tiles + " leaf tiles lie partly outside the DEM; missing areas are flat (0 m)");
    }
}

}  // namespace navmap::map::detail
