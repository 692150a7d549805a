// SPDX-License-Identifier: Apache-2.0
// navmap-compile: OpenStreetMap PBF + SRTM DEM tiles -> navmap tile store.
//   navmap-compile --osm data/andorra-2021-04-14.osm.pbf --dem data/N42E001.hgt --out build/andorra.navmap
// A sharded compile (docs/sharded-compile.md): N jobs with --shard K/N, then one --merge.
//   navmap-compile --osm ... --dem ... --shard 1/4 --out part-1.navmap
//   navmap-compile --merge part-0.navmap part-1.navmap part-2.navmap part-3.navmap --out andorra.navmap
// In bounded memory (docs/tile-store.md "Bounded memory"): the features spill to disk, band by band.
//   navmap-compile --osm region.osm.pbf --dem ... --memory-limit 2048 --spill-dir /var/tmp --out region.navmap
// Exit status: 0 ok, 1 bad input (one line naming the file and the problem), 2 usage.

#include <cstdlib>
#include <filesystem>
#include <iostream>

#include "navmap/cli/cli.h"
#include "navmap/map/compile/compiler.h"
#include "navmap/map/dem.h"
#include "navmap/map/store_info.h"
#ifdef NAVMAP_WITH_ORTHO_IO
#include "navmap/map/compile/ortho/marble_inputs.h"
#endif

namespace {

using navmap::cli::finiteIn;

CLI::Validator demSamples() {
    const std::string allowed =
        "0 (no DEM grid) or an integer in [2, " + std::to_string(navmap::map::kMaxDemSamples) + "]";
    return CLI::Validator(
        [allowed](std::string& input) -> std::string {
            char* end = nullptr;
            const long v = std::strtol(input.c_str(), &end, 10);
            if (input.empty() || end != input.c_str() + input.size() || v < 0 || v == 1 ||
                v > navmap::map::kMaxDemSamples) {
                return "'" + input + "' is not " + allowed;
            }
            return {};
        },
        "0 or 2.." + std::to_string(navmap::map::kMaxDemSamples));
}

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{"navmap-compile: compile OpenStreetMap + SRTM DEM into a navmap tile store"};
    navmap::cli::setUp(app, "navmap-compile");
    navmap::map::CompileOptions opt;
    std::vector<std::string> dems;
    std::string osm, out, ortho_data, shard, spill_dir;
    std::vector<std::string> merge;
    bool quiet = false;
    auto* osm_option = app.add_option("--osm", osm, "OpenStreetMap extract (.osm.pbf); required unless --merge");
    app.add_option("--dem", dems, "SRTM .hgt tile(s) (repeatable, 1201x1201 or 3601x3601)");
    app.add_option("--out", out, "tile store file to write (its folder must exist)")->required();
    app.add_option("--leaf-size", opt.leaf_tile_m, "edge of the finest tiles in metres")
        ->check(finiteIn(navmap::map::kMinLeafTileM, navmap::map::kMaxLeafTileM))
        ->capture_default_str();
    app.add_option("--dem-samples", opt.dem_samples, "DEM samples per tile side")
        ->check(demSamples())
        ->capture_default_str();
    app.add_option("--default-building-height", opt.default_building_height_m, "metres, when untagged")
        ->check(finiteIn(0.0, navmap::map::kMaxBuildingHeightM))
        ->capture_default_str();
#ifdef NAVMAP_WITH_ORTHO_IO
    app.add_option("--ortho-data", ortho_data,
                   "marble-qt-data folder (/usr/share/marble/data): sample the global inputs of the synthetic "
                   "orthoimages onto every tile (seed 6.5, docs/orthoimage.md)");
#endif
    auto* shard_option =
        app.add_option("--shard", shard,
                       "K/N: compile only shard K of N (the K-th of N column bands of tiles) and write "
                       "<out>.shard.json beside the store; --merge joins the N stores");
    auto* merge_option =
        app.add_option("--merge", merge, "shard stores of one compile (every K of N once): merge them into --out");
    merge_option->excludes(osm_option)->excludes(shard_option);
    app.add_option("--memory-limit", opt.memory_limit_mib,
                   "MiB: spill the node index and the features to disk and build the tiles in as many column "
                   "bands as keep one band's features within this; 0: everything in memory")
        ->check(navmap::cli::integerIn(0, 1LL << 30))
        ->capture_default_str();
    app.add_option("--spill-dir", spill_dir,
                   "folder for the scratch files of --memory-limit (removed at the end); default: the folder of --out");
    app.add_flag("-q,--quiet", quiet, "no progress output (summary and errors only)");
    if (const auto exit_status = navmap::cli::parse(app, argc, argv)) return *exit_status;
    if (osm.empty() && merge.empty()) {
        std::cerr << "navmap-compile: --osm is required (or --merge with the stores of a sharded compile)\n"
                  << "Run with --help for more information.\n";
        return 2;
    }
    if (!shard.empty()) {
        try {
            opt.shard = navmap::map::parseShardSpec(shard);
        } catch (const navmap::map::CompileError& e) {
            std::cerr << "navmap-compile: " << e.what() << "\nRun with --help for more information.\n";
            return 2;
        }
    }

    if (opt.memory_limit_mib > 0) {
        // libosmium reads ahead up to 20 compressed blocks and 20 decoded buffers (a decoded
        // block of ways is several MiB); its queue sizes are set through the environment only.
        // Two of each keep both cores busy (docs/tile-store.md "Bounded memory"). Set here,
        // before any thread starts; a value the user set is kept.
        for (const char* queue :
             {"OSMIUM_MAX_INPUT_QUEUE_SIZE", "OSMIUM_MAX_OSMDATA_QUEUE_SIZE", "OSMIUM_MAX_WORK_QUEUE_SIZE"}) {
            ::setenv(queue, "2", 0);
        }
    }
    opt.osm = osm;
    opt.out = out;
    opt.spill_dir = spill_dir;
    for (const auto& d : dems) opt.dems.emplace_back(d);
    if (!quiet) opt.log = [](const std::string& line) { std::cerr << line << '\n'; };
#ifdef NAVMAP_WITH_ORTHO_IO
    if (!ortho_data.empty()) {
        opt.ortho_inputs = [ortho_data](const std::array<double, 4>& bounds) {
            namespace ortho = navmap::map::ortho;
            ortho::MarbleInputOptions o;
            o.bounds = bounds;
            return std::make_shared<const ortho::GlobalInputs>(ortho::loadGlobalInputs(ortho_data, o));
        };
    }
#endif
    try {
        if (!merge.empty()) {
            std::vector<std::filesystem::path> stores(merge.begin(), merge.end());
            const auto stats = navmap::map::mergeShards(stores, out, opt.log);
            std::cout << "merged " << stats.shards << " shards: " << stats.tiles << " tiles, " << stats.store_bytes
                      << " bytes in " << stats.seconds << " s\n";
            return 0;
        }
        const auto stats = navmap::map::compileStore(opt);
        std::cout << navmap::map::formatSummary(stats);
        for (const auto& w : stats.warnings) std::cout << "warning: " << w << '\n';
        return 0;
    } catch (const navmap::map::CompileError& e) {
        std::cerr << "navmap-compile: " << e.what() << '\n';
    } catch (const navmap::map::DemError& e) {
        std::cerr << "navmap-compile: " << e.what() << '\n';
    } catch (const navmap::map::StoreError& e) {
        std::cerr << "navmap-compile: " << e.what() << '\n';
    }
    return 1;
}
