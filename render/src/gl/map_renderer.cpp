// SPDX-License-Identifier: Apache-2.0
#include "map_renderer.h"
#include "road_uniforms.h"
#include "sv_roads.h"
#include "vertex_layout.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstddef>
#include <cstdio>
#include <limits>
#include <numbers>
#include <numeric>
#include <span>
#include <vector>

#include <glm/gtc/matrix_access.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/type_ptr.hpp>

#include "navmap/render/terrain_lod.h"

namespace navmap::render::gl {

namespace {

// Land-cover raster per tile (8 m per texel on 2 km leaf tiles), shared by every display
// profile. RGBA4: land cover is flat class colours and a coverage strength, which 4 bits per
// channel hold; half the memory of RGBA8 (about 0.17 MiB per tile with mipmaps).
int landCoverTextureSize(float) { return 256; }
constexpr int kLandCoverSamples = 4;
// How far (pixels) the outline filter reaches from a road pixel: the 3x3 filter's 1 px, half a
// pixel to the centre of the pixel that reads the road, and room for the GPU's rounding.
constexpr float kOutlineReachPx = 2.0f;
// Side of the screen cells marked for the outline filter (OutlineCells), pixels: llvmpipe shades
// blocks of 4 x 4 pixels in tiles of 64, so multiples of 4 waste no partial blocks; smaller cells
// follow the roads closer but cost more CPU to mark.
constexpr int kOutlineCellPx = 8;
static_assert(kOutlineCellPx == kPackedMaskPixels, "the packing pass turns a cell into one column of texels");
// Cells per rectangle of the outline mask's packing pass (markOutlineCells).
constexpr int kOutlinePackGroup = 4;
// Screen error allowed to the road levels of detail (TileMesh, kRoadLodTolerance), pixels.
constexpr float kRoadLodErrorPx = 0.5f;
// Stencil bit the road and route passes set on the pixels they draw, so that the outline filter
// leaves them out: a road pixel holds its neighbourhood's maximum intensity itself, its edge
// strength is 0. llvmpipe then skips the 4x4 blocks inside roads before shading. (The glow uses
// bit 7, occlusion_effects.cpp.)
constexpr GLuint kRoadStencilBit = 0x40;
// The route's casing per side, as a fraction of its width (roads_geo.vert's u_route_casing_m).
constexpr float kRouteCasingFraction = 0.25f;
// Full width of the route's quads with their casing (its widest pass), metres.
float routeOuterWidth(float route_width_m) { return (1.0f + 2.0f * kRouteCasingFraction) * route_width_m; }
// How far, in pixels, roads_geo.vert can move any road or route quad's upper side beyond the quad
// on the ground when it widens a foreshortened road to RoadStyle::min_width_px: the most of
// leastWidthGrowthPx (OutlineCells::markQuad's bound per quad) over the classes and the route.
float roadWideningPx(const MapStyle& style) {
    const float min_width = style.roads.min_width_px;
    float most = leastWidthGrowthPx(min_width, routeOuterWidth(style.route_width_m), style.route_width_m);
    for (const RoadClassStyle& c : style.roads.classes) most = std::max(most, leastWidthGrowthPx(min_width, c.outerWidth(), c.width_m));
    return most;
}

using Clock = std::chrono::steady_clock;

// seed 5.5: which occlusion effects a frame gets (glow needs something to hide roads and
// roads to show; the aura needs labels and buildings to fade).
bool wantsGlow(const MapLayers& l) { return l.glow_roads && l.buildings && (l.roads || l.route); }
bool wantsAura(const MapLayers& l) { return l.label_aura && l.labels && l.buildings; }

// The land-cover levels a tile's pixels reach this frame (0 its own raster, 1 the parent's, 2 the
// grandparent's; terrain_tile.frag): from the finest some vertex has not morphed away from to the
// coarsest some vertex morphs into. Distances are measured as the geomorph measures them
// (terrain_lod.h: horizontal, plus the camera's distance from the LOD height band); the slots'
// ranges are disjoint and increasing (morph_start > 0.5).
struct CoverLevels {
    int finest = 0, coarsest = 0;
};
// False when the box [lo, hi] (tile-local) lies entirely outside one plane of the view frustum;
// `far` false leaves the far plane out.
bool boxInView(const glm::mat4& view_projection, glm::vec3 lo, glm::vec3 hi, bool far = true) {
    std::array<int, 6> outside{};
    for (int i = 0; i < 8; ++i) {
        const glm::vec4 c = view_projection * glm::vec4((i & 1) ? hi.x : lo.x, (i & 2) ? hi.y : lo.y, (i & 4) ? hi.z : lo.z, 1.0f);
        outside[0] += c.x < -c.w;
        outside[1] += c.x > c.w;
        outside[2] += c.y < -c.w;
        outside[3] += c.y > c.w;
        outside[4] += c.z < -c.w;
        outside[5] += far && c.z > c.w;
    }
    return std::none_of(outside.begin(), outside.end(), [](int n) { return n == 8; });
}
bool boxInView(const glm::mat4& view_projection, const TerrainBlock& b) {
    return boxInView(view_projection, glm::vec3(b.min, b.min_z), glm::vec3(b.max, b.max_z));
}
// Half the widest road footprint of the style (casing included), metres before distance scaling.
float widestHalfWidth(const RoadStyle& rs) {
    float half_width = 0.0f;
    for (const RoadClassStyle& c : rs.classes) half_width = std::max(half_width, 0.5f * c.outerWidth());
    return half_width;
}

// How far road or route quads drawn from pieces within `e` reach beyond it, before the least-width
// widening: `half_width` (fill and casing) at the distance scale (seed 3.6.3) of the extent's
// farthest point from `eye`, times sqrt 2 (a corner lies that far along and across the piece).
struct QuadReach {
    float farthest_m = 0.0f;
    float reach_m = 0.0f;
};
QuadReach quadReach(glm::vec3 eye, const BlockExtent& e, float half_width, const RoadStyle& rs) {
    const float farthest = glm::length(glm::max(glm::abs(eye - e.min), glm::abs(eye - e.max)));
    return {farthest, std::numbers::sqrt2_v<float> * half_width * distanceWidthScale(farthest, rs.scale_threshold_m, rs.max_scale)};
}

// Whether road or route quads drawn from pieces within `e`, reaching `reach` beyond it, can reach
// the view. The far plane is left out: the view-space offset against z-fighting (seed 3.6.2)
// pulls pieces a little towards the camera.
bool quadsInView(const glm::mat4& view_projection, const BlockExtent& e, float reach) {
    if (e.min.x > e.max.x) return false;  // nothing there
    return boxInView(view_projection, e.min - reach, e.max + reach, false);
}

// The view frustum's side and near planes (tile-local, metric), for a test per road piece: in
// the blocks in view, about a third to a half of the pieces still lie outside the view, and on
// llvmpipe each costs the render thread its vertices and triangle setup.
class PieceFrustum {
public:
    explicit PieceFrustum(const glm::mat4& view_projection) {
        const glm::vec4 x = glm::row(view_projection, 0), y = glm::row(view_projection, 1);
        const glm::vec4 z = glm::row(view_projection, 2), w = glm::row(view_projection, 3);
        m_planes = {w + x, w - x, w + y, w - y, w + z};  // the far plane left out, as in quadsInView
        for (glm::vec4& p : m_planes) p /= glm::length(glm::vec3(p));
    }
    /// Whether the quad roads_geo.vert expands from `r` can reach the view: the sphere around the
    /// piece's middle through its end points, grown by the widest quad's corner reach (half the
    /// width, scaled by distance as the shader does at the middle, times sqrt 2). The view-space
    /// offset (seed 3.6.2) moves points towards the eye, along the side planes' rays.
    [[nodiscard]] bool holds(const RoadInstance& r, glm::vec3 eye, float half_width, const RoadStyle& rs) const {
        const glm::vec3 mid = 0.5f * (r.p0 + r.p1);
        const float reach = half_width * distanceWidthScale(glm::length(mid - eye), rs.scale_threshold_m, rs.max_scale);
        const float radius = 0.5f * glm::length(r.p1 - r.p0) + std::numbers::sqrt2_v<float> * reach;
        for (const glm::vec4& p : m_planes) {
            if (glm::dot(glm::vec3(p), mid) + p.w < -radius) return false;
        }
        return true;
    }

private:
    std::array<glm::vec4, 5> m_planes{};
};

bool operator==(CoverLevels a, CoverLevels b) { return a.finest == b.finest && a.coarsest == b.coarsest; }
/// For the part [lo, hi] (tile-local x, y) of a tile seen from tile-local `eye`.
CoverLevels coverLevels(const TileMorph& m, glm::vec2 eye, glm::vec2 lo, glm::vec2 hi) {
    const glm::vec2 near = glm::max(glm::max(lo - eye, eye - hi), glm::vec2(0.0f));
    const glm::vec2 far = glm::max(glm::abs(eye - lo), glm::abs(eye - hi));
    const float nx = near.x, ny = near.y, fx = far.x, fy = far.y;
    const float dz2 = m.eye_dz_m * m.eye_dz_m;
    const float nearest = std::sqrt(nx * nx + ny * ny + dz2), farthest = std::sqrt(fx * fx + fy * fy + dz2);
    CoverLevels c;
    for (int j = 0; j < 2; ++j) {
        const auto k = static_cast<std::size_t>(j);
        if (m.end_m[k] <= m.start_m[k]) break;  // no morph in this slot (the shader's test)
        if (c.finest == j && nearest >= m.end_m[k]) c.finest = j + 1;
        if (farthest > m.start_m[k]) c.coarsest = j + 1;
    }
    return c;
}

// The terrain vertex as uploaded: normals as x, y in normalized shorts (z >= 0 follows; the
// shader unpacks them), 48 bytes instead of TerrainVertex's 72. Heights stay float: the route
// is draped on the CPU against the same values.
struct PackedTerrainVertex {
    glm::vec3 position;
    std::array<std::int16_t, 2> normal;
    std::array<float, kMorphLevels> ancestor_heights;
    std::array<std::int16_t, 2 * kMorphLevels> ancestor_normals;
};

std::int16_t snorm16(float v) { return static_cast<std::int16_t>(std::lround(std::clamp(v, -1.0f, 1.0f) * 32767.0f)); }

std::vector<PackedTerrainVertex> packTerrain(std::span<const TerrainVertex> vertices) {
    std::vector<PackedTerrainVertex> out(vertices.size());
    for (std::size_t i = 0; i < vertices.size(); ++i) {
        const TerrainVertex& v = vertices[i];
        PackedTerrainVertex& p = out[i];
        p.position = v.position;
        p.normal = {snorm16(v.normal.x), snorm16(v.normal.y)};
        p.ancestor_heights = v.ancestor_heights;
        for (std::size_t j = 0; j < v.ancestor_normals.size(); ++j) {
            p.ancestor_normals[2 * j] = snorm16(v.ancestor_normals[j].x);
            p.ancestor_normals[2 * j + 1] = snorm16(v.ancestor_normals[j].y);
        }
    }
    return out;
}

std::size_t indexBytes(GLenum type) { return type == GL_UNSIGNED_SHORT ? sizeof(std::uint16_t) : sizeof(std::uint32_t); }

// Uploads indices into the bound element buffer, as 16-bit values when the vertices allow it;
// returns the GL index type.
GLenum uploadIndices(std::span<const std::uint32_t> indices, std::size_t vertex_count) {
    if (vertex_count <= 0xFFFF) {
        std::vector<std::uint16_t> narrow(indices.begin(), indices.end());
        glBufferData(GL_ELEMENT_ARRAY_BUFFER, static_cast<GLsizeiptr>(narrow.size() * sizeof(std::uint16_t)), narrow.data(),
                     GL_STATIC_DRAW);
        return GL_UNSIGNED_SHORT;
    }
    glBufferData(GL_ELEMENT_ARRAY_BUFFER, static_cast<GLsizeiptr>(indices.size() * sizeof(std::uint32_t)), indices.data(),
                 GL_STATIC_DRAW);
    return GL_UNSIGNED_INT;
}

double msSince(Clock::time_point t) { return std::chrono::duration<double, std::milli>(Clock::now() - t).count(); }

// RoadInstance: p0 (3), p1 (3), class, cap reach (2), measure0, measure1 (flags: CPU only), repeated
// per quad corner.
void setupRoadAttributes() {
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
std::vector<RoadInstance> quadVertices(std::span<const RoadInstance> pieces) {
    std::vector<RoadInstance> out;
    out.reserve(pieces.size() * 4);
    for (const RoadInstance& r : pieces) out.insert(out.end(), 4, r);
    return out;
}

}  // namespace

struct MapRenderer::GpuTile {
    const map::Tile* source = nullptr;  // identity of the uploaded tile object
    glm::dvec3 origin{0.0};
    float size_m = 0.0f;
    GLuint terrain_vao = 0, terrain_vbo = 0, terrain_ibo = 0;
    GLenum terrain_index_type = GL_UNSIGNED_INT;  // GL_UNSIGNED_SHORT where the vertices allow
    std::vector<TerrainBlock> terrain_blocks;  // drawn one by one or merged (land-cover levels)
    GLuint land_cover = 0;  // 0: none (the shared empty texture is used)
    // The parent's and grandparent's land cover over this tile, for morphing it like the surface
    // (terrain_tile.frag); 0: that ancestor was not resident or has no land cover here.
    std::array<GLuint, 2> ancestor_cover{};
    GLuint roads_vao = 0, roads_vbo = 0;
    // First instance of each class among non-bridge roads (instances run least important
    // first, bridges last), so the casing pass can skip the classes drawn without casing.
    std::array<GLsizei, kStyledRoadClasses> class_first{};
    GLsizei bridge_first = 0;
    std::vector<BlockRun> road_runs;      // TileMesh::road_runs: pieces per group and block
    std::vector<BlockExtent> road_blocks;  // their extents, for culling
    std::vector<RoadInstance> road_pieces;  // as uploaded, quad q from piece q (markOutlineCells)
    // The lowest its drawn surface can lie (buildHorizon), over its own heights and those of the
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
            for (std::size_t k = 0; k < kMorphLevels; ++k) targets[k] = v < ancestor_heights[k].size() ? ancestor_heights[k][v] : heights[v];
            const glm::dvec2 d = glm::dvec2(c + dc, r + dr) * spacing - at;
            const auto distance = static_cast<float>(std::sqrt(glm::dot(d, d) + double(morph.eye_dz_m) * morph.eye_dz_m));
            top = std::max(top, double(morphedHeight(distance, morph, heights[v], targets)));
        }
        return top;
    }
    // This frame's pieces in view (cullRoads): quads [first, first + count) of m_road_indices,
    // the casing pass from casing_first.
    GLsizei visible_first = 0, visible_count = 0, visible_casing_first = 0;
    GLuint buildings_vao = 0, buildings_vbo = 0, buildings_ibo = 0;
    GLsizei building_index_count = 0;
    std::vector<BlockRun> building_runs;      // TileMesh::building_runs: indices per block
    std::vector<BlockExtent> building_blocks;  // their extents, for culling
    std::vector<glm::vec3> label_points;  // labelPoints(): anchors and segments on the terrain
    std::uint64_t last_used = 0;
    // This frame's camera relative to the tile's origin (render()), for every pass and cull test.
    glm::mat4 view{1.0f}, view_projection{1.0f};
    // view_projection with its sides pushed out by roadWideningPx(), for culling road quads.
    glm::mat4 road_cull{1.0f};
    // Geomorphing (terrain_lod.h): the ancestors the morph targets came from, this frame's ranges.
    std::array<const map::Tile*, kMorphLevels> morph_ancestors{};
    TileMorph morph;
    // The route draped onto this tile's grid (seed 3.6.1), per route object and version.
    int grid_size = 0;
    std::vector<float> heights;                                       // grid_size^2, for draping
    std::array<std::vector<float>, kMorphLevels> ancestor_heights;  // the same for the morph targets
    const RouteGeometry* route_source = nullptr;
    std::uint64_t route_version = 0;
    std::size_t route_points = 0;
    double route_last_measure = 0.0;
    std::vector<RoutePiece> route_pieces;
    std::vector<RoadInstance> route_instances;  // route_pieces with this frame's morph
    GLuint route_vao = 0, route_vbo = 0;
    GLsizei route_count = 0;
    bool route_morphed = false;  // the buffer holds morphed heights
    bool route_stale = true;     // draped anew, not uploaded yet
    BlockExtent route_extent;    // of route_pieces, at every level they can morph to
    bool route_in_view = false;  // this frame (updateRoute)

