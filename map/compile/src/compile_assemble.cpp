// SPDX-License-Identifier: Apache-2.0
// The frame and assemble stages of compileStore (compile_stages.h): the data's projection and
// tile scheme, the sea from the coastlines and the road graph from the graph ways.
#include <cmath>

#include "compile_stages.h"
#include "graph_build.h"
#include "navmap/map/compile/coastline.h"

namespace navmap::map::detail {

Frame frameOf(LatLonBounds bounds, const std::vector<RawCoastWay>& coast, double leaf_tile_m) {
    for (const auto& w : coast)
        for (const auto& p : w.points) bounds.grow(p);
    const double south = bounds.south, west = bounds.west, north = bounds.north, east = bounds.east;
    const Projection proj(0.5 * (south + north), 0.5 * (west + east));
    const Box data_bounds = dataBox(proj, south, west, north, east);
    const TileScheme scheme = TileScheme::forData(proj, south, west, north, east, leaf_tile_m);
    return Frame{bounds, proj, data_bounds, scheme, shardGridOf(scheme, data_bounds)};
}

StoreInfo storeInfoOf(const Frame& frame, int dem_samples) {
    StoreInfo info;
    info.origin_lat = frame.proj.originLat();
    info.origin_lon = frame.proj.originLon();
    info.scheme = frame.scheme;
    info.dem_samples = static_cast<std::uint32_t>(dem_samples);
    info.south = frame.bounds.south;
    info.west = frame.bounds.west;
    info.north = frame.bounds.north;
    info.east = frame.bounds.east;
    return info;
}

std::optional<PArea> assembleSea(std::vector<RawCoastWay> coast, const Frame& frame, CompileStats& stats,
                                 CompileLog& log) {
    static const std::string kNoName;
    stats.coast_ways = coast.size();
    if (coast.empty()) return std::nullopt;
    std::vector<CoastWay> coast_ways;
    coast_ways.reserve(coast.size());
    for (const auto& w : coast) coast_ways.push_back({w.id, w.first_node, w.last_node, project(frame.proj, w.points)});
    coast.clear();
    coast.shrink_to_fit();
    Coast assembled = assembleCoast(std::move(coast_ways), frame.data_bounds, kCoastCloseM);
    for (const auto& w : assembled.warnings) log.warn(w);
    stats.sea_rings = assembled.sea.size();
    stats.islands = assembled.islands.size();
    stats.coast_gaps_closed = assembled.gaps_closed;
    stats.coast_ways_left_out = assembled.ways_left_out;
    std::optional<PArea> sea;
    if (!assembled.empty()) {
        PArea pa{{}, AreaClass::Sea, &kNoName};
        for (auto& r : assembled.sea) pa.poly.area += std::abs(ringSignedArea(r));
        for (auto& r : assembled.islands) pa.poly.area -= std::abs(ringSignedArea(r));
        pa.poly.outers = std::move(assembled.sea);
        pa.poly.inners = std::move(assembled.islands);
        std::vector<PlanarPoint> pts;
        for (const auto& r : pa.poly.outers) pts.insert(pts.end(), r.begin(), r.end());
        pa.poly.bounds = boundsOf(pts);
        pa.poly.barycenter = {0.5 * (pa.poly.bounds.min_x + pa.poly.bounds.max_x),
                              0.5 * (pa.poly.bounds.min_y + pa.poly.bounds.max_y)};
        sea = std::move(pa);
        ++stats.areas;
    }
    log.log("coast: " + std::to_string(stats.coast_ways) + " coastline ways, " + std::to_string(stats.sea_rings) +
            " sea rings, " + std::to_string(stats.islands) + " islands");
    return sea;
}

RoadGraph assembleGraph(const std::vector<RawGraphWay>& ways, const Projection& proj) {
    return buildGraph(
        [&](const std::function<void(const RawGraphWay&)>& f) {
            for (const auto& w : ways) f(w);
        },
        proj);
}

}  // namespace navmap::map::detail
