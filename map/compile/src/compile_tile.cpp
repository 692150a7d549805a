// SPDX-License-Identifier: Apache-2.0
// The tile stage of compileStore (compile_stages.h): projected features into the tiles of the
// quadtree pyramid, level by level, with each tile's DEM grid and ortho layers.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <numbers>

#include "compile_stages.h"
#include "navmap/map/compile/coastline.h"
#include "navmap/map/compile/ortho/ortho_preprocess.h"

namespace navmap::map::detail {

namespace {

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

Road tileRoad(const std::vector<PlanarPoint>& piece, const RawRoad& raw, const Tile& t) {
    Road road;
    road.points.reserve(piece.size());
    for (const auto& p : piece) road.points.push_back(toLocal(p, t));
    road.name = raw.name;
    road.ref = raw.ref;
    road.osm_id = raw.id;
    road.cls = raw.cls;
    road.flags = raw.flags;
    road.layer = raw.layer;
    road.maxspeed_kmh = raw.maxspeed;
    return road;
}

/// The roads shown at the level, simplified above the leaf level and clipped to each tile.
void addRoads(const std::vector<PRoad>& roads, const TileScheme& scheme, LevelTiles& lt) {
    const auto level = static_cast<std::uint8_t>(lt.level());
    for (const auto& r : roads) {
        if (!lt.isLeaf() && lt.size() > roadMaxTile(r.raw->cls)) continue;
        const std::vector<PlanarPoint> pts = lt.isLeaf() ? r.pts : simplifyPolyline(r.pts, lt.tolerance());
        const TileRange range = scheme.range(level, r.bounds);
        for (std::uint32_t y = range.y0; !range.empty && y <= range.y1; ++y) {
            for (std::uint32_t x = range.x0; x <= range.x1; ++x) {
                if (!lt.owned(x)) continue;
                const TileId id{level, x, y};
                Tile& t = lt.at(id);
                if (range.x0 == range.x1 && range.y0 == range.y1) {
                    t.roads.push_back(tileRoad(pts, *r.raw, t));
                } else {
                    for (const auto& piece : clipPolyline(pts, scheme.bounds(id)))
                        t.roads.push_back(tileRoad(piece, *r.raw, t));
                }
            }
        }
    }
}

/// Buildings at the leaf level, and the large ones one level above, in the tile of their barycenter.
void addBuildings(const std::vector<PBuilding>& buildings, const TileScheme& scheme, LevelTiles& lt) {
    const int leaf = scheme.leafLevel();
    for (const auto& b : buildings) {
        if (!lt.isLeaf() && !(lt.level() == leaf - 1 && b.poly.area >= kBuildingKeepArea)) continue;
        const auto id = scheme.tileAt(lt.level(), b.poly.barycenter);
        if (!id || !lt.owned(id->x)) continue;
        Tile& t = lt.at(*id);
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
}

/// One area in the tiles it overlaps, clipped and triangulated per tile.
void addArea(const PArea& a, const TileScheme& scheme, LevelTiles& lt) {
    const double min_area = (lt.size() / 64.0) * (lt.size() / 64.0);
    if (!lt.isLeaf() && a.poly.area < min_area) return;
    std::vector<std::vector<PlanarPoint>> rings;
    for (const auto& r : a.poly.outers) rings.push_back(lt.isLeaf() ? r : simplifyRing(r, lt.tolerance()));
    for (const auto& r : a.poly.inners) rings.push_back(lt.isLeaf() ? r : simplifyRing(r, lt.tolerance()));
    const TileRange range = scheme.range(lt.level(), a.poly.bounds);
    for (std::uint32_t y = range.y0; !range.empty && y <= range.y1; ++y) {
        for (std::uint32_t x = range.x0; x <= range.x1; ++x) {
            if (!lt.owned(x)) continue;
            const TileId id{static_cast<std::uint8_t>(lt.level()), x, y};
            const Box box = scheme.bounds(id);
            std::vector<std::vector<PlanarPoint>> clipped;
            const bool inside = box.contains({a.poly.bounds.min_x, a.poly.bounds.min_y}) &&
                                box.contains({a.poly.bounds.max_x, a.poly.bounds.max_y});
            for (const auto& r : rings) {
                if (r.size() < 3) continue;
                clipped.push_back(inside ? r : clipRing(r, box));
            }
            Area out;
            Tile& t = lt.at(id);
            if (!makePolygon(clipped, t, out.polygon)) continue;
            if (a.cls == AreaClass::Sea) lt.sea_rings[id.key()] = clipped;
            out.cls = a.cls;
            out.name = *a.name;
            out.osm_id = a.poly.id;
            t.areas.push_back(std::move(out));
        }
    }
}

void addLabels(const std::vector<PLabel>& labels, const TileScheme& scheme, LevelTiles& lt) {
    const double size = lt.size();
    for (const auto& l : labels) {
        const bool show = lt.isLeaf() || size <= l.max_tile ||
                          (l.kind == LabelKind::Area && l.min_area >= (size / 16.0) * (size / 16.0));
        if (!show) continue;
        const auto id = scheme.tileAt(lt.level(), l.anchor);
        if (!id || !lt.owned(id->x)) continue;
        Tile& t = lt.at(*id);
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
}

/// How one level samples the DEM: n x n samples `spacing` apart, each the mean of k x k DEM
/// samples dlat x dlon apart.
struct DemSampling {
    int n;
    double spacing;
    int k;
    double dlat, dlon;
};

/// The tile's DEM grid; returns how many samples are covered (by the DEM or the sea).
std::size_t sampleTileDem(Tile& t, const std::vector<char>& wet, const DemSampling& s, const TilingContext& ctx) {
    const int n = s.n;
    const Box b = ctx.scheme.bounds(t.id);
    double lat[4], lon[4];  // SW, SE, NW, NE
    ctx.proj.reverse({b.min_x, b.min_y}, lat[0], lon[0]);
    ctx.proj.reverse({b.max_x, b.min_y}, lat[1], lon[1]);
    ctx.proj.reverse({b.min_x, b.max_y}, lat[2], lon[2]);
    ctx.proj.reverse({b.max_x, b.max_y}, lat[3], lon[3]);
    t.dem.size = static_cast<std::uint16_t>(n);
    t.dem.spacing_m = static_cast<float>(s.spacing);
    t.dem.heights.assign(static_cast<std::size_t>(n) * n, 0.0f);
    std::size_t covered = 0;
    for (int r = 0; r < n; ++r) {
        const double v = static_cast<double>(r) / (n - 1);
        for (int c = 0; c < n; ++c) {
            const double u = static_cast<double>(c) / (n - 1);
            if (!wet.empty() && wet[static_cast<std::size_t>(r) * n + c]) {
                ++covered;  // heights[] is 0 already
                continue;
            }
            const double la = (1 - u) * (1 - v) * lat[0] + u * (1 - v) * lat[1] + (1 - u) * v * lat[2] + u * v * lat[3];
            const double lo = (1 - u) * (1 - v) * lon[0] + u * (1 - v) * lon[1] + (1 - u) * v * lon[2] + u * v * lon[3];
            double sum = 0;
            int got = 0;
            for (int i = 0; i < s.k; ++i) {
                for (int j = 0; j < s.k; ++j) {
                    const auto h =
                        ctx.dems.sample(la + (i - 0.5 * (s.k - 1)) * s.dlat, lo + (j - 0.5 * (s.k - 1)) * s.dlon);
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
    return covered;
}

/// DEM grids, low-pass filtered to the level's spacing (a DEM pyramid, seed 6.5). Sample
/// positions come from the tile corners, so shared borders get identical values.
void sampleDem(LevelTiles& lt, const TilingContext& ctx, CompileStats& stats) {
    const int n = ctx.dem_samples;
    if (n < 2) return;
    const double spacing = n > 1 ? lt.size() / (n - 1) : 0;
    const int k = std::clamp(static_cast<int>(std::lround(spacing / ctx.dem_spacing_m)), 1, 4);
    const double dlat = spacing / 111320.0 / k;
    const double dlon = dlat / std::max(0.1, std::cos(ctx.proj.originLat() * std::numbers::pi / 180.0));
    const DemSampling sampling{n, spacing, k, dlat, dlon};
    for (auto& [key, t] : lt.tiles) {
        // SRTM is 0 or void over the sea (and void filling slopes it out from the shore): the
        // sea lies at 0 m, and counts as covered.
        std::vector<char> wet;
        if (const auto sea = lt.sea_rings.find(key); sea != lt.sea_rings.end()) {
            const Box b = ctx.scheme.bounds(t.id);
            wet = samplesInside(sea->second, b.min_x, b.min_y, spacing, n);
        }
        const std::size_t covered = sampleTileDem(t, wet, sampling, ctx);
        t.dem.coverage = static_cast<float>(covered) / static_cast<float>(n * n);
        if (lt.isLeaf() && covered < static_cast<std::size_t>(n) * n) ++stats.tiles_without_dem;
    }
}

}  // namespace

LevelTiles::LevelTiles(const TilingContext& ctx, int level)
    : m_scheme(ctx.scheme),
      m_level(level),
      m_size(ctx.scheme.tileSize(level)),
      m_leaf(level == ctx.scheme.leafLevel()) {
    // The tile columns this pass builds: the job's (all of them unless it is one shard of
    // several), and of those the band's.
    const auto job = shardColumns(level, ctx.shard, ctx.grid);
    const auto band = bandColumns(level, ctx.band.first, ctx.band.last, ctx.band.count, ctx.grid);
    m_own = {std::max(job.first, band.first), std::min(job.second, band.second)};
}

Tile& LevelTiles::at(TileId id) {
    auto [it, inserted] = tiles.try_emplace(id.key());
    if (inserted) {
        const Box b = m_scheme.bounds(id);
        it->second.id = id;
        it->second.origin_x = b.min_x;
        it->second.origin_y = b.min_y;
        it->second.size_m = m_size;
    }
    return it->second;
}

LevelTiles tileLevel(const ProjectedFeatures& features, const TilingContext& ctx, int level, CompileStats& stats) {
    const TileScheme& scheme = ctx.scheme;
    LevelTiles lt(ctx, level);
    // Every tile over the data gets a DEM grid, so terrain is continuous at each level.
    const TileRange all = scheme.range(level, ctx.data_bounds);
    for (std::uint32_t y = all.y0; !all.empty && y <= all.y1; ++y) {
        for (std::uint32_t x = all.x0; x <= all.x1; ++x) {
            if (lt.owned(x)) lt.at({static_cast<std::uint8_t>(level), x, y});
        }
    }
    addRoads(features.roads, scheme, lt);
    addBuildings(features.buildings, scheme, lt);
    // The sea (coastline.h) after the land areas, as one area of its own.
    for (const PArea& a : features.areas) addArea(a, scheme, lt);
    if (features.sea) addArea(*features.sea, scheme, lt);
    addLabels(features.labels, scheme, lt);
    sampleDem(lt, ctx, stats);
    if (ctx.ortho_inputs) {
        // seed 6.5: the global inputs and the tile's own areas and DEM onto its layers.
        const auto t_ortho = std::chrono::steady_clock::now();
        for (auto& [key, t] : lt.tiles) {
            t.ortho = ortho::sampleOrthoLayers(t, *ctx.ortho_inputs, ctx.proj);
            ++stats.tiles_with_ortho;
        }
        stats.ortho_seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - t_ortho).count();
    }
    for (auto& [key, t] : lt.tiles) {
        std::stable_sort(t.roads.begin(), t.roads.end(), [](const Road& a, const Road& b) { return a.cls < b.cls; });
        std::stable_sort(t.labels.begin(), t.labels.end(),
                         [](const Label& a, const Label& b) { return a.importance > b.importance; });
    }
    return lt;
}

void tileFeatures(const RawFeatures& raw, const TilingContext& ctx, CompileStats& stats) {
    const ProjectedFeatures features = projectFeatures(raw, ctx.proj, ctx.sea, stats);
    for (int level = 0; level <= ctx.scheme.leafLevel(); ++level) {
        const LevelTiles lt = tileLevel(features, ctx, level, stats);
        for (const auto& [key, t] : lt.tiles) ctx.emit(t);
        stats.tiles_per_level[static_cast<std::size_t>(level)] += lt.tiles.size();
        stats.tiles += lt.tiles.size();
        if (ctx.level_done) ctx.level_done(level, lt.size(), lt.tiles.size());
    }
}

}  // namespace navmap::map::detail