    ~GpuTile() {
        const GLuint vaos[] = {terrain_vao, roads_vao, buildings_vao, route_vao};
        const GLuint bufs[] = {terrain_vbo, terrain_ibo, roads_vbo, buildings_vbo, buildings_ibo, route_vbo};
        glDeleteVertexArrays(4, vaos);
        glDeleteBuffers(6, bufs);
        if (land_cover) glDeleteTextures(1, &land_cover);
        glDeleteTextures(2, ancestor_cover.data());
    }
};

MapRenderer::MapRenderer(const RendererOptions& options, bool software)
    : m_options(options),
      m_software(software),
      m_style(MapStyle::day()),
      m_terrain(ShaderProgram::fromEmbedded("terrain_tile.vert", "terrain_tile.frag")),
      m_terrain_cover{ShaderProgram::fromEmbedded("terrain_tile.vert", "terrain_tile.frag", "#define NAVMAP_COVER_LEVELS 2\n"),
                      ShaderProgram::fromEmbedded("terrain_tile.vert", "terrain_tile.frag", "#define NAVMAP_COVER_LEVELS 3\n")},
      m_land_cover(ShaderProgram::fromEmbedded("landcover_raster.vert", "landcover_raster.frag")),
      m_roads(ShaderProgram::fromEmbedded("roads_geo.vert", "roads_geo.frag")),
      m_route(ShaderProgram::fromEmbedded("roads_geo.vert", "roads_geo.frag", "#define NAVMAP_ROUTE_PROGRESS 1\n")),
      m_outline(ShaderProgram::fromEmbedded("screen_outline.vert", "screen_outline.frag")),
      m_outline_cells(ShaderProgram::fromEmbedded("screen_cells.vert", "screen_outline.frag")),
      m_outline_packed(ShaderProgram::fromEmbedded("screen_cells.vert", "screen_outline.frag", "#define NAVMAP_PACKED_MASK 1\n")),
      m_outline_pack(ShaderProgram::fromEmbedded("screen_cells.vert", "outline_pack.frag")),
      m_outline_edges(ShaderProgram::fromEmbedded("screen_cells.vert", "screen_outline.frag", "#define NAVMAP_EDGE_MASK 1\n")),
      m_buildings(ShaderProgram::fromEmbedded("buildings.vert", "buildings.frag")),
      m_marker(ShaderProgram::fromEmbedded("marker.vert", "marker.frag")) {
    const std::uint8_t transparent[4] = {0, 0, 0, 0};
    glGenTextures(1, &m_empty_texture);
    glBindTexture(GL_TEXTURE_2D, m_empty_texture);
    glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, 1, 1, 0, GL_RGBA, GL_UNSIGNED_BYTE, transparent);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    glBindTexture(GL_TEXTURE_2D, 0);
    glGenFramebuffers(1, &m_raster_fbo);
    glGenVertexArrays(1, &m_empty_vao);
    glGenBuffers(1, &m_road_index_buffer);
    glGenVertexArrays(1, &m_cell_vao);
    glGenBuffers(1, &m_cell_vbo);
    glBindVertexArray(m_cell_vao);
    glBindBuffer(GL_ARRAY_BUFFER, m_cell_vbo);
    glEnableVertexAttribArray(0);
    glVertexAttribPointer(0, 2, GL_FLOAT, GL_FALSE, 0, nullptr);
    glBindVertexArray(0);
    // CCP arrow: tip at +y, notch at the back (marker units, about one unit across).
    const float arrow[] = {0.0f, 1.0f, -0.6f, -0.7f, 0.0f, -0.35f, 0.0f, 1.0f, 0.0f, -0.35f, 0.6f, -0.7f};
    glGenVertexArrays(1, &m_marker_vao);
    glGenBuffers(1, &m_marker_vbo);
    glBindVertexArray(m_marker_vao);
    glBindBuffer(GL_ARRAY_BUFFER, m_marker_vbo);
    glBufferData(GL_ARRAY_BUFFER, sizeof arrow, arrow, GL_STATIC_DRAW);
    glEnableVertexAttribArray(0);
    glVertexAttribPointer(0, 2, GL_FLOAT, GL_FALSE, 0, nullptr);
    glBindVertexArray(0);
}

MapRenderer::~MapRenderer() {
    m_tiles.clear();
    glDeleteTextures(1, &m_empty_texture);
    glDeleteFramebuffers(1, &m_raster_fbo);
    glDeleteFramebuffers(1, &m_raster_ms_fbo);
    glDeleteRenderbuffers(1, &m_raster_ms_rb);
    glDeleteVertexArrays(1, &m_empty_vao);
    glDeleteVertexArrays(1, &m_marker_vao);
    glDeleteBuffers(1, &m_marker_vbo);
    glDeleteBuffers(1, &m_road_index_buffer);
    glDeleteVertexArrays(1, &m_cell_vao);
    glDeleteBuffers(1, &m_cell_vbo);
}

