// SPDX-License-Identifier: Apache-2.0
#pragma once
// CPU-side preparation of one map tile for drawing: the terrain grid with skirts, land-cover
// triangles, roads draped onto the terrain (seed 3.6.1) as one instance per segment (seed 3.4),
// and extruded buildings. GL-free, so it can run off the render thread and be unit-tested.

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include <glm/glm.hpp>

#include "navmap/map/tile.h"
#include "navmap/render/map_frame.h"
#include "road_draping.h"

namespace navmap::render {

struct TerrainVertex {
    glm::vec3 position;  ///< tile-local metres (x east, y north, z height)
    glm::vec3 normal;
    /// Geomorphing (terrain_lod.h): heights of the coarser levels' surfaces at this x, y
    /// (parent first), which the vertex shader blends through as the camera moves away.
    std::array<float, kMorphLevels> ancestor_heights{};
    /// x, y of those surfaces' unit normals (z = sqrt(1 - x^2 - y^2): they point up).
    std::array<glm::vec2, kMorphLevels> ancestor_normals{};
};

/// One road segment, drawn as one quad with analytic caps (seed 3.4).
struct RoadInstance {
    glm::vec3 p0;  ///< tile-local, on the terrain surface
    glm::vec3 p1;
    float road_class;       ///< map::RoadClass value
    float flags = 0.0f;     ///< map::road_flags bits
    float measure0 = 0.0f;  ///< route only: distance along the route at p0, metres
    float measure1 = 0.0f;  ///< route only: distance along the route at p1
    /// How far the quad reaches beyond p0 and beyond p1, in half widths: 1 holds the whole
    /// rounded cap (seed 3.4); less where the end joins the next piece of its chain, whose quad
    /// covers the rest of the cap (buildTileMesh, kJointOverlap).
    glm::vec2 cap_reach{1.0f, 1.0f};
};

/// Overlap of two joined pieces' quads beyond the least the bend needs, in half widths: their
/// end edges are not one edge (the widths are scaled per piece), so they overlap by a margin
/// instead of abutting.
inline constexpr float kJointOverlap = 0.05f;

/// How far each of two joined pieces must reach beyond their joint, in half widths, so that with
/// the other's quad and body they cover the round join: sin of half the turn angle (the outer wedge
/// between the two bodies lies within that of one or the other), all of the cap where a piece has
/// no length in plan; plus kJointOverlap, at most 1. A piece shorter than its half width keeps
/// both whole caps when drawn (capReach()).
float jointCapReach(glm::vec2 from, glm::vec2 to);

struct LandCoverVertex {
    glm::vec2 position;  ///< tile-local metres
    glm::vec4 color;     ///< land-cover colour; alpha = how strongly it replaces the relief tint
    /// A tint (map::areaIsTint: a harbour): blended over the cover drawn before it instead of
    /// replacing it, so the water of a harbour basin stays water under it.
    bool tint = false;
};

struct BuildingVertex {
    glm::vec3 position;
    glm::vec3 normal;
    glm::vec3 color;
    float footprint_m;  ///< building size, for culling of far small buildings in the shader
};

/// A square part of a tile's terrain grid with its share of the skirts (TileMesh::terrain_blocks).
struct TerrainBlock {
    std::uint32_t first = 0;         ///< first index in terrain_indices
    std::uint32_t count = 0;         ///< indices
    glm::vec2 min{0.0f}, max{0.0f};  ///< tile-local x, y extent
    /// Heights its vertices can take: own and geomorph targets, skirts included (culling).
    float min_z = 0.0f, max_z = 0.0f;
};

/// Consecutive elements of a tile's list (road pieces of one group, a class or the bridges;
/// building indices) that lie in one block of the tile (by position; blocks as terrain_blocks),
/// so what lies outside the view can be left out per block.
struct BlockRun {
    std::uint32_t first = 0;  ///< first element of the list
    std::uint32_t count = 0;
    std::uint32_t block = 0;   ///< index into the list's block extents
    std::uint32_t lods = ~0u;  ///< road pieces: bit k set where the run is drawn at road level k
};

/// Road level of detail (the terrain's screen-space error rule applied to the road polylines):
/// level 0 is the draped road; level k is its pieces simplified (Douglas-Peucker in 3D, both
/// planar and height error) within kRoadLodTolerance[k] metres, per road and tile block, so that
/// a road's span in a block keeps its end points at every level and blocks drawn at different
/// levels still join. The renderer picks a level per block from its distance.
inline constexpr int kRoadLods = 4;
inline constexpr std::array<float, kRoadLods> kRoadLodTolerance{0.0f, 1.0f, 4.0f, 16.0f};

/// The coarsest road level whose tolerance, seen from `distance_m` away, stays within
/// `max_error_px` on screen; `focal_px` is the projection's pixels per unit of tan(angle)
/// (projection[1][1] * height / 2).
int roadLodLevel(float distance_m, float focal_px, float max_error_px);

/// Extent of a list's elements in one block (tile-local; min > max: none).
struct BlockExtent {
    glm::vec3 min{0.0f}, max{0.0f};
};

/// Blocks per tile side: the land cover morphs over several levels across a tile (terrain_lod.h),
/// and a quarter of a tile mostly needs only one or two of them.
inline constexpr int kTerrainBlocks = 4;

struct TileMesh {
    map::TileId id;
    glm::dvec3 origin{0.0};  ///< store-frame metres of the tile's south-west corner (z = 0)
    float size_m = 0.0f;
    int grid_size = 0;
    std::vector<TerrainVertex> terrain;          ///< grid (grid_size^2) then skirt vertices
    std::vector<std::uint32_t> terrain_indices;  ///< per block: its grid triangles, then its skirts
    std::vector<TerrainBlock> terrain_blocks;    ///< kTerrainBlocks^2, row-major from the south-west
    std::vector<float> heights;                  ///< grid_size^2, row 0 south (for draping queries)
    /// Per coarser level (parent first), grid_size^2: that level's surface at each grid vertex
    /// (the geomorph targets). The tile's triangles each lie inside one triangle of every coarser
    /// level, so a fully morphed tile lies on that level's surface.
    std::array<std::vector<float>, kMorphLevels> ancestor_heights;
    float min_height = 0.0f;
    float max_height = 0.0f;
    std::vector<LandCoverVertex> land_cover;  ///< triangles, drawn in order
    /// Road pieces of every level of detail (a piece is in the levels of its run's `lods`), least
    /// important first; bridges last.
    std::vector<RoadInstance> roads;
    /// roads in runs of one group, block (by the piece's midpoint; blocks as terrain_blocks) and
    /// set of levels, in the order of roads; and each block's extent.
    std::vector<BlockRun> road_runs;
    std::vector<BlockExtent> road_blocks;
    std::size_t source_road_vertices = 0;  ///< polyline vertices before draping
    std::vector<BuildingVertex> buildings;
    std::vector<std::uint32_t> building_indices;  ///< block by block (building_runs)
    /// building_indices per block (one run per block with buildings, by the footprint's centre),
    /// and each block's extent.
    std::vector<BlockRun> building_runs;
    std::vector<BlockExtent> building_blocks;

