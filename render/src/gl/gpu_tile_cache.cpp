// SPDX-License-Identifier: Apache-2.0
#include "gpu_tile_cache.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <exception>
#include <span>
#include <utility>
#include <vector>

#include <glm/gtc/type_ptr.hpp>

#include "frame_context.h"
#include "gl/gl_work.h"
#include "label_pass.h"
#include "navmap/map/ortho/ortho_network.h"
#include "vertex_layout.h"

namespace navmap::render::gl {

namespace {

// Land-cover raster per tile (8 m per texel on 2 km leaf tiles), shared by every display
// profile. RGBA4: land cover is flat class colours and a coverage strength, which 4 bits per
// channel hold; half the memory of RGBA8 (about 0.17 MiB per tile with mipmaps).
int landCoverTextureSize(float) { return 256; }
constexpr int kLandCoverSamples = 4;

// Orthoimage pixels per side (docs/orthoimage.md "In the map"): 512 (4 m per pixel) on tiles of
// the leaf size of the default stores (2 km; up to 2.5 km), which the snail's view sees from a few
// metres, twice the land-cover raster's density; 256 on the coarser levels, which the level of
// detail shows only farther off at about the same size on screen, the density of their land-cover
// raster and of their cover layer.
constexpr double kCloseRangeTileM = 2500.0;
int orthoImageSize(double tile_m) { return tile_m <= kCloseRangeTileM ? 512 : 256; }

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

// Uploads indices into the bound element buffer, as 16-bit values when the vertices allow it;
// returns the GL index type.
GLenum uploadIndices(std::span<const std::uint32_t> indices, std::size_t vertex_count) {
    if (vertex_count <= 0xFFFF) {
        std::vector<std::uint16_t> narrow(indices.begin(), indices.end());
        countedBufferData(GL_ELEMENT_ARRAY_BUFFER, static_cast<GLsizeiptr>(narrow.size() * sizeof(std::uint16_t)),
                          narrow.data(), GL_STATIC_DRAW);
        return GL_UNSIGNED_SHORT;
    }
    countedBufferData(GL_ELEMENT_ARRAY_BUFFER, static_cast<GLsizeiptr>(indices.size() * sizeof(std::uint32_t)),
                      indices.data(), GL_STATIC_DRAW);
    return GL_UNSIGNED_INT;
}

// The terrain with its skirts and geomorph targets (PackedTerrainVertex) into a vertex array.
void uploadTerrain(GpuTile& g, const TileMesh& mesh) {
    glGenVertexArrays(1, &g.terrain_vao);
    glGenBuffers(1, &g.terrain_vbo);
    glGenBuffers(1, &g.terrain_ibo);
    glBindVertexArray(g.terrain_vao);
    glBindBuffer(GL_ARRAY_BUFFER, g.terrain_vbo);
    const std::vector<PackedTerrainVertex> packed = packTerrain(mesh.terrain);
    countedBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(packed.size() * sizeof(PackedTerrainVertex)),
                      packed.data(), GL_STATIC_DRAW);
    // Geomorph targets (terrain_tile.vert): 4 ancestor heights, then 4 normals' x, y as two vec4.
    static_assert(kMorphLevels == 4, "terrain_tile.vert takes 4 ancestor levels");
    using V = PackedTerrainVertex;
    setVertexAttributes(sizeof(V), {{0, 3, GL_FLOAT, offsetof(V, position)},
                                    {1, 2, GL_SHORT, offsetof(V, normal)},
                                    {2, 4, GL_FLOAT, offsetof(V, ancestor_heights)},
                                    {3, 4, GL_SHORT, offsetof(V, ancestor_normals)},
                                    {4, 4, GL_SHORT, offsetof(V, ancestor_normals) + 4 * sizeof(std::int16_t)}});
    glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, g.terrain_ibo);
    g.terrain_index_type = uploadIndices(mesh.terrain_indices, mesh.terrain.size());
    g.terrain_blocks = mesh.terrain_blocks;
}

// The road pieces as quads (quadVertices), their runs per block and where each class starts;
// the vertex array reads `index_buffer` (the pieces in view, RoadPass::cull).
void uploadRoads(GpuTile& g, TileMesh& mesh, GLuint index_buffer) {
    glGenVertexArrays(1, &g.roads_vao);
    glGenBuffers(1, &g.roads_vbo);
    glBindVertexArray(g.roads_vao);
    glBindBuffer(GL_ARRAY_BUFFER, g.roads_vbo);
    const auto quads = quadVertices(mesh.roads);
    countedBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(quads.size() * sizeof(RoadInstance)), quads.data(),
                      GL_STATIC_DRAW);
    setupRoadAttributes();
    glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, index_buffer);  // this frame's pieces in view
    const auto road_count = static_cast<GLsizei>(mesh.roads.size());
    g.road_runs = std::move(mesh.road_runs);
    g.road_blocks = std::move(mesh.road_blocks);
    g.class_first.fill(road_count);
    g.bridge_first = road_count;
    for (GLsizei i = road_count; i-- > 0;) {
        const RoadInstance& r = mesh.roads[static_cast<std::size_t>(i)];
        if (static_cast<int>(r.flags) & map::road_flags::kBridge) {
            g.bridge_first = i;
            continue;
        }
        const int c = std::clamp(static_cast<int>(r.road_class), 0, kStyledRoadClasses - 1);
        g.class_first[static_cast<std::size_t>(c)] = i;
    }
    g.road_pieces = std::move(mesh.roads);
}