MapRenderer::GpuTile* MapRenderer::upload(const std::shared_ptr<const map::Tile>& tile, const TileMorph* morph) {
    if (tile->dem.coverage < 1.0f && m_warned_flat.insert(tile->id.key()).second) {
        // The compiler found no DEM for part of this tile; that part renders flat at 0 m. The
        // caller logs it (once per tile, whichever display met it first).
        m_new_flat_tiles.push_back({tile->id, tile->dem.coverage});
        ++m_stats_flat_tiles;
    }
    std::array<const map::Tile*, kMorphLevels> ancestors{};
    for (std::size_t j = 0; morph && j < ancestors.size(); ++j) ancestors[j] = morph->ancestors[j].get();
    TileMesh mesh = buildTileMesh(*tile, {}, ancestors);
    auto gpu = std::make_unique<GpuTile>();
    gpu->source = tile.get();
    gpu->morph_ancestors = ancestors;
    gpu->grid_size = mesh.grid_size;
    gpu->heights = mesh.heights;
    gpu->ancestor_heights = mesh.ancestor_heights;
    gpu->origin = mesh.origin;
    gpu->size_m = mesh.size_m;
    if (!tile->labels.empty()) gpu->label_points = labelPoints(*tile, mesh.grid());

    glGenVertexArrays(1, &gpu->terrain_vao);
    glGenBuffers(1, &gpu->terrain_vbo);
    glGenBuffers(1, &gpu->terrain_ibo);
    glBindVertexArray(gpu->terrain_vao);
    glBindBuffer(GL_ARRAY_BUFFER, gpu->terrain_vbo);
    const std::vector<PackedTerrainVertex> packed = packTerrain(mesh.terrain);
    glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(packed.size() * sizeof(PackedTerrainVertex)), packed.data(),
                 GL_STATIC_DRAW);
    // Geomorph targets (terrain_tile.vert): 4 ancestor heights, then 4 normals' x, y as two vec4.
    static_assert(kMorphLevels == 4, "terrain_tile.vert takes 4 ancestor levels");
    using V = PackedTerrainVertex;
    setVertexAttributes(sizeof(V), {{0, 3, GL_FLOAT, offsetof(V, position)},
                                    {1, 2, GL_SHORT, offsetof(V, normal)},
                                    {2, 4, GL_FLOAT, offsetof(V, ancestor_heights)},
                                    {3, 4, GL_SHORT, offsetof(V, ancestor_normals)},
                                    {4, 4, GL_SHORT, offsetof(V, ancestor_normals) + 4 * sizeof(std::int16_t)}});
    glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, gpu->terrain_ibo);
    gpu->terrain_index_type = uploadIndices(mesh.terrain_indices, mesh.terrain.size());
    gpu->terrain_blocks = mesh.terrain_blocks;

    if (!mesh.roads.empty()) {
        glGenVertexArrays(1, &gpu->roads_vao);
        glGenBuffers(1, &gpu->roads_vbo);
        glBindVertexArray(gpu->roads_vao);
        glBindBuffer(GL_ARRAY_BUFFER, gpu->roads_vbo);
        const auto quads = quadVertices(mesh.roads);
        glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(quads.size() * sizeof(RoadInstance)), quads.data(),
                     GL_STATIC_DRAW);
        setupRoadAttributes();
        glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, m_road_index_buffer);  // this frame's pieces in view (cullRoads)
        const auto road_count = static_cast<GLsizei>(mesh.roads.size());
        gpu->road_runs = std::move(mesh.road_runs);
        gpu->road_blocks = std::move(mesh.road_blocks);
        gpu->class_first.fill(road_count);
        gpu->bridge_first = road_count;
        for (GLsizei i = road_count; i-- > 0;) {
            const RoadInstance& r = mesh.roads[static_cast<std::size_t>(i)];
            if (static_cast<int>(r.flags) & map::RoadFlags::Bridge) {
                gpu->bridge_first = i;
                continue;
            }
            const int c = std::clamp(static_cast<int>(r.road_class), 0, kStyledRoadClasses - 1);
            gpu->class_first[static_cast<std::size_t>(c)] = i;
        }
        gpu->road_pieces = std::move(mesh.roads);
    }
    if (!mesh.building_indices.empty()) {
        glGenVertexArrays(1, &gpu->buildings_vao);
        glGenBuffers(1, &gpu->buildings_vbo);
        glGenBuffers(1, &gpu->buildings_ibo);
        glBindVertexArray(gpu->buildings_vao);
        glBindBuffer(GL_ARRAY_BUFFER, gpu->buildings_vbo);
        glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(mesh.buildings.size() * sizeof(BuildingVertex)),
                     mesh.buildings.data(), GL_STATIC_DRAW);
        setVertexAttributes(sizeof(BuildingVertex), {{0, 3, GL_FLOAT, offsetof(BuildingVertex, position)},
                                                     {1, 3, GL_FLOAT, offsetof(BuildingVertex, normal)},
                                                     {2, 3, GL_FLOAT, offsetof(BuildingVertex, color)},
                                                     {3, 1, GL_FLOAT, offsetof(BuildingVertex, footprint_m)}});
        glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, gpu->buildings_ibo);
        glBufferData(GL_ELEMENT_ARRAY_BUFFER,
                     static_cast<GLsizeiptr>(mesh.building_indices.size() * sizeof(std::uint32_t)),
                     mesh.building_indices.data(), GL_STATIC_DRAW);
        gpu->building_index_count = static_cast<GLsizei>(mesh.building_indices.size());
        gpu->building_runs = std::move(mesh.building_runs);
        gpu->building_blocks = std::move(mesh.building_blocks);
    }
    glBindVertexArray(0);
    if (!mesh.land_cover.empty()) {
        gpu->land_cover = rasterizeLandCover(mesh.land_cover, landCoverTextureSize(mesh.size_m), glm::vec2(0.0f), mesh.size_m);
    }
    // The ancestors' rasters over this tile at their own texel density (half, a quarter).
    for (std::size_t j = 0; j < gpu->ancestor_cover.size(); ++j) {
        const map::Tile* a = ancestors[j];
        if (!a) continue;
        // Siblings uploaded in one frame share their ancestors: triangulated once per frame.
        auto [it, fresh] = m_ancestor_cover_triangles.try_emplace(a);
        if (fresh) it->second = landCoverTriangles(*a);
        const std::vector<LandCoverVertex>& triangles = it->second;
        if (triangles.empty()) continue;
        const glm::vec2 offset(static_cast<float>(mesh.origin.x - a->origin_x), static_cast<float>(mesh.origin.y - a->origin_y));
        gpu->ancestor_cover[j] = rasterizeLandCover(triangles, landCoverTextureSize(static_cast<float>(a->size_m)) >> (j + 1),
                                                    offset, mesh.size_m);
    }

    GpuTile* raw = gpu.get();
    m_tiles[tile->id.key()] = std::move(gpu);
    return raw;
}

GLuint MapRenderer::rasterizeLandCover(std::span<const LandCoverVertex> triangles, int size, glm::vec2 offset,
                                       float extent) {
    GLuint texture = 0;
    glGenTextures(1, &texture);
    glBindTexture(GL_TEXTURE_2D, texture);
    const int levels = 1 + static_cast<int>(std::log2(size));
    glTexStorage2D(GL_TEXTURE_2D, levels, GL_RGBA4, size, size);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR_MIPMAP_LINEAR);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    glBindFramebuffer(GL_FRAMEBUFFER, m_raster_fbo);
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, texture, 0);
    const GLenum c0 = GL_COLOR_ATTACHMENT0;
    glDrawBuffers(1, &c0);
    // Area edges anti-aliased (4x multisampled, then resolved into the texture): the rasters are
    // magnified on screen, where hard-edged texels would show as steps.
    if (m_raster_ms_size.grow(size, size)) {
        if (!m_raster_ms_fbo) glGenFramebuffers(1, &m_raster_ms_fbo);
        if (m_raster_ms_rb) glDeleteRenderbuffers(1, &m_raster_ms_rb);
        m_raster_ms_rb = makeRenderbuffer(GL_RGBA4, kLandCoverSamples, size, size);
        glBindFramebuffer(GL_FRAMEBUFFER, m_raster_ms_fbo);
        glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, m_raster_ms_rb);
        checkFramebufferComplete("land-cover raster");
    }
    glBindFramebuffer(GL_FRAMEBUFFER, m_raster_ms_fbo);
    glViewport(0, 0, size, size);
    const GLfloat clear[] = {0, 0, 0, 0};
    glClearBufferfv(GL_COLOR, 0, clear);
    glDisable(GL_DEPTH_TEST);
    glDisable(GL_CULL_FACE);
    glDisable(GL_BLEND);

    GLuint vao = 0, vbo = 0;
    glGenVertexArrays(1, &vao);
    glGenBuffers(1, &vbo);
    glBindVertexArray(vao);
    glBindBuffer(GL_ARRAY_BUFFER, vbo);
    glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(triangles.size() * sizeof(LandCoverVertex)), triangles.data(),
                 GL_STREAM_DRAW);
    setVertexAttributes(sizeof(LandCoverVertex), {{0, 2, GL_FLOAT, offsetof(LandCoverVertex, position)},
                                                  {1, 4, GL_FLOAT, offsetof(LandCoverVertex, color)}});
    glUseProgram(m_land_cover.id());
    glUniform2fv(m_land_cover.uniform("u_offset"), 1, glm::value_ptr(offset));
    glUniform1f(m_land_cover.uniform("u_extent"), extent);
    glDrawArrays(GL_TRIANGLES, 0, static_cast<GLsizei>(triangles.size()));
    glBindVertexArray(0);
    glDeleteBuffers(1, &vbo);
    glDeleteVertexArrays(1, &vao);
    glBindFramebuffer(GL_READ_FRAMEBUFFER, m_raster_ms_fbo);
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, m_raster_fbo);
    glBlitFramebuffer(0, 0, size, size, 0, 0, size, size, GL_COLOR_BUFFER_BIT, GL_NEAREST);
    glGenerateMipmap(GL_TEXTURE_2D);
    glBindTexture(GL_TEXTURE_2D, 0);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    return texture;
}

