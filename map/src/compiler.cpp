// SPDX-License-Identifier: Apache-2.0
#include "navmap/map/compiler.h"

// GCC 12 reports a false -Wstringop-overread inside libosmium's area builder once it is
// inlined here (osmium/builder/osm_object_builder.hpp); the code reads a NUL-terminated tag.
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic ignored "-Wstringop-overread"
#endif

#include <GeographicLib/Geodesic.hpp>
#include <osmium/area/assembler.hpp>
#include <osmium/area/multipolygon_manager.hpp>
#include <osmium/handler/node_locations_for_ways.hpp>
#include <osmium/index/map/flex_mem.hpp>
#include <osmium/io/any_input.hpp>
#include <osmium/relations/relations_manager.hpp>
#include <osmium/tags/tags_filter.hpp>
#include <osmium/visitor.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iomanip>
#include <map>
#include <numbers>
#include <sstream>
#include <unordered_map>

#include <zlib.h>

#include "navmap/map/coastline.h"
#include "navmap/map/dem.h"
#include "navmap/map/dem_mosaic.h"
#include "navmap/map/geometry.h"
#include "navmap/map/ortho/ortho_preprocess.h"
#include "navmap/map/projection.h"
#include "navmap/map/road_graph.h"
#include "navmap/map/store_writer.h"
#include "navmap/map/tile_scheme.h"
#include "navmap/map/triangulator.h"
#include "osm_handlers.h"

