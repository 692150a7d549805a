#pragma once
// CPU-side preparation of one map tile for drawing: the terrain grid with skirts, land-cover
// triangles, roads draped onto the terrain (seed 3.6.1) as one instance per segment (seed 3.4),
// and extruded buildings. GL-free, so it can run off the render thread and be unit-tested.

#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "navmap/map/tile.h"
#include "navmap/render/road_draping.h"

namespace navmap::render {

struct TerrainVertex {
    glm::vec3 position;  ///< tile-local metres (x east, y north, z height)
    glm::vec3 normal;
};

/// One road segment, drawn as one quad with analytic caps (seed 3.4).
struct RoadInstance {
    glm::vec3 p0;      ///< tile-local, on the terrain surface
    glm::vec3 p1;
    float road_class;  ///< map::RoadClass value
    float flags;       ///< map::RoadFlags bits
    float measure0 = 0.0f;  ///< route only: distance along the route at p0, metres
    float measure1 = 0.0f;  ///< route only: distance along the route at p1
};

struct LandCoverVertex {
    glm::vec2 position;  ///< tile-local metres
    glm::vec4 color;     ///< land-cover colour; alpha = how strongly it replaces the relief tint
};

struct BuildingVertex {
    glm::vec3 position;
    glm::vec3 normal;
    glm::vec3 color;
    float footprint_m;  ///< building size, for culling of far small buildings in the shader
};

struct TileMesh {
    map::TileId id;
    glm::dvec3 origin{0.0};  ///< store-frame metres of the tile's south-west corner (z = 0)
    float size_m = 0.0f;
    int grid_size = 0;
    std::vector<TerrainVertex> terrain;         ///< grid (grid_size^2) then skirt vertices
    std::vector<std::uint32_t> terrain_indices;  ///< grid triangles then skirt triangles
    std::vector<float> heights;                  ///< grid_size^2, row 0 south (for draping queries)
    float min_height = 0.0f;
    float max_height = 0.0f;
    std::vector<LandCoverVertex> land_cover;     ///< triangles, drawn in order
    std::vector<RoadInstance> roads;             ///< least important first; bridges last
    std::size_t source_road_vertices = 0;        ///< polyline vertices before draping
    std::vector<BuildingVertex> buildings;
    std::vector<std::uint32_t> building_indices;

    [[nodiscard]] HeightGrid grid() const { return HeightGrid{grid_size, size_m / double(grid_size - 1), heights.data()}; }
};

struct TileMeshOptions {
    float skirt_depth_m = 60.0f;   ///< skirts hide cracks between tiles of different levels
    bool drape_roads = true;       ///< seed 3.6.1 clipping; false keeps only the original vertices
    /// Draped pieces are merged while the merged piece stays this close to the surface
    /// (mergeDrapedPieces); 0 keeps every piece of the clipping.
    double road_merge_tolerance_m = 0.5;
};

/// Land-cover colour of an area class (day palette; alpha = coverage strength).
glm::vec4 landCoverColor(map::AreaClass cls);

TileMesh buildTileMesh(const map::Tile& tile, const TileMeshOptions& options = {});

}  // namespace navmap::render
