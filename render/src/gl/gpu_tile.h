// SPDX-License-Identifier: Apache-2.0
#pragma once
// One tile's GPU resources as GpuTileCache uploaded them (terrain with skirts, land-cover
// textures, road quads, buildings) and the per-frame state the passes keep on it (camera, culled
// road range, draped route). Owned by GpuTileCache; the passes read it and write only their own
// per-frame fields. Private to render/.

#include <GLES3/gl3.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <memory>
#include <span>
#include <utility>
#include <vector>

#include <glm/glm.hpp>

#include "navmap/map/tile.h"
#include "navmap/render/map_frame.h"
#include "navmap/render/road_style.h"
#include "navmap/render/terrain_lod.h"
#include "ortho_generator.h"
#include "road_draping.h"
#include "terrain_horizon.h"
#include "tile_mesh.h"
#include "vertex_layout.h"

namespace navmap::render::gl {

/// Whether resources made from the tile object `made_from` (kept as a pointer and a weak
/// reference) belong to `tile`: the same object, still alive. Another object allocated where a
/// freed one was (a reload, or the tile re-expressed into a re-centred frame) is not the same.
inline bool sameTileObject(const map::Tile* made_from, const std::weak_ptr<const map::Tile>& made_from_ref,
                           const map::Tile* tile) {
    return made_from == tile && !made_from_ref.expired();
}

struct GpuTile {
    const map::Tile* source = nullptr;  // identity of the uploaded tile object
    std::weak_ptr<const map::Tile> source_ref;
    glm::dvec3 origin{0.0};
    float size_m = 0.0f;
    GLuint terrain_vao = 0, terrain_vbo = 0, terrain_ibo = 0;
    GLenum terrain_index_type = GL_UNSIGNED_INT;  // GL_UNSIGNED_SHORT where the vertices allow
    std::vector<TerrainBlock> terrain_blocks;     // drawn one by one or merged (land-cover levels)
    GLuint land_cover = 0;                        // 0: none (the shared empty texture is used)
    // The parent's and grandparent's land cover over this tile, for morphing it like the surface
    // (terrain_tile.frag); 0: that ancestor was not resident or has no land cover here.
    std::array<GLuint, 2> ancestor_cover{};
    // The synthetic orthoimage (seed ch. 6), drawn instead of the land cover once ortho_ready
    // (MapStyle::ground); 0: none (not wanted yet, or the tile has no ortho layers).
    GLuint ortho = 0;
    bool ortho_ready = false;
    bool ortho_started = false;                 // asked for once; not again after a refusal
    OrthoGenerator* ortho_generator = nullptr;  // forgets the pending image with the tile
    GLuint roads_vao = 0, roads_vbo = 0;
    // First instance of each class among non-bridge roads (instances run least important
    // first, bridges last), so the casing pass can skip the classes drawn without casing.
    std::array<GLsizei, kStyledRoadClasses> class_first{};
    GLsizei bridge_first = 0;
    std::vector<BlockRun> road_runs;        // TileMesh::road_runs: pieces per group and block
    std::vector<BlockExtent> road_blocks;   // their extents, for culling
    std::vector<RoadInstance> road_pieces;  // as uploaded, quad q from piece q (OutlinePass::markCells)
    // The lowest its drawn surface can lie (RoadPass::buildHorizon), over its own heights and those of the
    // first floor_levels geomorph targets: the ones whose morph can start within the tile.
    TerrainFloor floor;
    int floor_levels = -1;