namespace navmap::map {

using namespace detail;  // NOLINT: private implementation file

namespace {

using Clock = std::chrono::steady_clock;
constexpr double kAlways = 1e300;

// ---- level-of-detail rules (docs/tile-store.md "Tile scheme": lower levels carry simplified geometry) ----

/// Largest tile edge (m) at which a road class still appears; the leaf level has everything.
double roadMaxTile(RoadClass c) {
    switch (c) {
        case RoadClass::Motorway:
        case RoadClass::Trunk: return kAlways;
        case RoadClass::Primary: return 64000;
        case RoadClass::Secondary: return 32000;
        case RoadClass::Tertiary: return 16000;
        case RoadClass::Unclassified:
        case RoadClass::Residential: return 8000;
        case RoadClass::Service:
        case RoadClass::Pedestrian: return 4000;
        default: return 0;  // tracks and paths: leaf only
    }
}

double placeMaxTile(PlaceClass c) {
    switch (c) {
        case PlaceClass::Country:
        case PlaceClass::State:
        case PlaceClass::City: return kAlways;
        case PlaceClass::Town: return 64000;
        case PlaceClass::Village: return 16000;
        case PlaceClass::Suburb: return 8000;
        case PlaceClass::Hamlet:
        case PlaceClass::Neighbourhood:
        case PlaceClass::Island: return 4000;
        default: return 0;
    }
}

constexpr double kBuildingKeepArea = 1500.0;  // m^2: buildings kept one level above the leaf
/// Coastline ends this close are joined, and ends this close to the data's border are closed
/// along it (osmcoastline's default gap distance is of the same order).
constexpr double kCoastCloseM = 1000.0;

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

std::vector<PlanarPoint> project(const Projection& proj, const std::vector<LatLon>& pts) {
    std::vector<PlanarPoint> out;
    out.reserve(pts.size());
    for (const auto& p : pts) out.push_back(proj.forward(p.lat, p.lon));
    return out;
}

void orient(std::vector<PlanarPoint>& ring, bool ccw) {
    if ((ringSignedArea(ring) > 0) != ccw) std::reverse(ring.begin(), ring.end());
}

PPoly projectPolygon(const Projection& proj, const RawPolygon& raw) {
    PPoly p;
    p.id = raw.id;
    for (const auto& r : raw.outers) {
        auto ring = project(proj, r);
        if (ring.size() < 3) continue;
        orient(ring, true);
        p.area += std::abs(ringSignedArea(ring));
        p.outers.push_back(std::move(ring));
    }
    for (const auto& r : raw.inners) {
        auto ring = project(proj, r);
        if (ring.size() < 3) continue;
        orient(ring, false);
        p.area -= std::abs(ringSignedArea(ring));
        p.inners.push_back(std::move(ring));
    }
    std::vector<PlanarPoint> all;
    for (const auto& r : p.outers) all.insert(all.end(), r.begin(), r.end());
    p.bounds = boundsOf(all);
    p.barycenter = polygonBarycenter(p.outers, p.inners);
    return p;
}

LocalPoint toLocal(PlanarPoint p, const Tile& t) {
    return {static_cast<float>(p.x - t.origin_x), static_cast<float>(p.y - t.origin_y)};
}

/// Builds a tile Polygon from oriented rings; false when nothing triangulates.
bool makePolygon(const std::vector<std::vector<PlanarPoint>>& rings, const Tile& tile, Polygon& out) {
    std::vector<std::vector<PlanarPoint>> usable;
    for (const auto& r : rings) {
        if (r.size() >= 3) usable.push_back(r);
    }
    if (usable.empty()) return false;
    const Triangulation tri = triangulate(usable);
    if (!tri.ok || tri.indices.empty()) return false;
    out.vertices.reserve(tri.vertices.size());
    for (const auto& v : tri.vertices) out.vertices.push_back(toLocal(v, tile));
    std::uint32_t end = 0;
    for (const auto& r : usable) {
        end += static_cast<std::uint32_t>(r.size());
        out.ring_ends.push_back(end);
    }
    out.indices = tri.indices;
    return true;
}

std::string fmtSeconds(double s) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%6.2fs", s);
    return buf;
}

// ---- sharded compile: what every shard of one compile has in common ----

// Name, size and CRC32 of an input file.
std::string fileFingerprint(const std::filesystem::path& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw CompileError(path.string() + ": cannot read");
    uLong crc = ::crc32(0L, Z_NULL, 0);
    std::uint64_t size = 0;
    std::vector<char> buffer(std::size_t{1} << 20);
    while (in) {
        in.read(buffer.data(), static_cast<std::streamsize>(buffer.size()));
        const auto n = static_cast<std::size_t>(in.gcount());
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
    out << std::setprecision(17) << "osm " << fileFingerprint(opt.osm);
    for (const auto& dem : opt.dems) out << "; dem " << fileFingerprint(dem);
    out << "; leaf " << opt.leaf_tile_m << " m; dem samples " << opt.dem_samples << "; building "
        << opt.default_building_height_m << " m; ortho " << (opt.ortho_inputs ? "yes" : "no");
    return out.str();
}

// ---- road graph ----

RoadGraph buildGraph(const std::vector<RawGraphWay>& ways, const Projection& proj) {
    RoadGraph g;
    std::vector<std::int64_t> ids;
    for (const auto& w : ways) ids.insert(ids.end(), w.nodes.begin(), w.nodes.end());
    std::sort(ids.begin(), ids.end());
    std::vector<std::int64_t> junctions;
    for (std::size_t i = 0; i + 1 < ids.size(); ++i) {
        if (ids[i] == ids[i + 1] && (junctions.empty() || junctions.back() != ids[i])) junctions.push_back(ids[i]);
    }
    for (const auto& w : ways) {
        junctions.push_back(w.nodes.front());
        junctions.push_back(w.nodes.back());
    }
    std::sort(junctions.begin(), junctions.end());
    junctions.erase(std::unique(junctions.begin(), junctions.end()), junctions.end());
    ids.clear();
    ids.shrink_to_fit();
    auto node_index = [&](std::int64_t id) -> std::int64_t {
        const auto it = std::lower_bound(junctions.begin(), junctions.end(), id);
        return (it != junctions.end() && *it == id) ? it - junctions.begin() : -1;
    };
    g.nodes.resize(junctions.size());
    const GeographicLib::Geodesic& geod = GeographicLib::Geodesic::WGS84();
    for (const auto& w : ways) {
        std::size_t start = 0;
        std::uint32_t shape_begin = static_cast<std::uint32_t>(g.shape.size());
        double length = 0;
        auto push = [&](std::size_t i) {
            const PlanarPoint p = proj.forward(w.points[i].lat, w.points[i].lon);
            g.shape.push_back({static_cast<float>(p.x), static_cast<float>(p.y)});
            return p;
        };
        const PlanarPoint first = push(0);
        const auto n0 = node_index(w.nodes[0]);
        g.nodes[static_cast<std::size_t>(n0)] = {first.x, first.y, w.nodes[0]};
        for (std::size_t i = 1; i < w.nodes.size(); ++i) {
            double s12 = 0;
            geod.Inverse(w.points[i - 1].lat, w.points[i - 1].lon, w.points[i].lat, w.points[i].lon, s12);
            length += s12;
            const PlanarPoint p = push(i);
            const auto ni = node_index(w.nodes[i]);
            if (ni < 0) continue;
            g.nodes[static_cast<std::size_t>(ni)] = {p.x, p.y, w.nodes[i]};
            const auto from = static_cast<std::uint32_t>(node_index(w.nodes[start]));
            const auto to = static_cast<std::uint32_t>(ni);
            const auto shape_end = static_cast<std::uint32_t>(g.shape.size());
            GraphEdge e{from,      to,  static_cast<float>(length), w.speed_kmh, w.cls, w.flags, shape_begin,
                        shape_end, w.id};
            g.edges.push_back(e);
            if (!w.oneway) {
                std::swap(e.from, e.to);
                e.flags |= edge_flags::kReversed;
                g.edges.push_back(e);
            }
            // The next edge starts at this junction and shares its shape point.
            start = i;
            length = 0;
            shape_begin = shape_end - 1;
        }
    }
    std::stable_sort(g.edges.begin(), g.edges.end(),
                     [](const GraphEdge& a, const GraphEdge& b) { return a.from < b.from; });
    g.first_edge.assign(g.nodes.size() + 1, 0);
    for (const auto& e : g.edges) ++g.first_edge[e.from + 1];
    for (std::size_t i = 1; i < g.first_edge.size(); ++i) g.first_edge[i] += g.first_edge[i - 1];
    return g;
}

}  // namespace

CompileStats compileStore(const CompileOptions& opt) {
    const auto t0 = Clock::now();
    auto elapsed = [&] { return std::chrono::duration<double>(Clock::now() - t0).count(); };
    CompileStats stats;
    auto log = [&](const std::string& msg) {
        if (opt.log) opt.log("[" + fmtSeconds(elapsed()) + "] " + msg);
    };
    auto warn = [&](const std::string& msg) {
        stats.warnings.push_back(msg);
        log("warning: " + msg);
    };
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
    // The one writer of opt.out from here on: a second compile to the same store fails now, not
    // after reading its input (StoreError "<out> is being written by another process (pid N)").
    StoreLock lock(opt.out);
    const std::string fingerprint = opt.shard.sharded() ? compileFingerprint(opt) : std::string{};

    // ---- DEM ----
    DemMosaic dems;
    double dem_spacing_m = 90.0;
    for (const auto& path : opt.dems) {
        Dem dem = loadHgt(path);  // DemError names the file
        log("DEM " + path.filename().string() + ": " + std::to_string(dem.rows) + "x" + std::to_string(dem.cols) +
            ", " + std::to_string(dem.void_count) + " void samples");
        stats.dem_voids_filled += fillVoids(dem);
        dem_spacing_m = dem.spacing * 111320.0;
        dems.add(std::move(dem));
    }
    stats.dem_files = dems.size();
    if (dems.empty()) warn("no DEM given: terrain is flat (0 m)");

    // ---- OSM: one relations pass for multipolygons, then one pass of small handlers ----
    const std::string osm_name = opt.osm.string();
    {
        std::error_code ec;
        if (!std::filesystem::is_regular_file(opt.osm, ec)) throw CompileError(osm_name + ": no such file");
    }
    RoadHandler roads;
    GraphHandler graph_ways;
    BuildingHandler buildings(opt.default_building_height_m);
    AreaHandler areas;
    LabelHandler labels;
    CoastlineHandler coast;
    try {
        const osmium::io::File file(osm_name);
        osmium::TagsFilter filter{false};
        for (const char* key : {"building", "landuse", "natural", "leisure", "waterway", "amenity", "place"}) {
            filter.add_rule(true, osmium::TagMatcher{key});
        }
        osmium::area::Assembler::config_type cfg;
        osmium::area::MultipolygonManager<osmium::area::Assembler> mp{cfg, filter};
        log("reading relations of " + opt.osm.filename().string());
        osmium::relations::read_relations(file, mp);

        using Index = osmium::index::map::FlexMem<osmium::unsigned_object_id_type, osmium::Location>;
        Index index;
        osmium::handler::NodeLocationsForWays<Index> locations{index};
        locations.ignore_errors();  // ways crossing the extract border keep their inside parts
        auto mp_handler =
            mp.handler([&](osmium::memory::Buffer&& buffer) { osmium::apply(buffer, buildings, areas, labels); });
        osmium::io::Reader reader{file, osmium::io::read_meta::no};
        const std::size_t total = std::max<std::size_t>(reader.file_size(), 1);
        double last_log = elapsed();
        while (osmium::memory::Buffer buffer = reader.read()) {
            osmium::apply(buffer, locations, roads, graph_ways, labels, coast, mp_handler);
            if (elapsed() - last_log >= 1.0) {  // progress once a second on long runs
                last_log = elapsed();
                const double pct = 100.0 * static_cast<double>(reader.offset()) / static_cast<double>(total);
                log("reading " + std::to_string(static_cast<int>(std::min(pct, 100.0))) + "% of the file read ahead; " +
                    std::to_string(roads.roads.size()) + " roads, " + std::to_string(buildings.buildings.size()) +
                    " buildings so far");
            }
        }
        log("read " + std::to_string(roads.roads.size()) + " roads, " + std::to_string(buildings.buildings.size()) +
            " buildings, " + std::to_string(areas.areas.size()) + " areas, " + std::to_string(labels.points.size()) +
            " point labels");
        reader.close();
    } catch (const CompileError&) {
        throw;
    } catch (const std::exception& e) {
        throw CompileError(osm_name + ": cannot read OSM data: " + e.what());
    }
    stats.read_seconds = elapsed();
    if (roads.roads.empty() && buildings.buildings.empty() && areas.areas.empty() && labels.points.empty() &&
        coast.ways.empty()) {
        throw CompileError(osm_name + ": no map features (roads, buildings, areas, places, coastlines) found");
    }

    // ---- bounds and projection ----
    double south = 90, north = -90, west = 180, east = -180;
    auto grow = [&](const LatLon& p) {
        south = std::min(south, p.lat);
        north = std::max(north, p.lat);
        west = std::min(west, p.lon);
        east = std::max(east, p.lon);
    };
    for (const auto& r : roads.roads)
        for (const auto& p : r.points) grow(p);
    for (const auto& b : buildings.buildings)
        for (const auto& r : b.polygon.outers)
            for (const auto& p : r) grow(p);
    for (const auto& a : areas.areas)
        for (const auto& r : a.polygon.outers)
            for (const auto& p : r) grow(p);
    for (const auto& l : labels.points) grow(l.pos);
    for (const auto& w : coast.ways)
        for (const auto& p : w.points) grow(p);
    const Projection proj(0.5 * (south + north), 0.5 * (west + east));
    Box data_bounds;
    {
        const PlanarPoint corners[4] = {proj.forward(south, west), proj.forward(south, east), proj.forward(north, west),
                                        proj.forward(north, east)};
        data_bounds = boundsOf(corners);
    }
    const TileScheme scheme = TileScheme::covering(data_bounds, opt.leaf_tile_m);
    std::shared_ptr<const ortho::GlobalInputs> ortho_inputs;
    if (opt.ortho_inputs) {
        const double t_ortho = elapsed();
        try {
            ortho_inputs = opt.ortho_inputs({south, west, north, east});
        } catch (const std::exception& e) {
            throw CompileError(e.what());
        }
        stats.ortho_seconds += elapsed() - t_ortho;
        log("read the global orthoimage inputs");
    }
    log("projection origin " + std::to_string(proj.originLat()) + ", " + std::to_string(proj.originLon()) + "; " +
        std::to_string(scheme.levelCount()) + " levels, root " +
        std::to_string(static_cast<long>(scheme.rootSize() / 1000)) + " km");

    // ---- project features ----
    std::vector<PRoad> proads;
    proads.reserve(roads.roads.size());
    for (const auto& r : roads.roads) {
        PRoad p{&r, project(proj, r.points), {}};
        p.bounds = boundsOf(p.pts);
        proads.push_back(std::move(p));
        stats.road_vertices += r.points.size();
    }
    std::stable_sort(proads.begin(), proads.end(),
                     [](const PRoad& a, const PRoad& b) { return a.raw->cls < b.raw->cls; });
    stats.roads = proads.size();

    std::vector<PBuilding> pbuildings;
    for (const auto& b : buildings.buildings) {
        PBuilding pb;
        pb.poly = projectPolygon(proj, b.polygon);
        if (pb.poly.outers.empty()) continue;
        std::vector<std::vector<PlanarPoint>> rings = pb.poly.outers;
        rings.insert(rings.end(), pb.poly.inners.begin(), pb.poly.inners.end());
        pb.tri = triangulate(rings);
        if (!pb.tri.ok || pb.tri.indices.empty()) continue;
        std::uint32_t end = 0;
        for (const auto& r : rings) pb.ring_ends.push_back(end += static_cast<std::uint32_t>(r.size()));
        pb.height = b.height_m;
        pb.min_height = b.min_height_m;
        pbuildings.push_back(std::move(pb));
    }
    stats.buildings = pbuildings.size();

    std::vector<PArea> pareas;
    std::vector<PLabel> plabels;
    for (const auto& a : areas.areas) {
        PArea pa{projectPolygon(proj, a.polygon), a.cls, &a.name};
        if (pa.poly.outers.empty() || pa.poly.area <= 0) continue;
        if (!a.name.empty()) {
            const PlanarPoint c = pa.poly.barycenter;  // seed 4.4.2: area labels at the barycenter
            plabels.push_back({LabelKind::Area, static_cast<std::uint8_t>(a.cls), &a.name, c, c, c,
                               static_cast<float>(std::clamp(0.2 + 0.05 * std::log10(pa.poly.area + 1.0), 0.2, 0.5)),
                               a.polygon.id, 0, pa.poly.area});
            ++stats.area_labels;
        }
        pareas.push_back(std::move(pa));
    }

    // The sea, from the coastlines (coastline.h): one area of its own, odd winding with its islands.
    static const std::string kNoName;
    stats.coast_ways = coast.ways.size();
    if (!coast.ways.empty()) {
        std::vector<CoastWay> coast_ways;
        coast_ways.reserve(coast.ways.size());
        for (const auto& w : coast.ways)
            coast_ways.push_back({w.id, w.first_node, w.last_node, project(proj, w.points)});
        Coast sea = assembleCoast(std::move(coast_ways), data_bounds, kCoastCloseM);
        for (const auto& w : sea.warnings) warn(w);
        stats.sea_rings = sea.sea.size();
        stats.islands = sea.islands.size();
        stats.coast_gaps_closed = sea.gaps_closed;
        stats.coast_ways_left_out = sea.ways_left_out;
        if (!sea.empty()) {
            PArea pa{{}, AreaClass::Sea, &kNoName};
            for (auto& r : sea.sea) pa.poly.area += std::abs(ringSignedArea(r));
            for (auto& r : sea.islands) pa.poly.area -= std::abs(ringSignedArea(r));
            pa.poly.outers = std::move(sea.sea);
            pa.poly.inners = std::move(sea.islands);
            std::vector<PlanarPoint> all;
            for (const auto& r : pa.poly.outers) all.insert(all.end(), r.begin(), r.end());
            pa.poly.bounds = boundsOf(all);
            pa.poly.barycenter = {0.5 * (pa.poly.bounds.min_x + pa.poly.bounds.max_x),
                                  0.5 * (pa.poly.bounds.min_y + pa.poly.bounds.max_y)};
            pareas.push_back(std::move(pa));
        }
        log("coast: " + std::to_string(stats.coast_ways) + " coastline ways, " + std::to_string(stats.sea_rings) +
            " sea rings, " + std::to_string(stats.islands) + " islands");
    }
    stats.areas = pareas.size();

    for (const auto& l : labels.points) {
        const PlanarPoint p = proj.forward(l.pos.lat, l.pos.lon);
        const double max_tile = l.kind == LabelKind::Place
                                    ? placeMaxTile(static_cast<PlaceClass>(l.subclass))
                                    : (static_cast<PoiClass>(l.subclass) == PoiClass::Peak ? 16000.0 : 0.0);
        plabels.push_back({l.kind, l.subclass, &l.name, p, p, p, l.importance, l.id, max_tile, 0});
        (l.kind == LabelKind::Place ? stats.place_labels : stats.poi_labels)++;
    }
    for (const auto& l : labels.places) {
        const PPoly poly = projectPolygon(proj, l.polygon);
        if (poly.outers.empty()) continue;
        const PlanarPoint c = poly.barycenter;
        plabels.push_back({LabelKind::Place, l.subclass, &l.name, c, c, c, l.importance, l.polygon.id,
                           placeMaxTile(static_cast<PlaceClass>(l.subclass)), 0});
        ++stats.place_labels;
    }
    for (const auto& r : proads) {
        const std::string& name = r.raw->name.empty() ? r.raw->ref : r.raw->name;
        // Tunnels are not drawn on the surface (docs/rendering.md "Tunnels"), so not labelled there.
        if (name.empty() || (r.raw->flags & road_flags::kTunnel)) continue;
        // seed 4.4.2: polyline center for horizontal labels, longest straight segment for rotated ones.
        const Segment s = longestStraightSegment(r.pts);
        plabels.push_back({LabelKind::Road, static_cast<std::uint8_t>(r.raw->cls), &name, polylineCenter(r.pts), s.a,
                           s.b, 0.7f - 0.05f * static_cast<float>(r.raw->cls), r.raw->id, roadMaxTile(r.raw->cls), 0});
        ++stats.road_labels;
    }

    // ---- road graph ----
    // The road graph is the whole network's: shard 0 builds it, the other shards none.
    const bool with_graph = opt.shard.index == 0;
    const RoadGraph graph = with_graph ? buildGraph(graph_ways.ways, proj) : RoadGraph{};
    stats.graph_nodes = graph.nodes.size();
    stats.graph_edges = graph.edges.size();
    graph_ways.ways.clear();
    graph_ways.ways.shrink_to_fit();
    log("projected " + std::to_string(stats.road_vertices) + " road vertices; graph " +
        std::to_string(stats.graph_nodes) + " nodes, " + std::to_string(stats.graph_edges) + " edges");

    // ---- write the pyramid level by level ----
    StoreInfo info;
    info.origin_lat = proj.originLat();
    info.origin_lon = proj.originLon();
    info.scheme = scheme;
    info.dem_samples = static_cast<std::uint32_t>(opt.dem_samples);
    info.south = south;
    info.west = west;
    info.north = north;
    info.east = east;
    StoreWriter writer(std::move(lock), info);
    stats.tiles_per_level.assign(static_cast<std::size_t>(scheme.levelCount()), 0);
    const int leaf = scheme.leafLevel();
    std::size_t leaf_tiles_without_dem = 0;

    for (int level = 0; level <= leaf; ++level) {
        const double size = scheme.tileSize(level);
        const bool is_leaf = level == leaf;
        const double tol = is_leaf ? 0.0 : size / 1024.0;
        std::map<std::uint64_t, Tile> tiles;  // ordered: stable file layout
        // The tile columns this job builds (all of them unless it is one shard of several).
        const auto own = shardColumns(level, opt.shard);
        const auto owned = [&](std::uint32_t x) { return x >= own.first && x <= own.second; };
        // The sea's rings clipped to each tile: its DEM samples there are at sea level.
        std::unordered_map<std::uint64_t, std::vector<std::vector<PlanarPoint>>> sea_rings;
        auto tile_for = [&](TileId id) -> Tile& {
            auto [it, inserted] = tiles.try_emplace(id.key());
            if (inserted) {
                const Box b = scheme.bounds(id);
                it->second.id = id;
                it->second.origin_x = b.min_x;
                it->second.origin_y = b.min_y;
                it->second.size_m = size;
            }
            return it->second;
        };
        // Every tile over the data gets a DEM grid, so terrain is continuous at each level.
        const TileRange all = scheme.range(level, data_bounds);
        for (std::uint32_t y = all.y0; !all.empty && y <= all.y1; ++y) {
            for (std::uint32_t x = all.x0; x <= all.x1; ++x) {
                if (owned(x)) tile_for({static_cast<std::uint8_t>(level), x, y});
            }
        }

        for (const auto& r : proads) {
            if (!is_leaf && size > roadMaxTile(r.raw->cls)) continue;
            const std::vector<PlanarPoint> pts = is_leaf ? r.pts : simplifyPolyline(r.pts, tol);
            const TileRange range = scheme.range(level, r.bounds);
            for (std::uint32_t y = range.y0; !range.empty && y <= range.y1; ++y) {
                for (std::uint32_t x = range.x0; x <= range.x1; ++x) {
                    if (!owned(x)) continue;
                    const TileId id{static_cast<std::uint8_t>(level), x, y};
                    Tile& t = tile_for(id);
                    auto emit = [&](const std::vector<PlanarPoint>& piece) {
                        Road road;
                        road.points.reserve(piece.size());
                        for (const auto& p : piece) road.points.push_back(toLocal(p, t));
                        road.name = r.raw->name;
                        road.ref = r.raw->ref;
                        road.osm_id = r.raw->id;
                        road.cls = r.raw->cls;
                        road.flags = r.raw->flags;
                        road.layer = r.raw->layer;
                        road.maxspeed_kmh = r.raw->maxspeed;
                        t.roads.push_back(std::move(road));
                    };
                    if (range.x0 == range.x1 && range.y0 == range.y1) {
                        emit(pts);
                    } else {
                        for (const auto& piece : clipPolyline(pts, scheme.bounds(id))) emit(piece);
                    }
                }
            }
        }

        for (const auto& b : pbuildings) {
            if (!is_leaf && !(level == leaf - 1 && b.poly.area >= kBuildingKeepArea)) continue;
            const auto id = scheme.tileAt(level, b.poly.barycenter);
            if (!id || !owned(id->x)) continue;
            Tile& t = tile_for(*id);
            Building out;
            out.footprint.vertices.reserve(b.tri.vertices.size());
            for (const auto& v : b.tri.vertices) out.footprint.vertices.push_back(toLocal(v, t));
            out.footprint.ring_ends = b.ring_ends;
            out.footprint.indices = b.tri.indices;
            out.height_m = b.height;
            out.min_height_m = b.min_height;
            out.osm_id = b.poly.id;
            t.buildings.push_back(std::move(out));
        }

        for (const auto& a : pareas) {
            const double min_area = (size / 64.0) * (size / 64.0);
            if (!is_leaf && a.poly.area < min_area) continue;
            std::vector<std::vector<PlanarPoint>> rings;
            for (const auto& r : a.poly.outers) rings.push_back(is_leaf ? r : simplifyRing(r, tol));
            for (const auto& r : a.poly.inners) rings.push_back(is_leaf ? r : simplifyRing(r, tol));
            const TileRange range = scheme.range(level, a.poly.bounds);
            for (std::uint32_t y = range.y0; !range.empty && y <= range.y1; ++y) {
                for (std::uint32_t x = range.x0; x <= range.x1; ++x) {
                    if (!owned(x)) continue;
                    const TileId id{static_cast<std::uint8_t>(level), x, y};
                    const Box box = scheme.bounds(id);
                    std::vector<std::vector<PlanarPoint>> clipped;
                    const bool inside = box.contains({a.poly.bounds.min_x, a.poly.bounds.min_y}) &&
                                        box.contains({a.poly.bounds.max_x, a.poly.bounds.max_y});
                    for (const auto& r : rings) {
                        if (r.size() < 3) continue;
                        clipped.push_back(inside ? r : clipRing(r, box));
                    }
                    Area out;
                    Tile& t = tile_for(id);
                    if (!makePolygon(clipped, t, out.polygon)) continue;
                    if (a.cls == AreaClass::Sea) sea_rings[id.key()] = clipped;
                    out.cls = a.cls;
                    out.name = *a.name;
                    out.osm_id = a.poly.id;
                    t.areas.push_back(std::move(out));
                }
            }
        }

        for (const auto& l : plabels) {
            const bool show = is_leaf || size <= l.max_tile ||
                              (l.kind == LabelKind::Area && l.min_area >= (size / 16.0) * (size / 16.0));
            if (!show) continue;
            const auto id = scheme.tileAt(level, l.anchor);
            if (!id || !owned(id->x)) continue;
            Tile& t = tile_for(*id);
            Label out;
            out.kind = l.kind;
            out.subclass = l.subclass;
            out.name = *l.name;
            out.anchor = toLocal(l.anchor, t);
            out.segment_start = toLocal(l.s0, t);
            out.segment_end = toLocal(l.s1, t);
            out.importance = l.importance;
            out.osm_id = l.id;
            t.labels.push_back(std::move(out));
        }

        // DEM grid, low-pass filtered to the level's spacing (a DEM pyramid, seed 6.5). Sample
        // positions come from the tile corners, so shared borders get identical values.
        const int n = opt.dem_samples;
        const double spacing = n > 1 ? size / (n - 1) : 0;
        const int k = std::clamp(static_cast<int>(std::lround(spacing / dem_spacing_m)), 1, 4);
        const double dlat = spacing / 111320.0 / k;
        const double dlon = dlat / std::max(0.1, std::cos(proj.originLat() * std::numbers::pi / 180.0));
        for (auto& [key, t] : tiles) {
            if (n < 2) break;
            const Box b = scheme.bounds(t.id);
            double lat[4], lon[4];  // SW, SE, NW, NE
            proj.reverse({b.min_x, b.min_y}, lat[0], lon[0]);
            proj.reverse({b.max_x, b.min_y}, lat[1], lon[1]);
            proj.reverse({b.min_x, b.max_y}, lat[2], lon[2]);
            proj.reverse({b.max_x, b.max_y}, lat[3], lon[3]);
            t.dem.size = static_cast<std::uint16_t>(n);
            t.dem.spacing_m = static_cast<float>(spacing);
            t.dem.heights.assign(static_cast<std::size_t>(n) * n, 0.0f);
            std::size_t covered = 0;
            // SRTM is 0 or void over the sea (and void filling slopes it out from the shore): the
            // sea lies at 0 m, and counts as covered.
            std::vector<char> wet;
            if (const auto sea = sea_rings.find(key); sea != sea_rings.end())
                wet = samplesInside(sea->second, b.min_x, b.min_y, spacing, n);
            for (int r = 0; r < n; ++r) {
                const double v = static_cast<double>(r) / (n - 1);
                for (int c = 0; c < n; ++c) {
                    const double u = static_cast<double>(c) / (n - 1);
                    if (!wet.empty() && wet[static_cast<std::size_t>(r) * n + c]) {
                        ++covered;  // heights[] is 0 already
                        continue;
                    }
                    const double la =
                        (1 - u) * (1 - v) * lat[0] + u * (1 - v) * lat[1] + (1 - u) * v * lat[2] + u * v * lat[3];
                    const double lo =
                        (1 - u) * (1 - v) * lon[0] + u * (1 - v) * lon[1] + (1 - u) * v * lon[2] + u * v * lon[3];
                    double sum = 0;
                    int got = 0;
                    for (int i = 0; i < k; ++i) {
                        for (int j = 0; j < k; ++j) {
                            const auto h =
                                dems.sample(la + (i - 0.5 * (k - 1)) * dlat, lo + (j - 0.5 * (k - 1)) * dlon);
                            if (h) {
                                sum += *h;
                                ++got;
                            }
                        }
                    }
                    if (got > 0) {
                        t.dem.heights[static_cast<std::size_t>(r) * n + c] = static_cast<float>(sum / got);
                        ++covered;
                    }
                }
            }
            t.dem.coverage = static_cast<float>(covered) / static_cast<float>(n * n);
            if (is_leaf && covered < static_cast<std::size_t>(n) * n) ++leaf_tiles_without_dem;
        }

        if (ortho_inputs) {
            // seed 6.5: the global inputs and the tile's own areas and DEM onto its layers.
            const double t_ortho = elapsed();
            for (auto& [key, t] : tiles) {
                t.ortho = ortho::sampleOrthoLayers(t, *ortho_inputs, proj);
                ++stats.tiles_with_ortho;
            }
            stats.ortho_seconds += elapsed() - t_ortho;
        }
        for (auto& [key, t] : tiles) {
            std::stable_sort(t.roads.begin(), t.roads.end(),
                             [](const Road& a, const Road& b) { return a.cls < b.cls; });
            std::stable_sort(t.labels.begin(), t.labels.end(),
                             [](const Label& a, const Label& b) { return a.importance > b.importance; });
            writer.addTile(t);
        }
        stats.tiles_per_level[static_cast<std::size_t>(level)] = tiles.size();
        stats.tiles += tiles.size();
        log("level " + std::to_string(level) + " (" + std::to_string(static_cast<long>(size)) + " m tiles): " +
            std::to_string(tiles.size()) + " tiles, store " + std::to_string(writer.tileBytes() / 1024) + " KiB");
    }
    stats.tiles_without_dem = leaf_tiles_without_dem;
    if (leaf_tiles_without_dem > 0 && !dems.empty()) {
        warn(std::to_string(leaf_tiles_without_dem) + " of " + std::to_string(stats.tiles_per_level.back()) +
             " leaf tiles lie partly outside the DEM; missing areas are flat (0 m)");
    }
    if (with_graph) writer.setGraph(graph);
    stats.store_bytes = writer.finish();
    if (opt.shard.sharded()) {
        ShardManifest manifest;
        manifest.shard = opt.shard;
        manifest.tiles = stats.tiles;
        manifest.graph = with_graph;
        manifest.fingerprint = fingerprint;
        writeShardManifest(shardManifestPath(opt.out), manifest);
        log("wrote " + shardManifestPath(opt.out).string());
    }
    stats.total_seconds = elapsed();
    log("wrote " + opt.out.string());
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
      << "road graph: " << s.graph_nodes << " nodes, " << s.graph_edges << " directed edges\n"
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