void MapRenderer::updateRoute(GpuTile& g, const MapFrame& frame) {
    // Draped per tile against the grid it is drawn with (seed 3.6.1), so the route lies on the
    // terrain at every level of detail; redone when the route or the tile's upload changes.
    const RouteGeometry& route = *frame.route;
    const double last = route.measure_m.empty() ? 0.0 : route.measure_m.back();
    if (g.route_source != &route || g.route_version != route.version || g.route_points != route.points.size() ||
        g.route_last_measure != last) {
        g.route_source = &route;
        g.route_version = route.version;
        g.route_points = route.points.size();
        g.route_last_measure = last;
        g.route_pieces.clear();
        if (g.grid_size >= 2) {
            const double spacing = g.size_m / double(g.grid_size - 1);
            std::array<HeightGrid, kMorphLevels> ancestors;
            for (std::size_t j = 0; j < ancestors.size(); ++j)
                ancestors[j] = HeightGrid{g.grid_size, spacing, g.ancestor_heights[j].data()};
            g.route_pieces = drapeRoute(route, g.origin, HeightGrid{g.grid_size, spacing, g.heights.data()}, ancestors);
        }
        // Its extent at every level it can morph to, for culling.
        g.route_extent = {glm::vec3(std::numeric_limits<float>::max()), glm::vec3(std::numeric_limits<float>::lowest())};
        for (const RoutePiece& r : g.route_pieces) {
            for (const auto& [p, ancestor_z] : {std::pair{r.p0, r.ancestor_z0}, std::pair{r.p1, r.ancestor_z1}}) {
                const auto [lowest, highest] = std::minmax_element(ancestor_z.begin(), ancestor_z.end());
                g.route_extent.min = glm::min(g.route_extent.min, glm::vec3(glm::vec2(p), std::min(p.z, *lowest)));
                g.route_extent.max = glm::max(g.route_extent.max, glm::vec3(glm::vec2(p), std::max(p.z, *highest)));
            }
        }
        g.route_count = 0;
        g.route_instances.clear();
        g.route_stale = true;
        if (g.route_pieces.empty()) return;
        if (!g.route_vao) {
            glGenVertexArrays(1, &g.route_vao);
            glGenBuffers(1, &g.route_vbo);
            glBindVertexArray(g.route_vao);
            glBindBuffer(GL_ARRAY_BUFFER, g.route_vbo);
            setupRoadAttributes();
            glBindVertexArray(0);
        }
    }
    // Not in view: neither morphed nor drawn this frame (half its outer width around its extent,
    // as roads_geo.vert draws it).
    const glm::vec3 eye(frame.camera.eye - g.origin);
    g.route_in_view = !g.route_pieces.empty() &&
                      (!frame.layers.cull_blocks ||
                       quadsInView(g.road_cull, g.route_extent,
                                   quadReach(eye, g.route_extent, 0.5f * routeOuterWidth(m_style.route_width_m), m_style.roads).reach_m));
    if (!g.route_in_view) return;
    if (!g.route_stale && g.morph.end_m[0] <= 0.0f && !g.route_morphed) return;  // unmorphed: the buffer is current
    g.route_stale = false;
    g.route_morphed = g.morph.end_m[0] > 0.0f;
    // The pieces follow the terrain's geomorph (the same factor per vertex as terrain_tile.vert).
    morphRoute(g.route_pieces, g.morph, glm::vec2(eye), g.route_instances);
    const auto quads = quadVertices(g.route_instances);
    glBindVertexArray(g.route_vao);
    m_quad_indices.bind(g.route_instances.size());
    glBindBuffer(GL_ARRAY_BUFFER, g.route_vbo);
    glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(quads.size() * sizeof(RoadInstance)), quads.data(),
                 GL_STREAM_DRAW);
    glBindVertexArray(0);
    glBindBuffer(GL_ARRAY_BUFFER, 0);
    g.route_count = static_cast<GLsizei>(g.route_instances.size());
}

void MapRenderer::buildHorizon(const MapFrame& frame, const glm::mat4& projection, const std::vector<GpuTile*>& tiles) {
    const auto t0 = Clock::now();
    const glm::dvec3 eye = frame.camera.eye;
    // The azimuths of the view's corner rays around the view's own. A view that looks down on
    // the ground below the eye spans every azimuth and sees little hidden (the bird's-eye view):
    // no horizon then.
    const glm::mat4 view_projection = projection * frame.camera.viewRelativeTo(eye);
    const glm::vec4 below = view_projection * glm::vec4(0.0f, 0.0f, -1.0f, 1.0f);
    m_horizon = {};
    if (below.w > 0.0f && std::abs(below.x) < below.w && std::abs(below.y) < below.w) return;
    const glm::mat4 to_world = glm::inverse(view_projection);
    const glm::vec4 ahead = to_world * glm::vec4(0.0f, 0.0f, 1.0f, 1.0f);
    {
        // A view looking down steeply (the bird's-eye view, 50 degrees) sees little hidden behind
        // the terrain; the snail's views look down 14 degrees.
        const glm::dvec3 forward = glm::dvec3(ahead) / double(ahead.w);
        constexpr double kSteepest = 0.6;  // radians down, about 35 degrees
        if (std::atan2(-forward.z, glm::length(glm::dvec2(forward))) > kSteepest) return;
    }
    const double mid = std::atan2(double(ahead.y / ahead.w), double(ahead.x / ahead.w));
    double from = 0.0, to = 0.0;
    for (const glm::vec2 c : {glm::vec2(-1, -1), glm::vec2(1, -1), glm::vec2(-1, 1), glm::vec2(1, 1)}) {
        const glm::vec4 p = to_world * glm::vec4(c, 1.0f, 1.0f);
        const double rel = std::remainder(std::atan2(double(p.y / p.w), double(p.x / p.w)) - mid, 2.0 * std::numbers::pi);
        from = std::min(from, rel);
        to = std::max(to, rel);
    }
    constexpr double kMargin = 0.05;  // radians
    const double az_from = mid + from - kMargin, az_to = mid + to + kMargin;
    // Lines of sight out to the farthest tile corner. Under the eye: the highest vertex of its
    // cell as drawn (geomorphed, as terrain_tile.vert does), which the two triangles between
    // them do not exceed.
    double last_m = 0.0;
    double ground_m = std::numeric_limits<double>::infinity();  // no tile under the eye: no horizon
    m_floors.clear();
    for (GpuTile* g : tiles) {
        const glm::dvec2 at = glm::dvec2(eye) - glm::dvec2(g->origin);  // the eye, tile-local
        const double farthest = glm::length(glm::max(glm::abs(at), glm::abs(at - double(g->size_m))));
        last_m = std::max(last_m, farthest);
        // terrain_lod.cpp morphedHeight(): level j + 1 counts where slots 0..j can morph.
        const double morph_farthest = std::sqrt(farthest * farthest + double(g->morph.eye_dz_m) * g->morph.eye_dz_m);
        int levels = 0;
        while (levels < kMorphLevels && g->morph.end_m[levels] > g->morph.start_m[levels] &&
               morph_farthest > g->morph.start_m[levels]) {
            ++levels;
        }
        if (levels != g->floor_levels) {
            g->floor = terrainFloor(glm::dvec2(g->origin), g->size_m, g->grid_size, g->heights,
                                    std::span(g->ancestor_heights).first(static_cast<std::size_t>(levels)));
            g->floor_levels = levels;
        }
        m_floors.push_back(&g->floor);
        if (g->grid_size >= 2 && at.x >= 0.0 && at.y >= 0.0 && at.x <= g->size_m && at.y <= g->size_m) {
            ground_m = g->highestDrawnAround(at) + 0.5;  // float rounding in the shader
        }
    }
    constexpr int kBins = 160;
    m_horizon.build(eye, ground_m, m_floors, az_from, az_to, kBins, last_m);
    m_stats.horizon_ms = msSince(t0);
}

void MapRenderer::cullRoads(const MapFrame& frame, const glm::mat4& projection, int height,
                            const std::vector<GpuTile*>& tiles, bool hidden) {
    // A quad reaches at most half the widest footprint (casing included) beyond its end points.
    const RoadStyle& rs = m_style.roads;
    const float half_width = widestHalfWidth(rs);
    const float focal_px = projection[1][1] * 0.5f * static_cast<float>(height);
    if (hidden) buildHorizon(frame, projection, tiles);
    const bool test_hidden = hidden && !m_horizon.empty();
    const float widening_px = roadWideningPx(m_style);
    const double keep = 1.0 - rs.z_offset_alpha;  // the roads' view-space scale (seed 3.6.2)
    std::size_t blocks_hidden = 0;
    // Whether a piece's quads can show: not left out of this view (seed 7.3: from where
    // roads_geo.vert narrows its class to nothing, measured at the piece's middle as there), and
    // in it.
    std::array<float, kStyledRoadClasses> gone_m2{};
    for (std::size_t c = 0; c < gone_m2.size(); ++c) gone_m2[c] = m_selection[c].goneFromM() * m_selection[c].goneFromM();
    auto shows = [&](const RoadInstance& r, glm::vec3 eye, const PieceFrustum& frustum) {
        const glm::vec3 d = 0.5f * (r.p0 + r.p1) - eye;
        const auto c = static_cast<std::size_t>(std::clamp(static_cast<int>(r.road_class + 0.5f), 0, kStyledRoadClasses - 1));
        return glm::dot(d, d) < gone_m2[c] && frustum.holds(r, eye, half_width, rs);
    };
    m_road_indices.clear();
    std::vector<std::uint32_t> drawn;  // per block: the road level bit, 0 outside the view
    for (GpuTile* g : tiles) {
        g->visible_first = g->visible_casing_first = static_cast<GLsizei>(m_road_indices.size() / 6);
        g->visible_count = 0;
        if (g->road_pieces.empty()) continue;
        const glm::vec3 eye(frame.camera.eye - g->origin);
        const PieceFrustum frustum(g->road_cull);
        drawn.assign(g->road_blocks.size(), 0u);
        for (std::size_t b = 0; b < g->road_blocks.size(); ++b) {
            const BlockExtent& e = g->road_blocks[b];
            const QuadReach quads = quadReach(eye, e, half_width, rs);
            if (frame.layers.cull_blocks && !quadsInView(g->road_cull, e, quads.reach_m)) continue;
            if (test_hidden) {
                // Every quad drawn from the block's pieces lies in its extent grown by their
                // reach, the least-width widening (pixels at the farthest distance) and a metre.
                const double reach = quads.reach_m + widening_px * quads.farthest_m / focal_px + 1.0f;
                if (m_horizon.hides(g->origin + glm::dvec3(e.min) - reach, g->origin + glm::dvec3(e.max) + reach, keep)) {
                    ++blocks_hidden;
                    continue;
                }
            }
            // The level from the block's nearest point (its extent holds every level's pieces).
            const float distance = glm::length(eye - glm::clamp(eye, e.min, e.max));
            drawn[b] = 1u << (frame.layers.road_lod ? roadLodLevel(distance, focal_px, kRoadLodErrorPx) : 0);
        }
        // The casing pass starts at the first class that has a casing (bridges always have one).
        GLsizei casing_from = g->bridge_first;
        for (int c = 0; c < kStyledRoadClasses; ++c) {
            if (m_style.roads.classes[c].casing_m > 0.0f) casing_from = std::min(casing_from, g->class_first[c]);
        }
        bool casing_found = false;
        for (const BlockRun& run : g->road_runs) {
            if (!(drawn[run.block] & run.lods)) continue;
            if (!casing_found && static_cast<GLsizei>(run.first) >= casing_from) {
                casing_found = true;
                g->visible_casing_first = g->visible_first + g->visible_count;
            }
            for (std::uint32_t q = run.first; q < run.first + run.count; ++q) {
                if (frame.layers.cull_blocks && !shows(g->road_pieces[q], eye, frustum)) continue;
                for (const std::uint32_t i : kQuadIndices) m_road_indices.push_back(4 * q + i);
                ++g->visible_count;
            }
        }
        if (!casing_found) g->visible_casing_first = g->visible_first + g->visible_count;
    }
    m_stats.road_blocks_hidden = blocks_hidden;
}