    /// The highest vertex, as geomorphed for this frame (terrain_tile.vert, terrain_lod.cpp
    /// morphedHeight), of the grid cell holding the tile-local point `at` seen from right above
    /// it: the drawn surface over the cell lies no higher.
    [[nodiscard]] double highestDrawnAround(glm::dvec2 at) const {
        const double spacing = size_m / double(grid_size - 1);
        const int c = std::clamp(static_cast<int>(at.x / spacing), 0, grid_size - 2);
        const int r = std::clamp(static_cast<int>(at.y / spacing), 0, grid_size - 2);
        double top = std::numeric_limits<double>::lowest();
        for (const auto& [dr, dc] : {std::pair{0, 0}, std::pair{0, 1}, std::pair{1, 0}, std::pair{1, 1}}) {
            const auto v = static_cast<std::size_t>((r + dr) * grid_size + c + dc);
            std::array<float, kMorphLevels> targets{};
            for (std::size_t k = 0; k < kMorphLevels; ++k)
                targets[k] = v < ancestor_heights[k].size() ? ancestor_heights[k][v] : heights[v];
            const glm::dvec2 d = glm::dvec2(c + dc, r + dr) * spacing - at;
            const auto distance =
                static_cast<float>(std::sqrt(glm::dot(d, d) + double(morph.eye_dz_m) * morph.eye_dz_m));
            top = std::max(top, double(morphedHeight(distance, morph, heights[v], targets)));
        }
        return top;
    }
    // This frame's pieces in view (RoadPass::cull): quads [first, first + count) of the road pass's
    // indices (RoadPass::indices()),
    // the casing pass from visible_casing_first.
    GLsizei visible_first = 0, visible_count = 0, visible_casing_first = 0;
    GLuint buildings_vao = 0, buildings_vbo = 0, buildings_ibo = 0;
    GLsizei building_index_count = 0;
    std::vector<BlockRun> building_runs;       // TileMesh::building_runs: indices per block
    std::vector<BlockExtent> building_blocks;  // their extents, for culling
    std::vector<glm::vec3> label_points;       // labelPoints(): anchors and segments on the terrain
    std::uint64_t last_used = 0;
    // This frame's camera relative to the tile's origin (MapRenderer::beginFrame), for every pass
    // and cull test.
    glm::mat4 view{1.0f}, view_projection{1.0f};
    // view_projection with its sides pushed out by roadWideningPx(), for culling road quads.
    glm::mat4 road_cull{1.0f};
    // Geomorphing (terrain_lod.h): the ancestors the morph targets came from, this frame's ranges.
    std::array<const map::Tile*, kMorphLevels> morph_ancestors{};
    TileMorph morph;
    // The route draped onto this tile's grid (seed 3.6.1), per route object and version; at most
    // kRoutePiecesPerTile pieces (RoutePass).
    int grid_size = 0;
    std::vector<float> heights;                                     // grid_size^2, for draping
    std::array<std::vector<float>, kMorphLevels> ancestor_heights;  // the same for the morph targets
    const RouteGeometry* route_source = nullptr;
    std::uint64_t route_version = 0;
    std::size_t route_points = 0;
    double route_last_measure = 0.0;
    double route_tolerance_m = 0.0;  // the simplification route_pieces were draped with
    std::vector<RoutePiece> route_pieces;
    std::vector<RoadInstance> route_instances;  // route_pieces with this frame's morph
    GLuint route_vao = 0, route_vbo = 0;
    GLsizei route_count = 0;
    bool route_morphed = false;  // the buffer holds morphed heights
    bool route_stale = true;     // draped anew, not uploaded yet
    BlockExtent route_extent;    // of route_pieces, at every level they can morph to
    bool route_in_view = false;  // this frame (RoutePass::update)

    GpuTile() = default;
    GpuTile(const GpuTile&) = delete;
    GpuTile& operator=(const GpuTile&) = delete;
    ~GpuTile() {
        const GLuint vaos[] = {terrain_vao, roads_vao, buildings_vao, route_vao};
        const GLuint bufs[] = {terrain_vbo, terrain_ibo, roads_vbo, buildings_vbo, buildings_ibo, route_vbo};
        glDeleteVertexArrays(4, vaos);
        glDeleteBuffers(6, bufs);
        if (land_cover) glDeleteTextures(1, &land_cover);
        glDeleteTextures(2, ancestor_cover.data());
        if (ortho) {
            if (ortho_generator) ortho_generator->cancel(ortho);
            glDeleteTextures(1, &ortho);
        }
    }
};

// Two triangles per road quad: corners 0 (-,+) 1 (-,-) 2 (+,+) 3 (+,-).
inline constexpr std::uint32_t kQuadIndices[6] = {0, 1, 2, 2, 1, 3};

// RoadInstance: p0 (3), p1 (3), class, cap reach (2), measure0, measure1 (flags: CPU only), repeated
// per quad corner.
inline void setupRoadAttributes() {
    setVertexAttributes(sizeof(RoadInstance), {{0, 3, GL_FLOAT, offsetof(RoadInstance, p0)},
                                               {1, 3, GL_FLOAT, offsetof(RoadInstance, p1)},
                                               {2, 1, GL_FLOAT, offsetof(RoadInstance, road_class)},
                                               {3, 2, GL_FLOAT, offsetof(RoadInstance, cap_reach)},
                                               {4, 2, GL_FLOAT, offsetof(RoadInstance, measure0)}});
}

// Road pieces as plain quads: each RoadInstance repeated for the four corners (the shader takes
// the corner from gl_VertexID & 3) and one shared index buffer of two triangles per quad.
// llvmpipe runs an instanced draw as one small draw per instance, which made the vertex side
// three quarters of the road pass; one indexed draw per tile and pass avoids that.
inline std::vector<RoadInstance> quadVertices(std::span<const RoadInstance> pieces) {
    std::vector<RoadInstance> out;
    out.reserve(pieces.size() * 4);
    for (const RoadInstance& r : pieces) out.insert(out.end(), 4, r);
    return out;
}

}  // namespace navmap::render::gl