// The buildings' vertices and indices, with their runs per block.
void uploadBuildings(GpuTile& g, TileMesh& mesh) {
    glGenVertexArrays(1, &g.buildings_vao);
    glGenBuffers(1, &g.buildings_vbo);
    glGenBuffers(1, &g.buildings_ibo);
    glBindVertexArray(g.buildings_vao);
    glBindBuffer(GL_ARRAY_BUFFER, g.buildings_vbo);
    countedBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(mesh.buildings.size() * sizeof(BuildingVertex)),
                      mesh.buildings.data(), GL_STATIC_DRAW);
    setVertexAttributes(sizeof(BuildingVertex), {{0, 3, GL_FLOAT, offsetof(BuildingVertex, position)},
                                                 {1, 3, GL_FLOAT, offsetof(BuildingVertex, normal)},
                                                 {2, 3, GL_FLOAT, offsetof(BuildingVertex, color)},
                                                 {3, 1, GL_FLOAT, offsetof(BuildingVertex, footprint_m)}});
    glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, g.buildings_ibo);
    countedBufferData(GL_ELEMENT_ARRAY_BUFFER,
                      static_cast<GLsizeiptr>(mesh.building_indices.size() * sizeof(std::uint32_t)),
                      mesh.building_indices.data(), GL_STATIC_DRAW);
    g.building_index_count = static_cast<GLsizei>(mesh.building_indices.size());
    g.building_runs = std::move(mesh.building_runs);
    g.building_blocks = std::move(mesh.building_blocks);
}

}  // namespace

GpuTileCache::GpuTileCache(const RendererOptions& options)
    : m_options(options), m_land_cover(ShaderProgram::fromEmbedded("landcover_raster.vert", "landcover_raster.frag")) {
    glGenFramebuffers(1, &m_raster_fbo);
    glGenBuffers(1, &m_road_index_buffer);
    if (options.warm_up) {
        // The first land-cover raster pays for the driver's code of the multisample resolve and
        // of the mipmap chain: on llvmpipe about 270 ms of shader JIT, which the first map frame
        // would wait for. One triangle on an 8 x 8 raster pays it here (docs/navmapd.md "Start-up").
        const LandCoverVertex triangle[3] = {
            {{0.0f, 0.0f}, glm::vec4(1.0f)}, {{1.0f, 0.0f}, glm::vec4(1.0f)}, {{0.0f, 1.0f}, glm::vec4(1.0f)}};
        const GLuint scratch = rasterizeLandCover(triangle, 8, glm::vec2(0.0f), 1.0f);
        glDeleteTextures(1, &scratch);
    }
    // The weights are read now, as the renderer is made at start-up, never in a frame: the read is
    // bounded (a regular file of the format's size at most, opened without blocking; a FIFO or
    // /dev/zero is refused at once), and whatever the disk does, no frame waits for it.
    if (!m_options.ortho_weights.empty()) {
        try {
            m_ortho_network = map::ortho::loadNetwork(m_options.ortho_weights);
        } catch (const map::ortho::OrthoNetworkError& e) {
            m_ortho_file_problem = e.what();
        }
    }
}

GpuTileCache::~GpuTileCache() {
    m_tiles.clear();
    glDeleteFramebuffers(1, &m_raster_fbo);
    glDeleteFramebuffers(1, &m_raster_ms_fbo);
    glDeleteRenderbuffers(1, &m_raster_ms_rb);
    glDeleteBuffers(1, &m_road_index_buffer);
}