void MapRenderer::uploadRoadIndices() {
    // Every road vertex array has this buffer bound (upload()); new storage each frame.
    glBindVertexArray(0);
    glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, m_road_index_buffer);
    glBufferData(GL_ELEMENT_ARRAY_BUFFER, static_cast<GLsizeiptr>(m_road_indices.size() * sizeof(std::uint32_t)),
                 m_road_indices.data(), GL_STREAM_DRAW);
}

std::size_t MapRenderer::drawRoads(ShaderProgram& program, int pass, const glm::mat4& projection,
                                   const std::vector<GpuTile*>& tiles) {
    setRoadUniforms(program, pass, false, projection);
    std::size_t drawn = 0;
    for (GpuTile* g : tiles) {
        const GLsizei first = pass == 0 ? g->visible_casing_first : g->visible_first;
        const GLsizei count = g->visible_first + g->visible_count - first;
        if (count <= 0) continue;
        glUniformMatrix4fv(program.uniform("u_view"), 1, GL_FALSE, glm::value_ptr(g->view));
        glUniformMatrix4fv(program.uniform("u_view_projection"), 1, GL_FALSE, glm::value_ptr(g->view_projection));
        glBindVertexArray(g->roads_vao);
        glDrawElements(GL_TRIANGLES, 6 * count, GL_UNSIGNED_INT,
                       reinterpret_cast<const void*>(static_cast<std::size_t>(first) * 6 * sizeof(std::uint32_t)));
        drawn += static_cast<std::size_t>(count);
    }
    return drawn;
}

void MapRenderer::drawRoute(ShaderProgram& program, int pass, const MapFrame& frame, const glm::mat4& projection,
                            const std::vector<GpuTile*>& tiles) {
    setRoadUniforms(program, pass, true, projection);
    glUniform1f(program.uniform("u_route_progress"), static_cast<float>(frame.route_progress_m));
    for (const GpuTile* g : tiles) {
        if (!g->route_count || !g->route_in_view) continue;
        glUniformMatrix4fv(program.uniform("u_view"), 1, GL_FALSE, glm::value_ptr(g->view));
        glUniformMatrix4fv(program.uniform("u_view_projection"), 1, GL_FALSE, glm::value_ptr(g->view_projection));
        glBindVertexArray(g->route_vao);
        m_quad_indices.draw(0, g->route_count);
    }
}

void MapRenderer::setRoadUniforms(ShaderProgram& p, int pass, bool route, const glm::mat4& projection) {
    glUniformMatrix4fv(p.uniform("u_projection"), 1, GL_FALSE, glm::value_ptr(projection));
    const RoadStyle& rs = m_style.roads;
    setRoadClassUniforms(p, rs, m_selection);
    glUniform1i(p.uniform("u_pass"), pass);
    glUniform1i(p.uniform("u_whole_caps"), m_whole_caps ? 1 : 0);
    glUniform1f(p.uniform("u_short_half_length"), kShortPieceHalfLength);
    glUniform3f(p.uniform("u_min_width"), std::max(rs.min_width_px, 0.0f), m_viewport.x, m_viewport.y);
    glUniform1i(p.uniform("u_route"), route ? 1 : 0);
    glUniform1f(p.uniform("u_route_width"), m_style.route_width_m);
    glUniform1f(p.uniform("u_route_casing_m"), kRouteCasingFraction * m_style.route_width_m);
    glUniform3fv(p.uniform("u_route_color"), 1, glm::value_ptr(m_style.route_color));
    glUniform3fv(p.uniform("u_route_casing"), 1, glm::value_ptr(m_style.route_casing));
    // The route sits above the roads: a slightly larger view-space offset (seed 3.6.2).
    glUniform3f(p.uniform("u_scale"), rs.scale_threshold_m, rs.max_scale, rs.z_offset_alpha * (route ? 1.5f : 1.0f));
}

void MapRenderer::evict() {
    const auto keep = static_cast<std::size_t>(std::max(m_options.tile_resource_cache, 1));
    if (m_tiles.size() <= keep) return;
    // The targets render one after another, so a tile is in use while any target drew it in its
    // latest frame, not only the target of this frame: evicting the other displays' tiles would
    // re-upload them on their next frame. A target that stopped rendering (no client) for
    // kIdleRenders renders no longer holds its tiles.
    constexpr std::uint64_t kIdleRenders = 256;
    std::uint64_t in_use_from = m_frame;
    for (const auto& [key, frame] : m_target_frame) {
        if (m_frame - frame < kIdleRenders) in_use_from = std::min(in_use_from, frame);
    }
    std::vector<std::pair<std::uint64_t, std::uint64_t>> by_age;  // last_used, key
    for (const auto& [key, t] : m_tiles) {
        if (t->last_used < in_use_from) by_age.emplace_back(t->last_used, key);
    }
    std::sort(by_age.begin(), by_age.end());
    for (std::size_t i = 0; i < by_age.size() && m_tiles.size() > keep; ++i) m_tiles.erase(by_age[i].second);
}

void MapRenderer::drawTerrain(const MapFrame& frame, const glm::mat4& projection, const glm::vec3& light,
                              const std::vector<GpuTile*>& tiles) {
    for (ShaderProgram* p : {&m_terrain, &m_terrain_cover[0], &m_terrain_cover[1]}) {
        glUseProgram(p->id());
        glUniformMatrix4fv(p->uniform("u_projection"), 1, GL_FALSE, glm::value_ptr(projection));
        glUniform3fv(p->uniform("u_light_dir"), 1, glm::value_ptr(light));
        glUniform3fv(p->uniform("u_sky_color"), 1, glm::value_ptr(m_style.sky_color));
        glUniform2f(p->uniform("u_fog_range"), m_style.fog_start_m, m_style.fog_end_m);
        glUniform1f(p->uniform("u_brightness"), m_style.brightness);
        glUniform1i(p->uniform("u_land_cover"), 0);
        glUniform1i(p->uniform("u_cover1"), 1);
        glUniform1i(p->uniform("u_cover2"), 2);
    }
    const ShaderProgram* bound = nullptr;
    for (GpuTile* g : tiles) {
        const glm::vec2 eye(static_cast<float>(frame.camera.eye.x - g->origin.x),
                            static_cast<float>(frame.camera.eye.y - g->origin.y));
        // Land cover of the levels each block of the tile reaches (morphing with the surface);
        // an ancestor with no land cover here shows none, one not resident is stood in for by
        // the next finer level.
        std::array<GLuint, 3> cover{m_empty_texture, m_empty_texture, m_empty_texture};
        const bool morph_cover = frame.layers.land_cover && g->morph_ancestors[0];
        if (frame.layers.land_cover) {
            if (g->land_cover) cover[0] = g->land_cover;
            if (g->ancestor_cover[0]) cover[1] = g->ancestor_cover[0];
            cover[2] = !g->morph_ancestors[1] ? cover[1] : (g->ancestor_cover[1] ? g->ancestor_cover[1] : m_empty_texture);
        }
        glBindVertexArray(g->terrain_vao);
        std::array<bool, 3> has_tile_uniforms{};  // per program: plain, 2 levels, 3 levels
        // Blocks outside the view are skipped; consecutive ones that need the same land-cover
        // levels are one draw.
        auto visible = [&](const TerrainBlock& k) { return boxInView(g->view_projection, k); };
        auto levelsOf = [&](const TerrainBlock& k) {
            return morph_cover ? coverLevels(g->morph, eye, k.min, k.max) : CoverLevels{};
        };
        // Nearest blocks first, like the tiles (a tile's hills hide its farther blocks before
        // they are shaded); a block that follows its predecessor in the index buffer and needs
        // the same levels joins its draw.
        m_block_order.resize(g->terrain_blocks.size());
        std::iota(m_block_order.begin(), m_block_order.end(), std::size_t{0});
        auto distance2 = [&](std::size_t i) {
            const glm::vec2 d = 0.5f * (g->terrain_blocks[i].min + g->terrain_blocks[i].max) - eye;
            return glm::dot(d, d);
        };
        std::sort(m_block_order.begin(), m_block_order.end(),
                  [&](std::size_t a, std::size_t c) { return distance2(a) < distance2(c); });
        for (std::size_t b = 0; b < m_block_order.size();) {
            const std::size_t first_index = m_block_order[b++];
            const TerrainBlock& first = g->terrain_blocks[first_index];
            if (!visible(first)) continue;
            const CoverLevels levels = levelsOf(first);
            std::uint32_t count = first.count;
            for (std::size_t last = first_index; b < m_block_order.size() && m_block_order[b] == last + 1; ++b, ++last) {
                const TerrainBlock& next = g->terrain_blocks[m_block_order[b]];
                if (!visible(next) || !(levelsOf(next) == levels)) break;
                count += next.count;
            }
            m_stats.terrain_triangles += count / 3;
            const int n = levels.coarsest - levels.finest + 1;
            ShaderProgram& p = n == 1 ? m_terrain : m_terrain_cover[n - 2];
            if (bound != &p) {
                glUseProgram(p.id());
                bound = &p;
            }
            if (!has_tile_uniforms[static_cast<std::size_t>(n - 1)]) {
                has_tile_uniforms[static_cast<std::size_t>(n - 1)] = true;
                glUniformMatrix4fv(p.uniform("u_view"), 1, GL_FALSE, glm::value_ptr(g->view));
                glUniform1f(p.uniform("u_tile_size"), g->size_m);
                glUniform4fv(p.uniform("u_morph_start"), 1, g->morph.start_m.data());
                glUniform4fv(p.uniform("u_morph_end"), 1, g->morph.end_m.data());
                glUniform1f(p.uniform("u_morph_eye_dz"), g->morph.eye_dz_m);
                glUniform2fv(p.uniform("u_morph_eye"), 1, glm::value_ptr(eye));
            }
            if (n > 1) glUniform2f(p.uniform("u_cover_slot"), levels.finest == 0 ? 1.0f : 0.0f, levels.finest == 0 ? 0.0f : 1.0f);
            for (int k = n - 1; k >= 0; --k) {
                glActiveTexture(static_cast<GLenum>(GL_TEXTURE0 + k));
                glBindTexture(GL_TEXTURE_2D, cover[static_cast<std::size_t>(levels.finest + k)]);
            }
            glDrawElements(GL_TRIANGLES, static_cast<GLsizei>(count), g->terrain_index_type,
                           reinterpret_cast<const void*>(std::size_t{first.first} * indexBytes(g->terrain_index_type)));
        }
    }
}

