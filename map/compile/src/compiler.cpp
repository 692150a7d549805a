// SPDX-License-Identifier: Apache-2.0
#include "navmap/map/compile/compiler.h"

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
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <iomanip>
#include <map>
#include <numbers>
#include <optional>
#include <span>
#include <sstream>
#include <unordered_map>

#include <unistd.h>
#include <zlib.h>
#ifdef __GLIBC__
#include <malloc.h>
#endif

#include "feature_spill.h"
#include "file_node_index.h"
#include "graph_build.h"
#include "multipolygon_spill.h"
#include "navmap/common/untrusted_file.h"
#include "navmap/map/compile/coastline.h"
#include "navmap/map/compile/dem_mosaic.h"
#include "navmap/map/compile/ortho/ortho_preprocess.h"
#include "navmap/map/compile/spill_file.h"
#include "navmap/map/compile/store_writer.h"
#include "navmap/map/compile/triangulator.h"
#include "navmap/map/dem.h"
#include "navmap/map/geometry.h"
#include "navmap/map/projection.h"
#include "navmap/map/road_graph.h"
#include "navmap/map/tile_codec.h"
#include "navmap/map/tile_scheme.h"
#include "osm_handlers.h"
#include "osm_limits.h"
#include "spill_dir.h"

namespace navmap::map {

using namespace detail;  // NOLINT: private implementation file

namespace {

using Clock = std::chrono::steady_clock;
constexpr double kAlways = 1e300;

// The OSM input: libosmium streams it (no size cap), but only from a regular file
// (docs/architecture.md "Untrusted files").
constexpr FileKind kOsmInput{"OSM input", 0};

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

std::vector<PlanarPoint> project(const Projection& proj, const std::vector<GeoCoordinate>& pts) {
    std::vector<PlanarPoint> out;
    out.reserve(pts.size());
    for (const auto& p : pts) out.push_back(proj.forward(p.lat_deg, p.lon_deg));
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

// ---- tiling: the features of the whole input, or of one band of tile columns ----

/// Bands first..last of `count` equal bands of the data's columns, together ({0, 0, 1}: all).
struct BandRange {
    int first = 0, last = 0, count = 1;
};

/// What every band of one compile shares.
struct TilingContext {
    const Projection& proj;
    const TileScheme& scheme;
    Box data_bounds;
    ShardGrid grid;  // the data's leaf columns, which shards and bands divide
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

bool counted(const std::vector<char>& flags, std::size_t i) { return flags.empty() || flags[i] != 0; }

/// Projects `raw`, derives its labels and builds the tiles of the context's columns, level by
/// level; adds the features it counts and the tiles it built to `stats`.
void tileFeatures(const RawFeatures& raw, const TilingContext& ctx, CompileStats& stats) {
    using ClockT = std::chrono::steady_clock;
    const Projection& proj = ctx.proj;
    const TileScheme& scheme = ctx.scheme;
    // ---- project features ----
    struct Counted {
        PRoad road;
        bool counted;
    };
    std::vector<Counted> croads;
    croads.reserve(raw.roads.size());
    for (std::size_t i = 0; i < raw.roads.size(); ++i) {
        const auto& r = raw.roads[i];
        PRoad p{&r, project(proj, r.points), {}};
        p.bounds = boundsOf(p.pts);
        const bool count = counted(raw.roads_counted, i);
        if (count) {
            stats.road_vertices += r.points.size();
            ++stats.roads;
        }
        croads.push_back({std::move(p), count});
    }
    std::stable_sort(croads.begin(), croads.end(),
                     [](const Counted& a, const Counted& b) { return a.road.raw->cls < b.road.raw->cls; });

    std::vector<PBuilding> pbuildings;
    for (std::size_t i = 0; i < raw.buildings.size(); ++i) {
        const auto& b = raw.buildings[i];
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
        if (counted(raw.buildings_counted, i)) ++stats.buildings;
    }

    std::vector<PArea> pareas;
    std::vector<PLabel> plabels;
    for (std::size_t i = 0; i < raw.areas.size(); ++i) {
        const auto& a = raw.areas[i];
        PArea pa{projectPolygon(proj, a.polygon), a.cls, &a.name};
        if (pa.poly.outers.empty() || pa.poly.area <= 0) continue;
        const bool count = counted(raw.areas_counted, i);
        if (!a.name.empty()) {
            const PlanarPoint ctr = pa.poly.barycenter;  // seed 4.4.2: area labels at the barycenter
            plabels.push_back({LabelKind::Area, static_cast<std::uint8_t>(a.cls), &a.name, ctr, ctr, ctr,
                               static_cast<float>(std::clamp(0.2 + 0.05 * std::log10(pa.poly.area + 1.0), 0.2, 0.5)),
                               a.polygon.id, 0, pa.poly.area});
            if (count) ++stats.area_labels;
        }
        pareas.push_back(std::move(pa));
        if (count) ++stats.areas;
    }
    // The sea (coastline.h) after the land areas, as one area of its own.
    std::vector<const PArea*> area_list;
    area_list.reserve(pareas.size() + 1);
    for (const auto& a : pareas) area_list.push_back(&a);
    if (ctx.sea) area_list.push_back(ctx.sea);

    for (std::size_t i = 0; i < raw.points.size(); ++i) {
        const auto& l = raw.points[i];
        const PlanarPoint p = proj.forward(l.pos.lat_deg, l.pos.lon_deg);
        const double max_tile = l.kind == LabelKind::Place
                                    ? placeMaxTile(static_cast<PlaceClass>(l.subclass))
                                    : (static_cast<PoiClass>(l.subclass) == PoiClass::Peak ? 16000.0 : 0.0);
        plabels.push_back({l.kind, l.subclass, &l.name, p, p, p, l.importance, l.id, max_tile, 0});
        if (counted(raw.points_counted, i)) (l.kind == LabelKind::Place ? stats.place_labels : stats.poi_labels)++;
    }
    for (std::size_t i = 0; i < raw.places.size(); ++i) {
        const auto& l = raw.places[i];
        const PPoly poly = projectPolygon(proj, l.polygon);
        if (poly.outers.empty()) continue;
        const PlanarPoint ctr = poly.barycenter;
        plabels.push_back({LabelKind::Place, l.subclass, &l.name, ctr, ctr, ctr, l.importance, l.polygon.id,
                           placeMaxTile(static_cast<PlaceClass>(l.subclass)), 0});
        if (counted(raw.places_counted, i)) ++stats.place_labels;
    }
    std::vector<PRoad> proads;
    proads.reserve(croads.size());
    for (auto& cr : croads) {
        const PRoad& r = cr.road;
        const std::string& name = r.raw->name.empty() ? r.raw->ref : r.raw->name;
        // Tunnels are not drawn on the surface (docs/rendering.md "Tunnels"), so not labelled there.
        if (!name.empty() && !(r.raw->flags & road_flags::kTunnel)) {
            // seed 4.4.2: polyline center for horizontal labels, longest straight segment for rotated ones.
            const Segment s = longestStraightSegment(r.pts);
            plabels.push_back({LabelKind::Road, static_cast<std::uint8_t>(r.raw->cls), &name, polylineCenter(r.pts),
                               s.a, s.b, 0.7f - 0.05f * static_cast<float>(r.raw->cls), r.raw->id,
                               roadMaxTile(r.raw->cls), 0});
            if (cr.counted) ++stats.road_labels;
        }
        proads.push_back(std::move(cr.road));
    }
    croads.clear();
    croads.shrink_to_fit();

    // ---- the pyramid level by level ----
    const int leaf = scheme.leafLevel();
    for (int level = 0; level <= leaf; ++level) {
        const double size = scheme.tileSize(level);
        const bool is_leaf = level == leaf;
        const double tol = is_leaf ? 0.0 : size / 1024.0;
        std::map<std::uint64_t, Tile> tiles;  // ordered: stable file layout
        // The tile columns this pass builds: the job's (all of them unless it is one shard of
        // several), and of those the band's.
        const auto job = shardColumns(level, ctx.shard, ctx.grid);
        const auto band = bandColumns(level, ctx.band.first, ctx.band.last, ctx.band.count, ctx.grid);
        const std::pair<std::uint32_t, std::uint32_t> own{std::max(job.first, band.first),
                                                          std::min(job.second, band.second)};
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
        const TileRange all = scheme.range(level, ctx.data_bounds);
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

        for (const PArea* area : area_list) {
            const PArea& a = *area;
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
        const int n = ctx.dem_samples;
        const double spacing = n > 1 ? size / (n - 1) : 0;
        const int k = std::clamp(static_cast<int>(std::lround(spacing / ctx.dem_spacing_m)), 1, 4);
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
                                ctx.dems.sample(la + (i - 0.5 * (k - 1)) * dlat, lo + (j - 0.5 * (k - 1)) * dlon);
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
            if (is_leaf && covered < static_cast<std::size_t>(n) * n) ++stats.tiles_without_dem;
        }

        if (ctx.ortho_inputs) {
            // seed 6.5: the global inputs and the tile's own areas and DEM onto its layers.
            const auto t_ortho = ClockT::now();
            for (auto& [key, t] : tiles) {
                t.ortho = ortho::sampleOrthoLayers(t, *ctx.ortho_inputs, proj);
                ++stats.tiles_with_ortho;
            }
            stats.ortho_seconds += std::chrono::duration<double>(ClockT::now() - t_ortho).count();
        }
        for (auto& [key, t] : tiles) {
            std::stable_sort(t.roads.begin(), t.roads.end(),
                             [](const Road& a, const Road& b) { return a.cls < b.cls; });
            std::stable_sort(t.labels.begin(), t.labels.end(),
                             [](const Label& a, const Label& b) { return a.importance > b.importance; });
            ctx.emit(t);
        }
        stats.tiles_per_level[static_cast<std::size_t>(level)] += tiles.size();
        stats.tiles += tiles.size();
        if (ctx.level_done) ctx.level_done(level, size, tiles.size());
    }
}

// ---- bounded memory: spilling and bands ----

/// Bytes of memory a band needs per byte of its spilled features: the raw features, their
/// projection, triangulations, simplified copies and the level's tiles (measured on 100 copies
/// of Andorra: about 5).
constexpr double kMemoryPerSpilledByte = 5.0;
/// The fine bands the bands are made of (at most one open spill file each while the features
/// are distributed).
constexpr int kMaxBands = 256;

/// Runs of the fine bands 0..N-1 (N = from.size()) whose features take at most `budget` spilled
/// bytes, from west to east, each as long as it fits (a fine band over the budget on its own
/// is a band of its own). from[k] / to[k]: bytes of the features whose ranges of fine bands
/// start / end at k (featureBands(); a feature with two ranges counts in each). The ranges
/// touching fine bands a..b are those starting at or before b less those ending before a.
std::vector<BandRange> bandsWithin(const std::vector<std::uint64_t>& from, const std::vector<std::uint64_t>& to,
                                   std::uint64_t budget) {
    const int n = static_cast<int>(from.size());
    std::vector<std::uint64_t> starting(from.size() + 1, 0), ended(from.size() + 1, 0);  // prefix sums
    for (std::size_t k = 0; k < from.size(); ++k) {
        starting[k + 1] = starting[k] + from[k];
        ended[k + 1] = ended[k] + to[k];
    }
    std::vector<BandRange> bands;
    for (int a = 0; a < n;) {
        int b = a;
        while (b + 1 < n && starting[static_cast<std::size_t>(b) + 2] - ended[static_cast<std::size_t>(a)] <= budget)
            ++b;
        bands.push_back({a, b, n});
        a = b + 1;
    }
    return bands;
}

/// The bands of tile columns that build a tile holding the feature `one` holds: at each level
/// where it appears (tileFeatures' level-of-detail rules), the bands of the columns its bounds
/// overlap (its label anchors lie inside them). Bounds grow by a metre for rounding. As ranges
/// of bands, one per level, sorted and merged where they overlap or touch: a feature in the
/// west shown on a coarse tile of the middle goes to the bands of the coarse tiles that hold it,
/// not to every band in between.
std::vector<std::pair<int, int>> featureBands(const RawFeatures& one, const Projection& proj, const TileScheme& scheme,
                                              const ShardGrid& grid, int bands) {
    const int leaf = scheme.leafLevel();
    std::vector<PlanarPoint> pts;
    auto add = [&](const std::vector<GeoCoordinate>& ll) {
        for (const auto& p : ll) pts.push_back(proj.forward(p.lat_deg, p.lon_deg));
    };
    std::function<bool(int level, double size)> shown;
    if (!one.roads.empty()) {
        const auto& r = one.roads.front();
        add(r.points);
        shown = [cls = r.cls](int, double size) { return size <= roadMaxTile(cls); };
    } else if (!one.buildings.empty()) {
        for (const auto& r : one.buildings.front().polygon.outers) add(r);
        shown = [leaf](int level, double) { return level == leaf - 1; };
    } else if (!one.areas.empty()) {
        const PPoly poly = projectPolygon(proj, one.areas.front().polygon);
        if (poly.outers.empty()) return {};
        pts = {{poly.bounds.min_x, poly.bounds.min_y}, {poly.bounds.max_x, poly.bounds.max_y}};
        shown = [area = poly.area](int, double size) { return area >= (size / 64.0) * (size / 64.0); };
    } else if (!one.places.empty()) {
        const auto& l = one.places.front();
        for (const auto& r : l.polygon.outers) add(r);
        shown = [max = placeMaxTile(static_cast<PlaceClass>(l.subclass))](int, double size) { return size <= max; };
    } else if (!one.points.empty()) {
        const auto& l = one.points.front();
        add({l.pos});
        const double max_tile = l.kind == LabelKind::Place
                                    ? placeMaxTile(static_cast<PlaceClass>(l.subclass))
                                    : (static_cast<PoiClass>(l.subclass) == PoiClass::Peak ? 16000.0 : 0.0);
        shown = [max_tile](int, double size) { return size <= max_tile; };
    }
    if (pts.empty()) return {};
    Box box = boundsOf(pts);
    box.min_x -= 1.0;
    box.min_y -= 1.0;
    box.max_x += 1.0;
    box.max_y += 1.0;
    std::vector<std::pair<int, int>> ranges;
    for (int level = 0; level <= leaf; ++level) {
        if (level != leaf && !shown(level, scheme.tileSize(level))) continue;
        const TileRange r = scheme.range(level, box);
        if (r.empty) continue;
        const auto l = static_cast<std::uint8_t>(level);
        ranges.emplace_back(tileShard({l, r.x0, 0}, bands, grid), tileShard({l, r.x1, 0}, bands, grid));
    }
    std::sort(ranges.begin(), ranges.end());
    std::vector<std::pair<int, int>> merged;
    for (const auto& r : ranges) {
        if (!merged.empty() && r.first <= merged.back().second + 1) {
            merged.back().second = std::max(merged.back().second, r.second);
        } else {
            merged.push_back(r);
        }
    }
    return merged;
}

void clearFeatures(RawFeatures& f) {
    f.roads.clear();
    f.buildings.clear();
    f.areas.clear();
    f.points.clear();
    f.places.clear();
    f.graph_ways.clear();
    f.roads_counted.clear();
    f.buildings_counted.clear();
    f.areas_counted.clear();
    f.points_counted.clear();
    f.places_counted.clear();
}

std::size_t featureCount(const RawFeatures& f) {
    return f.roads.size() + f.buildings.size() + f.areas.size() + f.points.size() + f.places.size();
}

/// Decodes a spill record of `reader` into `out`; throws SpillError naming the file.
void decodeRecord(const SpillReader& reader, std::span<const std::uint8_t> record, RawFeatures& out) {
    std::string error;
    if (!decodeFeature(record, out, error)) {
        throw SpillError(reader.path().string() + ": damaged feature record: " + error);
    }
}

std::string mib(std::uint64_t bytes) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.1f MiB", static_cast<double>(bytes) / 1048576.0);
    return buf;
}

/// osmium::relations::read_relations() with OsmLimits in front of the manager: a relation beyond
/// the member cap stops the compile, and the manager sees each member of a relation once.
template <typename Manager>
void readRelations(const osmium::io::File& file, Manager& manager, OsmLimits& limits) {
    osmium::io::Reader reader{file, osmium::osm_entity_bits::relation};
    while (osmium::memory::Buffer buffer = reader.read()) {
        for (const auto& relation : buffer.select<osmium::Relation>()) manager.relation(limits.uniqueMembers(relation));
    }
    reader.close();
    manager.prepare_for_lookup();
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
    // In memory every grid is loaded now; bounded, each is read when first sampled and dropped
    // again while a third of the limit is full (a band samples only the DEM under its columns).
    DemMosaic dems;
    double dem_spacing_m = 90.0;
    // DEM files whose every sample is a void: said as such, not as tiles outside the DEM.
    std::vector<std::filesystem::path> all_void_dems;
    auto all_void = [&](const std::filesystem::path& path, std::size_t samples) {
        all_void_dems.push_back(path);
        warn("DEM " + path.filename().string() + ": all " + std::to_string(samples) +
             " samples are voids: it gives no heights, its area is flat (0 m)");
    };
    for (const auto& path : opt.dems) {
        if (opt.memory_limit_mib > 0) {
            const HgtShape shape = probeHgt(path);  // DemError names the file
            log("DEM " + path.filename().string() + ": " + std::to_string(shape.side) + "x" +
                std::to_string(shape.side) + ", read when first needed");
            dem_spacing_m = shape.spacing * 111320.0;
            dems.addFile(path);
            continue;
        }
        Dem dem = loadHgt(path);  // DemError names the file
        log("DEM " + path.filename().string() + ": " + std::to_string(dem.rows) + "x" + std::to_string(dem.cols) +
            ", " + std::to_string(dem.void_count) + " void samples");
        if (dem.void_count == dem.heights.size()) all_void(path, dem.void_count);
        stats.dem_voids_filled += fillVoids(dem);
        dem_spacing_m = dem.spacing * 111320.0;
        dems.add(std::move(dem));
    }
    if (opt.memory_limit_mib > 0) dems.setBudget((opt.memory_limit_mib << 20) / 3);
    stats.dem_files = dems.size();
    if (dems.empty()) warn("no DEM given: terrain is flat (0 m)");

    // ---- OSM: one relations pass for multipolygons, then one pass of small handlers ----
    const std::string osm_name = opt.osm.string();
    {
        // A regular file, opened without blocking: /dev/zero or a FIFO is named as what it is.
        const UntrustedFile osm = UntrustedFile::open(opt.osm, kOsmInput);
        if (!osm.ok()) throw CompileError(osm.error());
    }
    // Bounded memory (docs/tile-store.md "Bounded memory"): the node index in a file and the
    // features in spill files, compiled band by band. Otherwise everything stays in memory.
    const bool bounded = opt.memory_limit_mib > 0;
    std::optional<SpillDir> spill;
    std::optional<SpillWriter> features_out, graph_out;
    if (bounded) {
        const std::filesystem::path parent =
            opt.spill_dir.empty() ? std::filesystem::absolute(opt.out).parent_path() : opt.spill_dir;
        spill.emplace(parent, opt.log);
        features_out.emplace(*spill / "features.spill", std::size_t{1} << 20);
        graph_out.emplace(*spill / "graph.spill", std::size_t{1} << 20);
        log("memory limit " + std::to_string(opt.memory_limit_mib) + " MiB: spilling to " + spill->path().string());
        dems.setScratchDir(spill->path());  // filled DEM grids dropped and needed again come back from there
    }
    // The road graph is the whole network's: shard 0 builds it, the other shards none.
    const bool with_graph = opt.shard.index == 0;
    RoadHandler roads;
    GraphHandler graph_ways;
    BuildingHandler buildings(opt.default_building_height_m);
    AreaHandler areas;
    LabelHandler labels;
    CoastlineHandler coast;
    RawFeatures all;  // in memory; empty when bounded
    std::size_t n_roads = 0, n_buildings = 0, n_areas = 0, n_points = 0, n_places = 0;
    double south = 90, north = -90, west = 180, east = -180;
    auto grow = [&](const GeoCoordinate& p) {
        south = std::min(south, p.lat_deg);
        north = std::max(north, p.lat_deg);
        west = std::min(west, p.lon_deg);
        east = std::max(east, p.lon_deg);
    };
    // What the handlers collected from the last buffer: into the bounds, then into memory or
    // the spill file, in input order per kind.
    auto take = [&](auto& from, auto& to, std::size_t& n, auto&& bounds) {
        for (auto& f : from) {
            bounds(f);
            if (bounded) {
                features_out->append(encodeFeature(f));
            } else {
                to.push_back(std::move(f));
            }
        }
        n += from.size();
        from.clear();
    };
    auto drain = [&] {
        take(roads.roads, all.roads, n_roads, [&](const RawRoad& r) {
            for (const auto& p : r.points) grow(p);
        });
        take(buildings.buildings, all.buildings, n_buildings, [&](const RawBuilding& b) {
            for (const auto& r : b.polygon.outers)
                for (const auto& p : r) grow(p);
        });
        take(areas.areas, all.areas, n_areas, [&](const RawArea& a) {
            for (const auto& r : a.polygon.outers)
                for (const auto& p : r) grow(p);
        });
        take(labels.points, all.points, n_points, [&](const RawPointLabel& l) { grow(l.pos); });
        take(labels.places, all.places, n_places, [](const RawAreaLabel&) {});
        if (!with_graph) {
            graph_ways.ways.clear();
        } else if (bounded) {
            for (const auto& w : graph_ways.ways) graph_out->append(encodeFeature(w));
            graph_ways.ways.clear();
        } else {
            for (auto& w : graph_ways.ways) all.graph_ways.push_back(std::move(w));
            graph_ways.ways.clear();
        }
    };
    try {
        const osmium::io::File file(osm_name);
        osmium::TagsFilter filter{false};
        for (const char* key : {"building", "landuse", "natural", "leisure", "waterway", "amenity", "place"}) {
            filter.add_rule(true, osmium::TagMatcher{key});
        }
        osmium::area::Assembler::config_type cfg;
        std::unique_ptr<NodeIndex> index;
        if (bounded) {
            index = std::make_unique<FileNodeIndex>(*spill / "nodes.index");
        } else {
            index = std::make_unique<osmium::index::map::FlexMem<osmium::unsigned_object_id_type, osmium::Location>>();
        }
        osmium::handler::NodeLocationsForWays<NodeIndex> locations{*index};
        OsmLimits limits{osm_name};  // first in each pass: nothing copies an object beyond the caps
        locations.ignore_errors();   // ways crossing the extract border keep their inside parts
        auto areas_out = [&](osmium::memory::Buffer&& buffer) { osmium::apply(buffer, buildings, areas, labels); };
        // The second pass, with the multipolygon manager's handler last.
        auto read_all = [&](auto& mp_handler) {
            osmium::io::Reader reader{file, osmium::io::read_meta::no};
            const std::size_t total = std::max<std::size_t>(reader.file_size(), 1);
            double last_log = elapsed();
            while (osmium::memory::Buffer buffer = reader.read()) {
                osmium::apply(buffer, limits, locations, roads, graph_ways, labels, coast, mp_handler);
                drain();
                if (elapsed() - last_log >= 1.0) {  // progress once a second on long runs
                    last_log = elapsed();
                    const double pct = 100.0 * static_cast<double>(reader.offset()) / static_cast<double>(total);
                    log("reading " + std::to_string(static_cast<int>(std::min(pct, 100.0))) +
                        "% of the file read ahead; " + std::to_string(n_roads) + " roads, " +
                        std::to_string(n_buildings) + " buildings so far");
                }
            }
            drain();
            log("read " + std::to_string(n_roads) + " roads, " + std::to_string(n_buildings) + " buildings, " +
                std::to_string(n_areas) + " areas, " + std::to_string(n_points) + " point labels");
            reader.close();
        };
        log("reading relations of " + opt.osm.filename().string());
        if (bounded) {
            // Member ways of multipolygon relations wait in a spill file, not in memory, until
            // their relation is complete (multipolygon_spill.h); the same areas in the same order.
            DiskMultipolygonManager mp{cfg, filter, *spill / "multipolygon-ways.spill"};
            readRelations(file, mp, limits);
            read_all(mp.handler(areas_out));
            log("multipolygons: " + std::to_string(mp.completeRelations()) + " relations complete, " +
                std::to_string(mp.memberWays()) + " member ways spilled");
        } else {
            osmium::area::MultipolygonManager<osmium::area::Assembler> mp{cfg, filter};
            readRelations(file, mp, limits);
            read_all(mp.handler(areas_out));
        }
        stats.repeated_members = limits.repeatedMembers();
        if (limits.relationsWithRepeats() > 0) {
            warn(std::to_string(limits.relationsWithRepeats()) +
                 " relation(s) listed members more than once (relation " +
                 std::to_string(limits.firstRelationWithRepeats()) +
                 " first): " + std::to_string(limits.repeatedMembers()) + " repeats left out");
        }
    } catch (const CompileError&) {
        throw;
    } catch (const std::exception& e) {
        throw CompileError(osm_name + ": cannot read OSM data: " + e.what());
    }
    if (bounded) {
        features_out->close();
        graph_out->close();
        std::error_code ec;
        std::filesystem::remove(*spill / "nodes.index", ec);  // no longer needed: free the disk
        std::filesystem::remove(*spill / "multipolygon-ways.spill", ec);
    }
    stats.read_seconds = elapsed();
    if (n_roads == 0 && n_buildings == 0 && n_areas == 0 && n_points == 0 && coast.ways.empty()) {
        throw CompileError(osm_name + ": no map features (roads, buildings, areas, places, coastlines) found");
    }

    // ---- bounds and projection ----
    for (const auto& w : coast.ways)
        for (const auto& p : w.points) grow(p);
    const Projection proj(0.5 * (south + north), 0.5 * (west + east));
    const Box data_bounds = dataBox(proj, south, west, north, east);
    const TileScheme scheme = TileScheme::forData(proj, south, west, north, east, opt.leaf_tile_m);
    const ShardGrid grid = shardGridOf(scheme, data_bounds);
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
    log("frame origin " + std::to_string(proj.originLat()) + ", " + std::to_string(proj.originLon()) + "; " +
        std::to_string(scheme.levelCount()) + " levels under world tile " + scheme.worldRoot().toString() + ", root " +
        std::to_string(static_cast<long>(scheme.rootSize() / 1000)) + " km, leaves " +
        std::to_string(static_cast<long>(std::lround(scheme.tileSize(scheme.leafLevel())))) + " m");

    // The sea, from the coastlines (coastline.h): one area of its own, odd winding with its islands.
    static const std::string kNoName;
    std::optional<PArea> sea;
    stats.coast_ways = coast.ways.size();
    if (!coast.ways.empty()) {
        std::vector<CoastWay> coast_ways;
        coast_ways.reserve(coast.ways.size());
        for (const auto& w : coast.ways)
            coast_ways.push_back({w.id, w.first_node, w.last_node, project(proj, w.points)});
        coast.ways.clear();
        coast.ways.shrink_to_fit();
        Coast assembled = assembleCoast(std::move(coast_ways), data_bounds, kCoastCloseM);
        for (const auto& w : assembled.warnings) warn(w);
        stats.sea_rings = assembled.sea.size();
        stats.islands = assembled.islands.size();
        stats.coast_gaps_closed = assembled.gaps_closed;
        stats.coast_ways_left_out = assembled.ways_left_out;
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
        log("coast: " + std::to_string(stats.coast_ways) + " coastline ways, " + std::to_string(stats.sea_rings) +
            " sea rings, " + std::to_string(stats.islands) + " islands");
    }

    StoreInfo info;
    info.origin_lat = proj.originLat();
    info.origin_lon = proj.originLon();
    info.scheme = scheme;
    info.dem_samples = static_cast<std::uint32_t>(opt.dem_samples);
    info.south = south;
    info.west = west;
    info.north = north;
    info.east = east;
    stats.tiles_per_level.assign(static_cast<std::size_t>(scheme.levelCount()), 0);
    TilingContext ctx{proj,
                      scheme,
                      data_bounds,
                      grid,
                      dems,
                      dem_spacing_m,
                      opt.dem_samples,
                      ortho_inputs.get(),
                      sea ? &*sea : nullptr,
                      opt.shard,
                      BandRange{},
                      {},
                      {}};
    auto log_graph = [&](const RoadGraph& graph) {
        stats.graph_nodes = graph.nodes.size();
        stats.graph_edges = graph.edges.size();
        log("road graph: " + std::to_string(stats.graph_nodes) + " nodes, " + std::to_string(stats.graph_edges) +
            " edges");
    };
    std::uint64_t store_bytes = 0;

    if (!bounded) {
        // ---- everything in memory: the pyramid level by level, straight into the store ----
        const RoadGraph graph = with_graph ? buildGraph(
                                                 [&](const std::function<void(const RawGraphWay&)>& f) {
                                                     for (const auto& w : all.graph_ways) f(w);
                                                 },
                                                 proj)
                                           : RoadGraph{};
        log_graph(graph);
        all.graph_ways.clear();
        all.graph_ways.shrink_to_fit();
        StoreWriter writer(std::move(lock), info);
        ctx.emit = [&](const Tile& t) { writer.addTile(t); };
        ctx.level_done = [&](int level, double size, std::size_t tiles) {
            log("level " + std::to_string(level) + " (" + std::to_string(static_cast<long>(size)) + " m tiles): " +
                std::to_string(tiles) + " tiles, store " + std::to_string(writer.tileBytes() / 1024) + " KiB");
        };
        tileFeatures(all, ctx, stats);
        if (with_graph) writer.setGraph(graph);
        store_bytes = writer.finish();
    } else {
        // ---- bounded: features into band files, bands compiled one at a time, tiles merged ----
        const std::uint64_t limit = opt.memory_limit_mib * std::uint64_t{1048576};
        // Bands are runs of kMaxBands equal column bands ("fine bands") whose features fit a
        // band's budget, half the limit (a third is the DEM's): measured first, from each
        // feature's ranges of fine bands. The ranges are kept, a record per feature in
        // feature-bands.spill, so that distributing the features needs no second decoding.
        const auto band_budget = static_cast<std::uint64_t>(static_cast<double>(limit) / 2.0 / kMemoryPerSpilledByte);
        static_assert(kMaxBands <= 256, "a fine band is one byte in feature-bands.spill");
        const std::vector<BandRange> bands = [&] {
            std::vector<std::uint64_t> from(kMaxBands, 0), to(kMaxBands, 0);  // bytes by first / last fine band
            SpillReader in(*spill / "features.spill");
            SpillWriter ranges_out(*spill / "feature-bands.spill", std::size_t{1} << 20);
            std::vector<std::uint8_t> record, ranges;
            RawFeatures one;
            while (in.next(record)) {
                clearFeatures(one);
                decodeRecord(in, record, one);
                ranges.clear();
                // A feature in two ranges of one band counts twice there: on the safe side.
                for (const auto& [lo, hi] : featureBands(one, proj, scheme, grid, kMaxBands)) {
                    from[static_cast<std::size_t>(lo)] += record.size();
                    to[static_cast<std::size_t>(hi)] += record.size();
                    ranges.push_back(static_cast<std::uint8_t>(lo));
                    ranges.push_back(static_cast<std::uint8_t>(hi));
                }
                ranges_out.append(ranges);
            }
            ranges_out.close();
            return bandsWithin(from, to, band_budget);
        }();
        const int n_bands = static_cast<int>(bands.size());
        log("spilled " + std::to_string(features_out->records()) + " features (" + mib(features_out->bytes()) +
            "), at most " + mib(band_budget) + " per band; " + std::to_string(n_bands) + " band(s)");
        // Bands that hold none of this job's columns get no features.
        std::vector<char> band_used(static_cast<std::size_t>(n_bands), 0);
        std::vector<int> band_of(kMaxBands, 0);  // fine band -> band
        for (int k = 0; k < n_bands; ++k) {
            const BandRange& b = bands[static_cast<std::size_t>(k)];
            for (int f = b.first; f <= b.last; ++f) band_of[static_cast<std::size_t>(f)] = k;
            for (int level = 0; level <= scheme.leafLevel(); ++level) {
                const auto job = shardColumns(level, opt.shard, grid);
                const auto cols = bandColumns(level, b.first, b.last, b.count, grid);
                if (std::max(job.first, cols.first) <= std::min(job.second, cols.second)) band_used[k] = 1;
            }
        }
        auto band_path = [&](int k) { return *spill / ("band-" + std::to_string(k) + ".spill"); };
        {
            std::vector<std::unique_ptr<SpillWriter>> band_out(static_cast<std::size_t>(n_bands));
            for (int k = 0; k < n_bands; ++k) {
                if (band_used[k]) band_out[k] = std::make_unique<SpillWriter>(band_path(k));
            }
            SpillReader in(*spill / "features.spill");
            SpillReader ranges_in(*spill / "feature-bands.spill");
            std::vector<std::uint8_t> record, ranges;
            std::vector<int> targets;  // the bands of one feature
            while (in.next(record)) {
                if (!ranges_in.next(ranges) || ranges.size() % 2 != 0) {
                    throw SpillError(ranges_in.path().string() +
                                     ": damaged: not one record of band ranges per feature of " + in.path().string());
                }
                targets.clear();
                for (std::size_t i = 0; i < ranges.size(); i += 2) {
                    for (int k = band_of[ranges[i]]; k <= band_of[ranges[i + 1]]; ++k) targets.push_back(k);
                }
                std::sort(targets.begin(), targets.end());
                targets.erase(std::unique(targets.begin(), targets.end()), targets.end());
                bool first = true;
                for (const int k : targets) {
                    if (!band_out[k]) continue;
                    // Counted in its first band only.
                    record[0] =
                        static_cast<std::uint8_t>(first ? (record[0] & ~kRepeatFlag) : (record[0] | kRepeatFlag));
                    band_out[k]->append(record);
                    first = false;
                }
            }
            for (auto& b : band_out) {
                if (b) b->close();
            }
        }
        features_out.reset();
        std::filesystem::remove(*spill / "features.spill");
        std::filesystem::remove(*spill / "feature-bands.spill");

        // Each band's tiles, encoded, in a file of its own; where each tile is.
        struct TileRef {
            std::uint64_t key;
            int band;
            std::uint64_t offset;
        };
        std::vector<TileRef> refs;
        std::vector<std::unique_ptr<SpillReader>> tile_in(static_cast<std::size_t>(n_bands));
        auto tiles_path = [&](int k) { return *spill / ("tiles-" + std::to_string(k) + ".spill"); };
        for (int k = 0; k < n_bands; ++k) {
            if (!band_used[k]) continue;
            RawFeatures band;
            std::uint64_t band_bytes = 0;
            {
                SpillReader in(band_path(k));
                band_bytes = in.size();
                std::vector<std::uint8_t> record;
                while (in.next(record)) decodeRecord(in, record, band);
            }
            std::filesystem::remove(band_path(k));
            SpillWriter tiles_out(tiles_path(k), std::size_t{1} << 20);
            ctx.band = bands[static_cast<std::size_t>(k)];
            std::vector<std::uint8_t> payload;
            std::size_t band_tiles = 0;
            ctx.emit = [&](const Tile& t) {
                payload.clear();
                for (int i = 0; i < 8; ++i) payload.push_back(static_cast<std::uint8_t>(t.id.key() >> (8 * i)));
                const auto encoded = encodeTile(t);
                payload.insert(payload.end(), encoded.begin(), encoded.end());
                refs.push_back({t.id.key(), k, tiles_out.append(payload)});
                ++band_tiles;
            };
            stats.features_per_band.push_back(featureCount(band));
            tileFeatures(band, ctx, stats);
            tiles_out.close();
            tile_in[k] = std::make_unique<SpillReader>(tiles_path(k));
            log("band " + std::to_string(k + 1) + "/" + std::to_string(n_bands) + ": " +
                std::to_string(featureCount(band)) + " features (" + mib(band_bytes) + "), " +
                std::to_string(band_tiles) + " tiles");
            band = RawFeatures{};
#ifdef __GLIBC__
            // The band's many small blocks are free now: hand them back, so that the next band
            // does not stack its memory on what the allocator keeps.
            ::malloc_trim(0);
#endif
        }

        // The DEM grids are done with: their memory goes before the road graph's comes.
        stats.dem_voids_filled += dems.voidsFilled();
        for (const auto& path : dems.allVoidFiles()) {
            const HgtShape shape = probeHgt(path);
            all_void(path, static_cast<std::size_t>(shape.side) * static_cast<std::size_t>(shape.side));
        }
        log("DEM: " + std::to_string(dems.fileLoads()) + " reads of " + std::to_string(dems.size()) + " files, " +
            std::to_string(dems.scratchReads()) + " grids read back filled, at most " + mib(dems.peakFileBytes()) +
            " held");
        dems = DemMosaic{};
        // The road graph on disk (graph_build.h): node ids sorted in runs of a quarter of the
        // limit, nodes, edges and shape in scratch files, encoded into the store at the end.
        std::optional<DiskGraph> graph;
        if (with_graph) {
            graph.emplace(
                [&](const std::function<void(const RawGraphWay&)>& f) {
                    SpillReader in(*spill / "graph.spill");
                    std::vector<std::uint8_t> record;
                    RawFeatures one;
                    while (in.next(record)) {
                        one.graph_ways.clear();
                        decodeRecord(in, record, one);
                        for (const auto& w : one.graph_ways) f(w);
                    }
                },
                proj, spill->path(), limit / 4);
            stats.graph_nodes = graph->nodes();
            stats.graph_edges = graph->edges();
            log("road graph: " + std::to_string(stats.graph_nodes) + " nodes, " + std::to_string(stats.graph_edges) +
                " edges (node ids sorted in " + std::to_string(graph->idRuns()) + " run(s), on disk until written)");
        } else {
            log_graph(RoadGraph{});
        }
        std::filesystem::remove(*spill / "graph.spill");

        // The single compile's order: level by level, by key within a level (TileId::key() sorts so).
        std::sort(refs.begin(), refs.end(), [](const TileRef& a, const TileRef& b) { return a.key < b.key; });
        StoreWriter writer(std::move(lock), info);
        std::vector<std::uint8_t> payload, tile_bytes;
        std::size_t level_tiles = 0;
        for (std::size_t i = 0; i < refs.size(); ++i) {
            const TileRef& r = refs[i];
            const TileId id{static_cast<std::uint8_t>(r.key >> 56),
                            static_cast<std::uint32_t>((r.key >> 28) & 0xFFFFFFF),
                            static_cast<std::uint32_t>(r.key & 0xFFFFFFF)};
            tile_in[r.band]->readAt(r.offset, payload);
            if (payload.size() < 8) throw SpillError(tile_in[r.band]->path().string() + ": damaged tile record");
            tile_bytes.assign(payload.begin() + 8, payload.end());
            writer.addRawTile(id, tile_bytes);
            ++level_tiles;
            if (i + 1 == refs.size() || (refs[i + 1].key >> 56) != (r.key >> 56)) {
                log("level " + std::to_string(id.level) + " (" +
                    std::to_string(static_cast<long>(scheme.tileSize(id.level))) +
                    " m tiles): " + std::to_string(level_tiles) + " tiles, store " +
                    std::to_string(writer.tileBytes() / 1024) + " KiB");
                level_tiles = 0;
            }
        }
        if (graph) writer.writeGraph([&](const StoreWriter::ByteSink& sink) { graph->encode(sink); });
        store_bytes = writer.finish();
    }

    if (stats.tiles_without_dem > 0 && stats.dem_files > 0) {
        const std::string tiles =
            std::to_string(stats.tiles_without_dem) + " of " + std::to_string(stats.tiles_per_level.back());
        std::string names;
        for (const auto& path : all_void_dems) names += (names.empty() ? "" : ", ") + path.filename().string();
        if (all_void_dems.size() == stats.dem_files) {
            warn(tiles + " leaf tiles have no heights: the DEM is all voids (" + names + "); terrain is flat (0 m)");
        } else if (!all_void_dems.empty()) {
            warn(tiles + " leaf tiles lie partly outside the DEM or on DEM files that are all voids (" + names +
                 "); missing areas are flat (0 m)");
        } else {
            warn(tiles + " leaf tiles lie partly outside the DEM; missing areas are flat (0 m)");
        }
    }
    stats.store_bytes = store_bytes;
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
