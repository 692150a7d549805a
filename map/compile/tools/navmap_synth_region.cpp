// SPDX-License-Identifier: Apache-2.0
// navmap-synth-region: a country-sized test region made of copies of a real extract, for scale
// runs of navmap-compile (docs/benchmarks/2026-11-26-bounded-compile.md). Not installed.
//   navmap-synth-region --osm data/andorra-2021-04-14.osm.pbf --dem data/N42E001.hgt --copies 100 --out-dir /tmp/r100
// writes /tmp/r100/region.osm.pbf and the .hgt tiles that cover it, and prints the
// navmap-compile arguments for them. Exit status: 0 ok, 1 bad input, 2 usage.

#include <iostream>

#include "navmap/cli/cli.h"
#include "synth_region.h"

int main(int argc, char** argv) {
    CLI::App app{"navmap-synth-region: copies of an OSM extract and its SRTM tile over a large area"};
    navmap::cli::setUp(app, "navmap-synth-region");
    navmap::map::tools::SynthRegionOptions opt;
    std::string osm, dem, out_dir;
    app.add_option("--osm", osm, "source extract (.osm.pbf)")->required();
    app.add_option("--dem", dem, "its SRTM tile (.hgt); the region gets tiles made from it");
    app.add_option("--copies", opt.copies, "copies of the extract, ceil(sqrt(N)) per row")
        ->check(navmap::cli::integerIn(1, 10000))
        ->capture_default_str();
    app.add_option("--gap", opt.gap_deg, "degrees between neighbouring copies")
        ->check(navmap::cli::finiteIn(0.0, 10.0))
        ->capture_default_str();
    app.add_flag("--highways-only", opt.highways_only, "copy only highway=* ways and their nodes");
    app.add_option("--shift-lat", opt.shift_lat_deg, "degrees north the whole region is moved")
        ->check(navmap::cli::finiteIn(-80.0, 80.0))
        ->capture_default_str();
    app.add_option("--shift-lon", opt.shift_lon_deg, "degrees east the whole region is moved")
        ->check(navmap::cli::finiteIn(-170.0, 170.0))
        ->capture_default_str();
    app.add_option("--out-dir", out_dir, "folder for region.osm.pbf and the .hgt tiles (created)")->required();
    bool quiet = false;
    app.add_flag("-q,--quiet", quiet, "no progress output");
    if (const auto exit_status = navmap::cli::parse(app, argc, argv)) return *exit_status;
    opt.osm = osm;
    opt.dem = dem;
    opt.out_dir = out_dir;
    if (!quiet) opt.log = [](const std::string& line) { std::cerr << line << '\n'; };
    try {
        const auto region = navmap::map::tools::synthesizeRegion(opt);
        std::cout << "--osm " << region.osm.string();
        for (const auto& d : region.dems) std::cout << " --dem " << d.string();
        std::cout << '\n';
        return 0;
    } catch (const std::exception& e) {
        std::cerr << "navmap-synth-region: " << e.what() << '\n';
        return 1;
    }
}