void MapRenderer::markOutlineCells(const MapFrame& frame, const glm::mat4& projection, int width, int height,
                                   const std::vector<GpuTile*>& tiles) {
    const auto t0 = Clock::now();
    m_cells.reset(width, height, kOutlineCellPx, kOutlineReachPx);
    const RoadStyle& rs = m_style.roads;
    QuadShape shape{0.0f, rs.scale_threshold_m, rs.max_scale, rs.z_offset_alpha, rs.min_width_px, 0.0f};
    // Roads: the pieces cullRoads kept, each with its widest pass (fill and casing).
    for (const GpuTile* g : tiles) {
        if (!frame.layers.roads) break;
        m_cells.setView(g->view, projection);
        for (GLsizei k = g->visible_first; k < g->visible_first + g->visible_count; ++k) {
            const RoadInstance& r = g->road_pieces[m_road_indices[6 * static_cast<std::size_t>(k)] / 4];
            const RoadClassStyle& c = rs.of(static_cast<int>(r.road_class + 0.5f));
            shape.width_m = c.outerWidth();
            shape.fill_width_m = c.width_m;
            m_cells.markQuad(r.p0, r.p1, shape, m_whole_caps ? glm::vec2(1.0f) : r.cap_reach);
        }
    }
    // The route with its casing and its larger offset (setRoadUniforms), as drawn this frame.
    if (frame.layers.route && frame.route) {
        shape.width_m = routeOuterWidth(m_style.route_width_m);
        shape.fill_width_m = m_style.route_width_m;
        shape.z_offset_alpha = 1.5f * rs.z_offset_alpha;
        for (const GpuTile* g : tiles) {
            if (!g->route_count || !g->route_in_view) continue;
            m_cells.setView(g->view, projection);
            for (const RoadInstance& r : g->route_instances) m_cells.markQuad(r.p0, r.p1, shape);
        }
    }
    filterCellVertices();
    // The packing pass's rectangles: cells in groups of four along a row, so that its texels
    // (one per cell and row) fill llvmpipe's 4 x 4 blocks; a block costs the same, covered in
    // part or whole.
    m_pack_first = m_cell_vertices.size();
    for (const CellRect& r : m_cells.rects(kOutlinePackGroup)) addCellRect(r);
    m_cell_ms = msSince(t0);
}

void MapRenderer::filterCellVertices() {
    m_cell_vertices.clear();
    m_cell_pixels = 0;
    for (const CellRect& r : m_cells.rects()) {
        m_cell_pixels += static_cast<std::size_t>(r.x1 - r.x0) * static_cast<std::size_t>(r.y1 - r.y0);
        addCellRect(r);
    }
}

void MapRenderer::addCellRect(const CellRect& r) {
    // Whole cells even at the right edge of the screen (the GPU clips the overhang): the packing
    // pass turns each into a column of packed texels.
    const int x1 = (r.x1 + kOutlineCellPx - 1) / kOutlineCellPx * kOutlineCellPx;
    const glm::vec2 lo(static_cast<float>(r.x0), static_cast<float>(r.y0)), hi(static_cast<float>(x1), static_cast<float>(r.y1));
    m_cell_vertices.insert(m_cell_vertices.end(), {lo, {hi.x, lo.y}, {lo.x, hi.y}, {lo.x, hi.y}, {hi.x, lo.y}, hi});
}

GLuint MapRenderer::markEdgeCells(const RenderTarget& target) {
    // On llvmpipe the read is a copy in memory once the roads are rasterized (the packing pass
    // would wait for them too); finding the edges costs a multiply per 8 pixels and a few bit
    // operations per 64. The filter then reads one texel per pixel, over the cells that hold an
    // edge only.
    target.readMask(m_mask_bytes);
    const auto t0 = Clock::now();
    const int w = target.width(), h = target.height(), groups = target.packedMaskWidth();
    m_edge_mask.resize(static_cast<std::size_t>(groups) * static_cast<std::size_t>(h));
    outlineEdges(m_mask_bytes.data(), w, h, m_edge_mask.data());
    m_cells.reset(w, h, kOutlineCellPx, 0.0f);
    m_cells.markEdges(m_edge_mask.data(), groups);
    filterCellVertices();
    m_pack_first = m_cell_vertices.size();  // no packing pass
    m_cell_ms = msSince(t0);
    return target.uploadPackedMask(m_edge_mask.data());
}

std::size_t MapRenderer::drawBuildings(ShaderProgram& p, const MapFrame& frame, const glm::mat4& projection,
                                       const std::vector<GpuTile*>& tiles) {
    glUniformMatrix4fv(p.uniform("u_projection"), 1, GL_FALSE, glm::value_ptr(projection));
    glUniform3fv(p.uniform("u_light_dir"), 1, glm::value_ptr(glm::normalize(m_style.light_dir)));
    glUniform3fv(p.uniform("u_sky_color"), 1, glm::value_ptr(m_style.sky_color));
    glUniform2f(p.uniform("u_fog_range"), m_style.fog_start_m, m_style.fog_end_m);
    glUniform1f(p.uniform("u_brightness"), m_style.brightness);
    glUniform1f(p.uniform("u_cull_ratio"), m_style.building_cull_ratio);
    std::size_t drawn = 0;
    for (const GpuTile* g : tiles) drawn += drawBuildingsOf(p, frame, *g);
    return drawn;
}

std::size_t MapRenderer::drawBuildingsOf(ShaderProgram& program, const MapFrame& frame, const GpuTile& g) {
    if (!g.building_index_count) return 0;
    glUniformMatrix4fv(program.uniform("u_view"), 1, GL_FALSE, glm::value_ptr(g.view));
    glBindVertexArray(g.buildings_vao);
    // The blocks in view, consecutive ones in one draw.
    auto visible = [&](const BlockRun& run) {
        const BlockExtent& e = g.building_blocks[run.block];
        return !frame.layers.cull_blocks || boxInView(g.view_projection, e.min, e.max);
    };
    std::size_t drawn = 0;
    for (std::size_t r = 0; r < g.building_runs.size();) {
        if (!visible(g.building_runs[r++])) continue;
        const std::uint32_t first = g.building_runs[r - 1].first;
        std::uint32_t count = g.building_runs[r - 1].count;
        for (; r < g.building_runs.size() && visible(g.building_runs[r]); ++r) count += g.building_runs[r].count;
        glDrawElements(GL_TRIANGLES, static_cast<GLsizei>(count), GL_UNSIGNED_INT,
                       reinterpret_cast<const void*>(std::size_t{first} * sizeof(std::uint32_t)));
        drawn += count / 3;
    }
    return drawn;
}

