// SPDX-License-Identifier: Apache-2.0
#pragma once
// Synthetic large regions for scale tests (navmap-synth-region, map_bench's BM_CompileLarge):
// copies of a real extract laid side by side on a grid of offsets over a country-sized area,
// every object id remapped so that ids stay unique across copies, and SRTM tiles for the whole
// area made by repeating the source tile's heights with the same offsets.

#include <cstddef>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

namespace navmap::map::tools {

struct SynthRegionOptions {
    std::filesystem::path osm;                    ///< source extract (.osm.pbf)
    std::filesystem::path dem;                    ///< its SRTM tile (.hgt); empty: no DEM tiles are written
    std::filesystem::path out_dir;                ///< region.osm.pbf and the .hgt tiles go here (must exist)
    int copies = 1;                               ///< laid out row by row, ceil(sqrt(copies)) per row
    double gap_deg = 0.02;                        ///< between the copies' bounding boxes
    bool highways_only = false;                   ///< copy only highway=* ways and their nodes
    double shift_lat_deg = 0.0;                   ///< the whole region moved north by this much
    double shift_lon_deg = 0.0;                   ///< and east by this much
    std::function<void(const std::string&)> log;  ///< progress lines; may be null
};

struct SynthRegion {
    std::filesystem::path osm;                ///< out_dir/region.osm.pbf
    std::vector<std::filesystem::path> dems;  ///< out_dir/N..E...hgt covering the region
    std::size_t nodes = 0, ways = 0, relations = 0, way_nodes = 0;
    double south = 0, west = 0, north = 0, east = 0;  ///< of the region's nodes, degrees
    double step_lat = 0, step_lon = 0;                ///< offset between neighbouring copies
};

/// Writes the region; throws std::runtime_error naming the file on a read or write failure.
SynthRegion synthesizeRegion(const SynthRegionOptions& options);

}  // namespace navmap::map::tools