std::span<GpuTile* const> GpuTileCache::acquire(const MapFrame& frame, int target_id, MapFrameStats& stats,
                                                Ground ground) {
    const bool want_ortho = ground == Ground::Orthoimage && frame.layers.land_cover && frame.layers.terrain;
    std::vector<std::pair<GpuTile*, std::shared_ptr<const map::Tile>>> ortho_wanted;
    ++m_frame;
    m_target_frame[target_id] = m_frame;  // this target's latest frame (evict())
    // Uploads (bounded per frame so a burst of new tiles does not stall one frame).
    std::vector<GpuTile*>& tiles = m_drawn;
    tiles.clear();
    tiles.reserve(frame.tiles.size());
    int uploads = 0;
    std::size_t without_layers = 0;  // drawn tiles that cannot have an orthoimage
    for (std::size_t ti = 0; ti < frame.tiles.size(); ++ti) {
        const auto& tile = frame.tiles[ti];
        if (!tile) continue;
        const TileMorph* morph = ti < frame.tile_morph.size() ? &frame.tile_morph[ti] : nullptr;
        auto it = m_tiles.find(tile->id.key());
        GpuTile* gpu = (it != m_tiles.end() && sameTileObject(it->second->source, it->second->source_ref, tile.get()))
                           ? it->second.get()
                           : nullptr;
        // Re-upload when a geomorph target (an ancestor tile) is new to this tile; until the
        // upload budget allows, the tile is drawn with the targets it has.
        bool new_targets = false;
        for (std::size_t j = 0; gpu && morph && j < kMorphLevels; ++j) {
            const map::Tile* a = morph->ancestors[j].get();
            if (a && a != gpu->morph_ancestors[j]) new_targets = true;
        }
        if (!gpu || new_targets) {
            if (!frame.upload_all && m_options.max_tile_uploads_per_frame > 0 &&
                uploads >= m_options.max_tile_uploads_per_frame) {
                if (!gpu) {
                    ++stats.tiles_pending;
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
        if (want_ortho && !gpu->ortho_started && !tile->ortho.empty()) ortho_wanted.emplace_back(gpu, tile);
        if (want_ortho && tile->ortho.empty()) ++without_layers;
    }
    if (without_layers > 0 && !m_no_layers_reported) {
        // Said once: a store compiled without the layers keeps the land cover everywhere.
        m_no_layers_reported = true;
        stats.ortho_problem = std::to_string(without_layers) + " of " + std::to_string(tiles.size()) +
                              " drawn tiles have no orthoimage layers (the store was compiled without "
                              "navmap-compile-ortho --ortho-data): they show the land cover";
    }
    m_ancestor_cover_triangles.clear();  // only for the uploads above, while `frame` holds the tiles
    stats.tiles_uploaded = static_cast<std::size_t>(uploads);
    stats.flat_tiles = m_flat_tiles;
    stats.new_flat_tiles = std::move(m_new_flat_tiles);
    m_new_flat_tiles.clear();
    stats.tiles_drawn = tiles.size();
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
        std::stable_sort(ortho_wanted.begin(), ortho_wanted.end(),
                         [&](const auto& a, const auto& b) { return distance2(a.first) < distance2(b.first); });
    }
    if (want_ortho) updateOrthoimages(ortho_wanted, stats);
    return tiles;
}

OrthoGenerator* GpuTileCache::orthoGenerator() {
    if (m_ortho_tried) return m_ortho.get();
    m_ortho_tried = true;
    const std::string fallback = " (the ground shows the land cover)";
    if (m_options.ortho_weights.empty()) {
        m_ortho_problem = "orthoimages off: no weights file configured" + fallback;
        return nullptr;
    }
    if (!m_ortho_network) {
        m_ortho_problem = "orthoimages off: " + m_ortho_file_problem + fallback;
        return nullptr;
    }
    try {
        m_ortho = std::make_unique<OrthoGenerator>(*m_ortho_network);
    } catch (const std::exception& e) {  // RenderError (the driver)
        m_ortho_problem = std::string("orthoimages off: ") + e.what() + fallback;
    }
    m_ortho_network.reset();  // uploaded (or refused): the copy is not needed again
    return m_ortho.get();
}

void GpuTileCache::updateOrthoimages(std::span<const std::pair<GpuTile*, std::shared_ptr<const map::Tile>>> wanted,
                                     MapFrameStats& stats) {
    const auto t0 = Clock::now();
    OrthoGenerator* gen = orthoGenerator();
    if (!m_ortho_problem.empty()) {
        stats.ortho_problem += (stats.ortho_problem.empty() ? "" : "; ") + std::exchange(m_ortho_problem, {});
    }
    if (!gen) return;
    for (const auto& [gpu, tile] : wanted) {
        gpu->ortho_started = true;
        gpu->ortho_generator = gen;
        OrthoGenerator::Request r;
        r.tile = tile;
        r.extent = static_cast<float>(tile->size_m);
        r.size = orthoImageSize(tile->size_m);
        // Plants (seed 6.7.1) only where they are seen from close by: the close-range tiles.
        r.vegetation = tile->size_m <= kCloseRangeTileM;
        std::string problem;
        gpu->ortho = gen->start(r, problem);
        // A tile whose layers cannot be sampled keeps its land cover; said once per tile.
        if (!gpu->ortho) stats.ortho_problem += (stats.ortho_problem.empty() ? "" : "; ") + problem;
    }
    const std::size_t images = gen->timings().images;
    if (gen->pending() > 0) gen->step(m_options.ortho_pixels_per_frame);
    for (GpuTile* g : m_drawn) {
        if (g->ortho && !g->ortho_ready) g->ortho_ready = gen->ready(g->ortho);
    }
    stats.ortho_generated = gen->timings().images - images;
    stats.ortho_pending = gen->pending();
    stats.ortho_ms = msSince(t0);
}

void GpuTileCache::evict() {
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

GpuTile* GpuTileCache::upload(const std::shared_ptr<const map::Tile>& tile, const TileMorph* morph) {
    if (tile->dem.coverage < 1.0f && m_warned_flat.insert(tile->id.key()).second) {
        // The compiler found no DEM for part of this tile; that part renders flat at 0 m. The
        // caller logs it (once per tile, whichever display met it first).
        m_new_flat_tiles.push_back({tile->id, tile->dem.coverage});
        ++m_flat_tiles;
    }
    std::array<const map::Tile*, kMorphLevels> ancestors{};
    for (std::size_t j = 0; morph && j < ancestors.size(); ++j) ancestors[j] = morph->ancestors[j].get();
    TileMesh mesh = buildTileMesh(*tile, {}, ancestors);
    auto gpu = std::make_unique<GpuTile>();
    gpu->source = tile.get();
    gpu->source_ref = tile;
    gpu->morph_ancestors = ancestors;
    gpu->grid_size = mesh.grid_size;
    gpu->heights = mesh.heights;
    gpu->ancestor_heights = mesh.ancestor_heights;
    gpu->origin = mesh.origin;
    gpu->size_m = mesh.size_m;
    if (!tile->labels.empty()) gpu->label_points = labelPoints(*tile, mesh.grid());

    uploadTerrain(*gpu, mesh);
    if (!mesh.roads.empty()) uploadRoads(*gpu, mesh, m_road_index_buffer);
    if (!mesh.building_indices.empty()) uploadBuildings(*gpu, mesh);
    glBindVertexArray(0);
    if (!mesh.land_cover.empty()) {
        gpu->land_cover =
            rasterizeLandCover(mesh.land_cover, landCoverTextureSize(mesh.size_m), glm::vec2(0.0f), mesh.size_m);
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
        const glm::vec2 offset(static_cast<float>(mesh.origin.x - a->origin_x),
                               static_cast<float>(mesh.origin.y - a->origin_y));
        gpu->ancestor_cover[j] = rasterizeLandCover(
            triangles, landCoverTextureSize(static_cast<float>(a->size_m)) >> (j + 1), offset, mesh.size_m);
    }

    // A re-upload for new geomorph targets keeps the tile's orthoimage (finished or pending).
    if (const auto old = m_tiles.find(tile->id.key());
        old != m_tiles.end() && sameTileObject(old->second->source, old->second->source_ref, tile.get())) {
        GpuTile& o = *old->second;
        gpu->ortho = std::exchange(o.ortho, 0);
        gpu->ortho_ready = o.ortho_ready;
        gpu->ortho_started = o.ortho_started;
        gpu->ortho_generator = o.ortho_generator;
    }
    GpuTile* raw = gpu.get();
    m_tiles[tile->id.key()] = std::move(gpu);
    return raw;
}

GLuint GpuTileCache::rasterizeLandCover(std::span<const LandCoverVertex> triangles, int size, glm::vec2 offset,
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
    countedBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(triangles.size() * sizeof(LandCoverVertex)),
                      triangles.data(), GL_STREAM_DRAW);
    setVertexAttributes(sizeof(LandCoverVertex), {{0, 2, GL_FLOAT, offsetof(LandCoverVertex, position)},
                                                  {1, 4, GL_FLOAT, offsetof(LandCoverVertex, color)}});
    glUseProgram(m_land_cover.id());
    glUniform2fv(m_land_cover.uniform("u_offset"), 1, glm::value_ptr(offset));
    glUniform1f(m_land_cover.uniform("u_extent"), extent);
    // Runs of plain cover replace what is under them; runs of tints blend over it ("over" on
    // the premultiplied colours the raster shader writes).
    if (triangles.empty()) countedDrawArrays(GL_TRIANGLES, 0, 0);
    for (std::size_t first = 0; first < triangles.size();) {
        const bool tint = triangles[first].tint;
        std::size_t end = first;
        while (end < triangles.size() && triangles[end].tint == tint) ++end;
        if (tint) {
            glEnable(GL_BLEND);
            glBlendFunc(GL_ONE, GL_ONE_MINUS_SRC_ALPHA);
        } else {
            glDisable(GL_BLEND);
        }
        countedDrawArrays(GL_TRIANGLES, static_cast<GLint>(first), static_cast<GLsizei>(end - first));
        first = end;
    }
    glDisable(GL_BLEND);
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

}  // namespace navmap::render::gl