void MapRenderer::render(const MapFrame& frame, const RenderTarget& target) {
    m_whole_caps = !frame.layers.trim_joint_caps;
    m_viewport = {static_cast<float>(target.width()), static_cast<float>(target.height())};
    ++m_frame;
    m_target_frame[m_target_key] = m_frame;  // this target's latest frame (evict())
    m_stats = {};
    const auto t_frame = Clock::now();
    auto lap = [&](double& slot, Clock::time_point& t) {
        if (!m_options.profile_passes) return;
        glFinish();
        slot = msSince(t);
        t = Clock::now();
    };
    Clock::time_point t = Clock::now();

    // Uploads (bounded per frame so a burst of new tiles does not stall one frame).
    std::vector<GpuTile*> tiles;
    tiles.reserve(frame.tiles.size());
    int uploads = 0;
    for (std::size_t ti = 0; ti < frame.tiles.size(); ++ti) {
        const auto& tile = frame.tiles[ti];
        if (!tile) continue;
        const TileMorph* morph = ti < frame.tile_morph.size() ? &frame.tile_morph[ti] : nullptr;
        auto it = m_tiles.find(tile->id.key());
        GpuTile* gpu = (it != m_tiles.end() && it->second->source == tile.get()) ? it->second.get() : nullptr;
        // Re-upload when a geomorph target (an ancestor tile) is new to this tile; until the
        // upload budget allows, the tile is drawn with the targets it has.
        bool new_targets = false;
        for (std::size_t j = 0; gpu && morph && j < kMorphLevels; ++j) {
            const map::Tile* a = morph->ancestors[j].get();
            if (a && a != gpu->morph_ancestors[j]) new_targets = true;
        }
        if (!gpu || new_targets) {
            if (m_options.max_tile_uploads_per_frame > 0 && uploads >= m_options.max_tile_uploads_per_frame) {
                if (!gpu) {
                    ++m_stats.tiles_pending;
                    continue;
                }
            } else {
                gpu = upload(tile, morph);
                ++uploads;
            }
        }
        gpu->morph = morph ? *morph : TileMorph{};
        gpu->morph.ancestors = {};  // identities kept in morph_ancestors; do not extend the tiles' life
        gpu->last_used = m_frame;
        tiles.push_back(gpu);
    }
    m_ancestor_cover_triangles.clear();  // only for the uploads above, while `frame` holds the tiles
    m_stats.tiles_uploaded = static_cast<std::size_t>(uploads);
    m_stats.flat_tiles = m_stats_flat_tiles;
    m_stats.new_flat_tiles = std::move(m_new_flat_tiles);
    m_new_flat_tiles.clear();
    m_stats.tiles_drawn = tiles.size();
    // Nearest tiles first: the terrain and buildings of near tiles then hide most of what lies
    // behind them before it is shaded (llvmpipe tests depth before running the fragment shader).
    {
        const glm::dvec3 eye = frame.camera.eye;
        auto distance2 = [&](const GpuTile* g) {
            const glm::dvec2 c = glm::dvec2(g->origin) + 0.5 * static_cast<double>(g->size_m);
            const glm::dvec2 d = c - glm::dvec2(eye);
            return d.x * d.x + d.y * d.y;
        };
        std::stable_sort(tiles.begin(), tiles.end(),
                         [&](const GpuTile* a, const GpuTile* b) { return distance2(a) < distance2(b); });
    }
    const double aspect = static_cast<double>(target.width()) / target.height();
    const glm::mat4 projection = frame.camera.projection(aspect);
    m_selection = selectionFades(m_style.roads, projection[1][1] * 0.5f * static_cast<float>(target.height()),
                                 frame.layers.road_selection);
    // Clip x and y scaled down so that the planes x = +-w, y = +-w lie the widening further out.
    const float widening_px = roadWideningPx(m_style);
    const glm::mat4 grow = glm::scale(glm::mat4(1.0f), glm::vec3(1.0f / (1.0f + 2.0f * widening_px / static_cast<float>(target.width())),
                                                                  1.0f / (1.0f + 2.0f * widening_px / static_cast<float>(target.height())), 1.0f));
    for (GpuTile* g : tiles) {
        g->view = frame.camera.viewRelativeTo(g->origin);
        g->view_projection = projection * g->view;
        g->road_cull = grow * g->view_projection;
    }
    if (frame.route && frame.layers.route) {
        for (GpuTile* g : tiles) updateRoute(*g, frame);
    }
    lap(m_stats.uploads_ms, t);

    const glm::vec3 light = glm::normalize(m_style.light_dir);
    SvRoads* sv = SvRoads::forFrame(m_sv_roads, frame, target);  // shadow-volume roads (seed 3.5), else null
    // The road pieces in view are picked on another thread while this one sets up the buildings
    // and the terrain: llvmpipe rasterizes only after the whole scene is set up, so a core is
    // free meanwhile. The culling writes only the tiles' visible_* and m_road_indices, which
    // nothing before the road passes reads.
    // Hidden blocks are left out where the whole terrain in view is drawn (none waits for upload).
    const bool cull_hidden = frame.layers.cull_hidden_roads && frame.layers.terrain && m_stats.tiles_pending == 0;
    if (frame.layers.roads) m_side.start([&] { cullRoads(frame, projection, target.height(), tiles, cull_hidden); });
    const SideTask::Scope side_scope(m_side);
    // Where the screen-space outlines can be (seed 3.6.3), worked out on the other thread after
    // the culling, while this one sets up the road passes. It reads what the culling and
    // updateRoute wrote and nothing the passes change.
    const bool outlines = frame.layers.outlines && (frame.layers.roads || frame.layers.route);
    const bool outline_cells = outlines && frame.layers.outlines_near_roads && !sv;
    // On a software rasterizer the cells come from the road mask itself, read back after the
    // roads (markEdgeCells); elsewhere from the quads (markOutlineCells), and the GPU packs.
    using OutlineMask = MapLayers::OutlineMask;
    const OutlineMask mask_at = frame.layers.outline_mask;
    const bool edges_on_cpu = outline_cells && (mask_at == OutlineMask::Cpu || (mask_at == OutlineMask::Auto && m_software)) &&
                              target.readsMaskBytes();
    target.clear(m_style.sky_color.r, m_style.sky_color.g, m_style.sky_color.b);
    target.bindForDrawing(false);
    glDisable(GL_BLEND);
    glEnable(GL_DEPTH_TEST);
    glDepthMask(GL_TRUE);

    // Buildings before the roads, which test against terrain and buildings without writing depth
    // (junctions stay clean, buildings hide the roads behind them); and before the terrain where
    // nothing needs the terrain alone: the terrain behind them then fails the depth test before it
    // is shaded (llvmpipe tests depth before the fragment shader). Glowing roads and the label
    // aura (seed 5.5) keep the terrain's depth (the aura also its colour) before the buildings for
    // runOcclusionEffects(); the shadow-volume roads keep it in a target of their own (SvRoads).
    const bool terrain_alone = sv || wantsGlow(frame.layers) || wantsAura(frame.layers);
    auto buildings = [&] {
        glDepthFunc(GL_LESS);
        glEnable(GL_CULL_FACE);
        glUseProgram(m_buildings.id());
        m_stats.building_triangles += drawBuildings(m_buildings, frame, projection, tiles);
        lap(m_stats.buildings_ms, t);
    };
    if (frame.layers.buildings && !terrain_alone) buildings();

    // Terrain.
    if (frame.layers.terrain) {
        if (sv) sv->beginTerrain(target);  // + the terrain depth target (seed 3.5.2)
        glDepthFunc(GL_LESS);
        glEnable(GL_CULL_FACE);
        glCullFace(GL_BACK);
        drawTerrain(frame, projection, light, tiles);
        if (sv) sv->endTerrain(target);
        lap(m_stats.terrain_ms, t);
    }

    if (wantsGlow(frame.layers) || wantsAura(frame.layers)) {
        if (!m_effects) m_effects = std::make_unique<OcclusionEffects>();
        m_effects->captureTerrainDepth(target, wantsGlow(frame.layers), wantsAura(frame.layers));
    }

    if (frame.layers.buildings && terrain_alone) buildings();  // after the terrain (see above)

    if (frame.layers.roads) {
        m_side.wait();  // cullRoads
        uploadRoadIndices();
    }
    if (outline_cells && !edges_on_cpu) {
        m_side.start([&] { markOutlineCells(frame, projection, target.width(), target.height(), tiles); });
    }

    // Roads (seed 3.6.3): no blending, least important first, casing pass then fill pass.
    target.bindForDrawing(true);
    glDisable(GL_CULL_FACE);
    glDepthMask(GL_FALSE);
    glDepthFunc(GL_LEQUAL);
    // With the outline cells from the quads, the road and route pixels also mark kRoadStencilBit
    // for the filter: the same pixels as the mask (drawn, not discarded, depth test passed). Not
    // when multisampled: the filter's stencil test would then be per sample, unlike its mask. Not
    // with the edges found on the CPU, which leave out the road pixels themselves. The full-screen
    // filter stays without either, the reference the cells are tested against.
    const bool mark_roads = outline_cells && target.samples() == 0 && !edges_on_cpu;
    if (mark_roads) {
        glEnable(GL_STENCIL_TEST);
        glStencilMask(kRoadStencilBit);
        glStencilFunc(GL_ALWAYS, kRoadStencilBit, kRoadStencilBit);
        glStencilOp(GL_KEEP, GL_KEEP, GL_REPLACE);
    }
    if (sv) {
        m_stats.road_segments += sv->draw(frame, projection, target, m_style.roads);
        m_stats.sv_roads = true;
        lap(m_stats.sv_roads_ms, t);
    }
    if (frame.layers.roads && !sv) {
        glUseProgram(m_roads.id());
        drawRoads(m_roads, 0, projection, tiles);
        m_stats.road_segments += drawRoads(m_roads, 1, projection, tiles);
        lap(m_stats.roads_ms, t);
    }
    if (frame.layers.route && frame.route) {
        glUseProgram(m_route.id());
        for (int pass = 0; pass < 2; ++pass) drawRoute(m_route, pass, frame, projection, tiles);
        lap(m_stats.route_ms, t);
    }
    if (mark_roads) {
        glDisable(GL_STENCIL_TEST);
        glStencilMask(0xFF);
    }
    glDepthMask(GL_TRUE);
    // Screen-space dark outlines around roads and route (seed 3.6.3). The filter runs only on
    // the screen cells that the road and route quads, grown by its reach, touch, or that hold an
    // edge pixel of the mask read back: most of the frame is away from roads. (Shadow-volume
    // roads have no quads: the whole screen.)
    if (outlines) {
        GLuint edges = 0;
        if (edges_on_cpu) {
            edges = markEdgeCells(target);
            m_stats.outline_mask_on_cpu = true;
        }
        target.resolveMask();
        glDisable(GL_DEPTH_TEST);
        if (outline_cells) {
            m_side.wait();  // markOutlineCells, when it runs
            m_stats.outline_pixels = m_cell_pixels;
            m_stats.outline_cells_ms = m_cell_ms;
            glBindVertexArray(m_cell_vao);
            glBindBuffer(GL_ARRAY_BUFFER, m_cell_vbo);
            glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(m_cell_vertices.size() * sizeof(glm::vec2)),
                         m_cell_vertices.data(), GL_STREAM_DRAW);
            glBindBuffer(GL_ARRAY_BUFFER, 0);
        } else {
            m_stats.outline_pixels = static_cast<std::size_t>(target.width()) * static_cast<std::size_t>(target.height());
            glBindVertexArray(m_empty_vao);
        }
        // Vertices [first, end) of m_cell_vertices: the filter's cells, then the packing pass's.
        auto draw_cells = [](std::size_t first, std::size_t end) {
            if (end > first) glDrawArrays(GL_TRIANGLES, static_cast<GLint>(first), static_cast<GLsizei>(end - first));
        };
        glActiveTexture(GL_TEXTURE0);
        GLuint mask = edges_on_cpu ? edges : target.maskTexture();
        if (mark_roads) {
            // The mask bit-packed over the cells (outline_pack.frag); the rest of the packed
            // texture is 0, as the mask is outside the cells (every road quad lies in them).
            mask = target.bindPackedMask();
            const GLuint zero[4] = {0, 0, 0, 0};
            glClearBufferuiv(GL_COLOR, 0, zero);
            glUseProgram(m_outline_pack.id());
            glBindTexture(GL_TEXTURE_2D, target.maskTexture());
            glUniform1i(m_outline_pack.uniform("u_road_mask"), 0);
            // Pixel x maps to texel x / kPackedMaskPixels: a cell is one column of texels.
            glUniform2f(m_outline_pack.uniform("u_viewport"),
                        static_cast<float>(kPackedMaskPixels * target.packedMaskWidth()),
                        static_cast<float>(target.height()));
            draw_cells(m_pack_first, m_cell_vertices.size());
            target.bindForDrawing(false);
        }
        ShaderProgram& p = edges_on_cpu ? m_outline_edges : mark_roads ? m_outline_packed : outline_cells ? m_outline_cells : m_outline;
        glEnable(GL_BLEND);
        glBlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA);
        glUseProgram(p.id());
        glBindTexture(GL_TEXTURE_2D, mask);
        glUniform1i(p.uniform("u_mask"), 0);
        glUniform3fv(p.uniform("u_outline_color"), 1, glm::value_ptr(m_style.roads.outline));
        glUniform1f(p.uniform("u_strength"), m_style.roads.outline_strength);
        if (outline_cells) {
            glUniform2f(p.uniform("u_viewport"), static_cast<float>(target.width()), static_cast<float>(target.height()));
        }
        if (mark_roads) {
            glEnable(GL_STENCIL_TEST);
            glStencilFunc(GL_NOTEQUAL, kRoadStencilBit, kRoadStencilBit);
            glStencilOp(GL_KEEP, GL_KEEP, GL_KEEP);
        }
        if (outline_cells) {
            draw_cells(0, m_pack_first);
        } else {
            glDrawArrays(GL_TRIANGLES, 0, 3);  // full screen
        }
        glBindTexture(GL_TEXTURE_2D, 0);
        glDisable(GL_BLEND);
        glDisable(GL_STENCIL_TEST);
        lap(m_stats.outlines_ms, t);
    }

    if (!frame.layers.labels) runOcclusionEffects(frame, target, projection, tiles);
    if (!frame.layers.labels) drawArrows(frame, target, projection, tiles);
    // Labels (seed ch. 4, 5.5): after the outlines so they lie above the roads, before the marker,
    // and out of the marker's way.
    const std::optional<MarkerOnScreen> marker = markerOnScreen(frame, target);
    if (frame.layers.labels) {
        if (!m_label_text) m_label_text = std::make_shared<LabelText>();
        if (!m_label_pass) m_label_pass = std::make_unique<LabelPass>(m_label_text);
        m_tile_labels.clear();
        for (const GpuTile* g : tiles) {
            HeightGrid grid;
            if (g->grid_size >= 2 && g->heights.size() == static_cast<std::size_t>(g->grid_size) * g->grid_size) {
                grid = {g->grid_size, g->size_m / (g->grid_size - 1), g->heights.data()};
            }
            m_tile_labels.push_back({g->source, g->origin, g->label_points, grid, g->size_m});
        }
        target.bindForDrawing(false);
        const std::span<const glm::vec2> keep_out = marker ? std::span<const glm::vec2>(marker->outline) : std::span<const glm::vec2>();
        m_label_pass->layout(frame, m_tile_labels, {target.width(), target.height()}, m_stats, keep_out,
                             m_style.route_width_m);
        runOcclusionEffects(frame, target, projection, tiles);  // seed 5.5.2: composited before the labels
        drawArrows(frame, target, projection, tiles);
        target.bindForDrawing(false);
        m_label_pass->draw({target.width(), target.height()}, m_stats);
        if (frame.layers.measure_label_occlusion) {
            glFinish();  // the frame's drawing so far is the frame's cost, not the measurement's
            const auto t_occlusion = Clock::now();
            m_label_pass->measureOcclusion(target.depthStencilRenderbuffer(), target.samples(),
                                           {target.width(), target.height()}, m_stats);
            target.bindForDrawing(false);
            m_stats.label_occlusion_ms = msSince(t_occlusion);
        }
        double label_gpu_ms = 0;  // labels_ms is the pass's own CPU time; keep it out of marker_ms
        lap(label_gpu_ms, t);
    }

    if (marker) drawMarker(frame, *marker, target);
    lap(m_stats.marker_ms, t);
    if (frame.guidance) {
        if (!m_guidance) m_guidance = std::make_unique<GuidanceOverlayPass>();
        m_guidance->draw(*frame.guidance, m_style, target);
    }

    glBindVertexArray(0);
    glBindTexture(GL_TEXTURE_2D, 0);
    evict();
    m_stats.total_ms = msSince(t_frame);
}

