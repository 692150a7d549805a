// SPDX-License-Identifier: Apache-2.0
#pragma once
// The in-memory map tile the renderer consumes: roads, buildings, areas, labels and a DEM
// grid for one quadtree cell. GL-free and immutable once loaded (shared as
// std::shared_ptr<const Tile> between the loader thread and the render thread).
//
// Frames and units (see docs/tile-store.md):
// - The store has one planar frame: World Mercator metres (x east, y north) around the store
//   origin (navmap::map::Projection, world_tiles.h). Doubles.
// - A tile's geometry is float metres relative to the tile's own origin (origin_x, origin_y),
//   its south-west corner in the store frame, so values stay within [0, size_m] and keep
//   centimetre precision anywhere in the store. Renderers add (origin - camera origin) in
//   double and go to float only after that (camera-relative rendering).

#include <array>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "navmap/map/feature_classes.h"
#include "navmap/map/ortho/ortho_layers.h"
#include "navmap/map/road_class.h"

namespace navmap::map {

/// Quadtree address: level 0 is the root square; x grows east, y grows north, both in
/// [0, 2^level).
struct TileId {
    std::uint8_t level = 0;
    std::uint32_t x = 0;
    std::uint32_t y = 0;

    friend bool operator==(const TileId&, const TileId&) = default;
    [[nodiscard]] TileId parent() const {
        return level == 0 ? *this : TileId{static_cast<std::uint8_t>(level - 1), x / 2, y / 2};
    }
    [[nodiscard]] std::uint64_t key() const { return (std::uint64_t{level} << 56) | (std::uint64_t{x} << 28) | y; }
    [[nodiscard]] std::string toString() const;  ///< "level/x/y"
};

struct TileIdHash {
    std::size_t operator()(const TileId& id) const { return std::hash<std::uint64_t>{}(id.key()); }
};

/// A point in tile-local metres (east, north of Tile::origin_x/origin_y).
struct LocalPoint {
    float x = 0;
    float y = 0;
    friend bool operator==(const LocalPoint&, const LocalPoint&) = default;
};

/// A road polyline clipped to the tile. Stored with centimetre precision.
struct Road {
    std::vector<LocalPoint> points;  ///< at least 2; for one-way roads in the direction of travel
    std::string name;                ///< UTF-8, exactly as in OSM ("" if none)
    std::string ref;                 ///< e.g. "CG-3"
    std::int64_t osm_id = 0;         ///< way id
    RoadClass cls = RoadClass::Path;
    std::uint8_t flags = 0;          ///< road_flags bits
    std::int8_t layer = 0;           ///< OSM layer (-5..5), bridges/tunnels stack by it
    std::uint16_t maxspeed_kmh = 0;  ///< 0 when not tagged
};

/// A polygon (possibly with holes, possibly split by tile clipping) with its triangulation.
struct Polygon {
    /// Ring vertices (rings concatenated, open), then extra vertices from the triangulator.
    std::vector<LocalPoint> vertices;
    /// End (exclusive) of each ring in `vertices`; the first ring starts at 0. Outer rings are
    /// counter-clockwise, holes clockwise.
    std::vector<std::uint32_t> ring_ends;
    /// Triangles (three indices each, counter-clockwise seen from above) covering the polygon.
    std::vector<std::uint32_t> indices;
};

/// A building footprint, extruded from min_height_m to height_m above the terrain.
/// Whole building, not clipped: it belongs to the tile holding its barycenter, so it may
/// stick out of the tile square by up to its own size.
struct Building {
    Polygon footprint;
    float height_m = 0;
    float min_height_m = 0;
    std::int64_t osm_id = 0;  ///< way id, or relation id for multipolygons
};

/// A land-cover area clipped to the tile square.
struct Area {
    Polygon polygon;
    AreaClass cls = AreaClass::Other;
    std::string name;
    std::int64_t osm_id = 0;
};

enum class LabelKind : std::uint8_t { Place = 0, Poi, Road, Area };

/// A label feature with its anchors (seed 4.4.2). It lives in the tile holding `anchor`.
struct Label {
    LabelKind kind = LabelKind::Place;
    /// PlaceClass for places, PoiClass for POIs, RoadClass for roads, AreaClass for areas.
    std::uint8_t subclass = 0;
    std::string name;  ///< UTF-8, exact
    /// Point features: the feature position. Roads: the polyline center (horizontal labels).
    /// Areas: the barycenter.
    LocalPoint anchor;
    /// Roads only: the longest straight segment (rotated labels); equal to anchor otherwise.
    LocalPoint segment_start, segment_end;
    float importance = 0;  ///< [0, 1], higher is more important (label priority)
    std::int64_t osm_id = 0;
};

/// Heights on a regular grid spanning the tile square edge to edge, so neighbouring tiles of
/// one level share their border samples (crack-free). Row 0 is the south edge, column 0 the
/// west edge; sample (r, c) sits at local (c * spacing_m, r * spacing_m). Stored at 0.1 m.
struct TileDem {
    std::uint16_t size = 0;  ///< samples per side (0: tile has no DEM grid)
    float spacing_m = 0;
    std::vector<float> heights;  ///< size * size metres above sea level; 0 where no DEM
    float coverage = 0;          ///< fraction of samples that had DEM data (missing = flat 0 m)
    /// The samples one spacing beyond each edge (west, east, south, north: DemEdge), `size` each,
    /// along the edge from south to north or west to east: those of the tile of the same level
    /// across it (its column size - 2, column 1, row size - 2, row 1). Empty where the source has
    /// no such tile or it has no grid of this size. Not stored: the tile source fills them when it
    /// loads the tile (attachDemBorders), so that the normals at the border are central
    /// differences, the same in both tiles (docs/rendering.md "Terrain normals").
    std::array<std::vector<float>, 4> beyond;
    [[nodiscard]] float at(int row, int col) const { return heights[static_cast<std::size_t>(row) * size + col]; }
};

/// The edges of a tile's DEM grid, in the order of TileDem::beyond.
enum DemEdge : std::uint8_t { kDemWest = 0, kDemEast = 1, kDemSouth = 2, kDemNorth = 3 };

struct Tile {
    TileId id;
    double origin_x = 0;  ///< store-frame metres of the tile's south-west corner
    double origin_y = 0;
    double size_m = 0;        ///< edge length of the tile square
    std::vector<Road> roads;  ///< sorted by class, most important first (seed 3.6)
    std::vector<Building> buildings;
    std::vector<Area> areas;
    std::vector<Label> labels;  ///< sorted by importance, highest first
    TileDem dem;
    ortho::OrthoLayers ortho;  ///< synthetic orthoimage inputs (seed 6.5); empty without them

    /// Approximate heap + object bytes, used by the cache budget.
    [[nodiscard]] std::size_t byteSize() const;
};

/// Fills tile.dem.beyond from the tiles of the same level across its four edges, as `neighbour`
/// returns them (as stored, their own `beyond` unused; null: no tile there). What a tile source
/// does on load: the result depends on the source's data alone, never on what a cache holds.
void attachDemBorders(Tile& tile, const std::function<std::shared_ptr<const Tile>(TileId)>& neighbour);

}  // namespace navmap::map