    [[nodiscard]] HeightGrid grid() const {
        return HeightGrid{grid_size, size_m / double(grid_size - 1), heights.data()};
    }
    /// The grid with the heights of ancestor level j + 1 (0: parent).
    [[nodiscard]] HeightGrid ancestorGrid(int j) const {
        return HeightGrid{grid_size, size_m / double(grid_size - 1),
                          ancestor_heights[static_cast<std::size_t>(j)].data()};
    }
    [[nodiscard]] std::array<HeightGrid, kMorphLevels> ancestorGrids() const {
        std::array<HeightGrid, kMorphLevels> g;
        for (int j = 0; j < kMorphLevels; ++j) g[static_cast<std::size_t>(j)] = ancestorGrid(j);
        return g;
    }
};

struct TileMeshOptions {
    float skirt_depth_m = 60.0f;  ///< skirts hide cracks between tiles of different levels
    bool drape_roads = true;      ///< seed 3.6.1 clipping; false keeps only the original vertices
    /// Draped pieces are merged while the merged piece stays this close to the surface
    /// (mergeDrapedPieces); 0 keeps every piece of the clipping.
    double road_merge_tolerance_m = 0.5;
};

/// Where a road is drawn among the others (docs/rendering.md "Tunnels and layers"), lowest
/// first: by OSM layer (-5..5), within a layer bridges after the roads on the ground, then the
/// less important classes before the more important ones, which overwrite them at junctions
/// (seed 3.6.3 "Intersections").
int roadDrawOrder(const map::Road& road);
/// A bridge deck's height above the straight line between its ends' terrain: 2 m, and 4 m more
/// for each layer above 1, so stacked bridges keep their order in depth too.
double bridgeDeckHeightM(int layer);

/// Land-cover colour of an area class (day palette; alpha = coverage strength).
glm::vec4 landCoverColor(map::AreaClass cls);

/// The tile's land-cover areas as coloured triangles (tile-local metres), in drawing order
/// (TileMesh::land_cover).
std::vector<LandCoverVertex> landCoverTriangles(const map::Tile& tile);

/// `ancestors` (up to kMorphLevels, parent first, entries may be null): the tiles whose DEMs are
/// the geomorph targets. A missing one is replaced by every 2^(j+1)-th sample of the tile's own grid.
TileMesh buildTileMesh(const map::Tile& tile, const TileMeshOptions& options = {},
                       std::span<const map::Tile* const> ancestors = {});

/// The samples around grid sample (r, c) that its central-difference normal takes, and the cells
/// between west and east and between south and north: 2 inside the grid, 1 at a border where the
/// difference is one-sided. At the border the sample beyond the edge comes from `dem`'s
/// `beyond` (map::TileDem::beyond, the tile across the edge; `dem` the grid's own, or null:
/// one-sided at every border).
struct NormalStencil {
    float west = 0.0f, east = 0.0f, south = 0.0f, north = 0.0f;
    int dx_cells = 0, dy_cells = 0;
};
NormalStencil normalStencil(const HeightGrid& grid, int r, int c, const map::TileDem* dem);

/// The surface of the ancestor `levels_up` levels above a tile (heights, normals) at the vertices
/// of the tile's grid, triangulated as that ancestor's mesh renders it (HeightGrid's split).
/// `heights`: the tile's grid_size^2 samples; `ancestor` may be null (see buildTileMesh).
void ancestorSurface(const map::Tile& tile, int grid_size, std::span<const float> heights, const map::Tile* ancestor,
                     int levels_up, std::vector<float>& out_heights, std::vector<glm::vec3>& out_normals);

/// One piece of the route draped onto one tile (seed 3.6.1): both ends lie on one triangle of the
/// tile's grid, so the straight piece lies on the surface; with the coarser levels' heights at its
/// ends the piece also follows the tile's geomorph (every level is linear on that triangle).
struct RoutePiece {
    glm::vec3 p0, p1;                                              ///< tile-local metres, on the tile's own surface
    std::array<float, kMorphLevels> ancestor_z0{}, ancestor_z1{};  ///< coarser levels' surfaces at p0, p1
    float measure0 = 0.0f, measure1 = 0.0f;                        ///< distance along the route, metres
    /// In one of RouteGeometry::tunnels_m (pieces are split where a tunnel begins or ends).
    bool tunnel = false;
};

/// The most route pieces one tile drapes, whatever the route: what the tile draws, morphs and
/// uploads of it per frame stays bounded by the tile, not by the route's point count.
inline constexpr std::size_t kRoutePiecesPerTile = 4096;
/// Cells per side of the coverage raster that leaves out, once a tile's route would exceed
/// RouteDrapeOptions::max_pieces, the segments that lie only where the route is drawn already;
/// halved while what is left still exceeds it, down to kRouteCoverageCellsCoarsest.
inline constexpr int kRouteCoverageCells = 128;
inline constexpr int kRouteCoverageCellsCoarsest = 16;

struct RouteDrapeOptions {
    /// Douglas-Peucker tolerance (metres) of the route's runs inside the tile, before draping: a
    /// view's pixel tolerance at the tile. 0 keeps every point.
    double tolerance_m = 0.0;
    /// At most this many pieces (kRoutePiecesPerTile): over it, segments whose coverage cells are
    /// all drawn already are left out (kRouteCoverageCells), then what still exceeds it.
    std::size_t max_pieces = kRoutePiecesPerTile;
};

/// What one drapeRoute() call did, counted (the route work of a tile; MapFrameStats route_*).
struct RouteDrapeCounts {
    std::size_t segments_clipped = 0;     ///< route segments overlapping the tile square
    std::size_t segments_draped = 0;      ///< of them, left after simplifying and coverage
    std::size_t segments_covered = 0;     ///< left out: drawn already by the tile's other segments
    std::size_t segments_over_limit = 0;  ///< left out: draping them would exceed max_pieces
    bool coverage_used = false;           ///< the route exceeded max_pieces before coverage
};

/// Clips the route (store frame; z is ignored) to the square of a tile (south-west corner
/// `origin`, edge grid.extent()), simplifies each run inside it to options.tolerance_m and drapes
/// it onto `grid` with barycentric tracing; `ancestors` (same layout as grid,
/// TileMesh::ancestorGrids) give ancestor_z. Measures are interpolated per draped vertex. Never
/// more than options.max_pieces pieces (RouteDrapeOptions); `counts` (may be null) says what was done.
std::vector<RoutePiece> drapeRoute(const RouteGeometry& route, const glm::dvec3& origin, const HeightGrid& grid,
                                   const std::array<HeightGrid, kMorphLevels>& ancestors,
                                   const RouteDrapeOptions& options = {}, RouteDrapeCounts* counts = nullptr);

/// Route instances of a tile with heights morphed like the terrain (terrain_lod.h morphedHeight);
/// eye_local: the camera's x, y relative to the tile origin.
void morphRoute(std::span<const RoutePiece> pieces, const TileMorph& morph, const glm::vec2& eye_local,
                std::vector<RoadInstance>& out);

}  // namespace navmap::render