void MapRenderer::runOcclusionEffects(const MapFrame& frame, const RenderTarget& target, const glm::mat4& projection,
                                      const std::vector<GpuTile*>& tiles) {
    const bool glow = wantsGlow(frame.layers), aura = wantsAura(frame.layers);
    if (!m_effects || (!glow && !aura)) return;
    if (m_options.profile_passes) glFinish();
    auto t = Clock::now();
    auto lap = [&](double& slot) {
        if (!m_options.profile_passes) return;
        glFinish();
        slot = msSince(t);
        t = Clock::now();
    };
    if (aura) {
        // seed 5.5.1 step 2: the buildings (with the aura's program) and then the roads and the
        // route over them, as the scene draws them, into the layer behind the labels.
        auto buildings = [&](ShaderProgram& p) { drawBuildings(p, frame, projection, tiles); };
        auto roads = [&] {
            glUseProgram(m_roads.id());
            for (int pass = 0; pass < 2 && frame.layers.roads; ++pass) drawRoads(m_roads, pass, projection, tiles);
            glUseProgram(m_route.id());
            for (int pass = 0; pass < 2 && frame.layers.route && frame.route; ++pass) drawRoute(m_route, pass, frame, projection, tiles);
        };
        std::span<const LabelOccluder> labels;
        if (frame.layers.labels && m_label_pass) labels = m_label_pass->occluders();
        m_effects->aura(target, labels, projection, m_style, buildings, roads);
        lap(m_stats.aura_ms);
    }
    if (glow) {
        // seed 5.5.2: the fill of the roads and the route again, for the hidden parts.
        auto roads = [&](ShaderProgram& p) {
            if (frame.layers.roads) drawRoads(p, 1, projection, tiles);
            if (frame.layers.route && frame.route) drawRoute(p, 1, frame, projection, tiles);
        };
        m_effects->glow(target, frame.layers, m_style, roads);
        lap(m_stats.glow_ms);
    }
    target.bindForDrawing(false);
}

void MapRenderer::drawArrows(const MapFrame& frame, const RenderTarget& target, const glm::mat4& projection,
                             const std::vector<GpuTile*>& tiles) {
    if (!ManeuverArrowPass::wanted(frame)) return;
    if (!m_arrows) m_arrows = std::make_unique<ManeuverArrowPass>();
    std::vector<ArrowTile> arrow_tiles(tiles.size());
    for (std::size_t i = 0; i < tiles.size(); ++i) {
        const GpuTile& g = *tiles[i];
        ArrowTile& a = arrow_tiles[i];
        a.origin = g.origin;
        a.morph = g.morph;
        a.view = g.view;
        if (g.grid_size < 2) continue;
        const double spacing = g.size_m / double(g.grid_size - 1);
        a.grid = {g.grid_size, spacing, g.heights.data()};
        for (std::size_t j = 0; j < a.ancestors.size(); ++j) a.ancestors[j] = {g.grid_size, spacing, g.ancestor_heights[j].data()};
    }
    const GLuint terrain_depth = m_effects && wantsGlow(frame.layers) ? m_effects->terrainDepth(target) : 0;
    m_arrows->draw(frame, m_style, target, projection, arrow_tiles, terrain_depth);
}

std::optional<MapRenderer::MarkerOnScreen> MapRenderer::markerOnScreen(const MapFrame& frame, const RenderTarget& target) const {
    if (!frame.layers.marker || !frame.marker) return std::nullopt;
    const MarkerState& m = *frame.marker;
    const double aspect = static_cast<double>(target.width()) / target.height();
    const glm::mat4 vp = frame.camera.projection(aspect) * frame.camera.viewRelativeTo(m.position);
    MarkerOnScreen out;
    out.anchor_clip = vp * glm::vec4(0.0f, 0.0f, 0.0f, 1.0f);
    if (out.anchor_clip.w <= 0.0f) return std::nullopt;  // behind the camera
    // Heading as it appears on screen: project a point a few metres ahead.
    const double rad = glm::radians(m.heading_deg);
    const glm::vec4 ahead = vp * glm::vec4(static_cast<float>(5.0 * std::sin(rad)), static_cast<float>(5.0 * std::cos(rad)), 0.0f, 1.0f);
    const glm::vec2 a = glm::vec2(out.anchor_clip) / out.anchor_clip.w * glm::vec2(target.width(), target.height());
    const glm::vec2 b = glm::vec2(ahead) / ahead.w * glm::vec2(target.width(), target.height());
    const glm::vec2 dir = b - a;
    out.screen_dir = glm::length(dir) > 1e-4f ? glm::normalize(dir) : glm::vec2(0.0f, 1.0f);
    // Its outline as drawn (screen pixels, y down): the arrow's convex hull (tip and the two back
    // corners) at the size of its dark outline; labels keep out of it, the metrics measure it.
    const glm::vec2 ndc = glm::vec2(out.anchor_clip) / out.anchor_clip.w;
    const glm::vec2 center((ndc.x * 0.5f + 0.5f) * static_cast<float>(target.width()),
                           (0.5f - ndc.y * 0.5f) * static_cast<float>(target.height()));
    const glm::vec2 side(out.screen_dir.y, -out.screen_dir.x);
    const float size = m_style.marker_size_px + 3.0f;
    for (const glm::vec2 corner : {glm::vec2(0.0f, 1.0f), glm::vec2(0.6f, -0.7f), glm::vec2(-0.6f, -0.7f)}) {
        const glm::vec2 up = (corner.x * side + corner.y * out.screen_dir) * size;  // y up
        out.outline.push_back(center + glm::vec2(up.x, -up.y));
    }
    return out;
}

void MapRenderer::drawMarker(const MapFrame& frame, const MarkerOnScreen& marker, const RenderTarget& target) {
    const MarkerState& m = *frame.marker;
    m_stats.drawn_marker.outline = marker.outline;
    target.bindForDrawing(false);
    glDisable(GL_DEPTH_TEST);
    glDisable(GL_CULL_FACE);
    glUseProgram(m_marker.id());
    glUniform4fv(m_marker.uniform("u_anchor_clip"), 1, glm::value_ptr(marker.anchor_clip));
    glUniform2fv(m_marker.uniform("u_screen_dir"), 1, glm::value_ptr(marker.screen_dir));
    glUniform2f(m_marker.uniform("u_viewport"), static_cast<float>(target.width()), static_cast<float>(target.height()));
    // Outline first (slightly larger, dark), then the fill.
    glBindVertexArray(m_marker_vao);
    const glm::vec4 dark(0.1f, 0.1f, 0.1f, 1.0f);
    glUniform1f(m_marker.uniform("u_size_px"), m_style.marker_size_px + 3.0f);
    glUniform4fv(m_marker.uniform("u_color"), 1, glm::value_ptr(dark));
    glDrawArrays(GL_TRIANGLES, 0, 6);
    glUniform1f(m_marker.uniform("u_size_px"), m_style.marker_size_px);
    const glm::vec4 color = m.stale ? m_style.marker_stale_color : m_style.marker_color;
    glUniform4fv(m_marker.uniform("u_color"), 1, glm::value_ptr(color));
    glDrawArrays(GL_TRIANGLES, 0, 6);
    glEnable(GL_DEPTH_TEST);
}

}  // namespace navmap::render::gl
