// SPDX-License-Identifier: Apache-2.0
#pragma once
// The tiles' GPU resources (GpuTile), shared by every display target: uploads a frame's tiles
// within the per-frame budget (terrain, land-cover rasters of the tile and its geomorph targets,
// road quads, buildings), starts the synthetic orthoimages of tiles with ortho layers while the
// style's ground asks for them and works on them within a per-frame pixel budget
// (OrthoGenerator), and evicts the tiles no target drew lately. The passes read the tiles it
// hands out for a frame. Private to render/.

#include <GLES3/gl3.h>

#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <unordered_map>
#include <unordered_set>
#include <vector>

#include "gpu_tile.h"
#include "navmap/map/ortho/ortho_network.h"
#include "navmap/render/map_frame.h"
#include "navmap/render/renderer.h"
#include "render_target.h"
#include "shader_program.h"

namespace navmap::render::gl {

class GpuTileCache {
public:
    /// Uses options.max_tile_uploads_per_frame and options.tile_resource_cache. Compiles the
    /// land-cover raster program (throws RenderError).
    explicit GpuTileCache(const RendererOptions& options);
    ~GpuTileCache();
    GpuTileCache(const GpuTileCache&) = delete;
    GpuTileCache& operator=(const GpuTileCache&) = delete;

    /// The frame's tiles on the GPU, nearest first, for display `target_id`: resident ones and
    /// those uploaded now (bounded per frame so a burst of new tiles does not stall one frame),
    /// each with this frame's geomorph. Fills the upload counts of `stats` (tiles_uploaded,
    /// tiles_pending, tiles_drawn, the tiles lacking DEM). With `ground` Orthoimage, starts the
    /// orthoimages of the frame's tiles that have none yet, nearest first, and steps the generator
    /// within RendererOptions::ortho_pixels_per_frame (ortho_* of `stats`). Valid until the next call.
    std::span<GpuTile* const> acquire(const MapFrame& frame, int target_id, MapFrameStats& stats, Ground ground);
    /// Frees the least recently used tiles beyond the cache size that no target drew in its
    /// latest frame.
    void evict();
    /// Calls `f` with every tile held (drawn in this frame or not).
    template <typename F>
    void forEachTile(F&& f) {
        for (auto& entry : m_tiles) f(*entry.second);
    }
    /// Forgets display `target_id` (its latest frame no longer holds tiles).
    void dropTarget(int target_id) { m_target_frame.erase(target_id); }
    /// The element buffer bound to every tile's road vertex array: RoadPass fills it each frame
    /// with the quads in view.
    [[nodiscard]] GLuint roadIndexBuffer() const { return m_road_index_buffer; }

private:
    /// `morph` (may be null): the geomorph targets (TileMorph::ancestors).
    GpuTile* upload(const std::shared_ptr<const map::Tile>& tile, const TileMorph* morph);
    /// A new RGBA4 texture (size^2, mipmapped) with the land-cover triangles (tile-local metres)
    /// of the square [offset, offset + extent] of their tile.
    GLuint rasterizeLandCover(std::span<const LandCoverVertex> triangles, int size, glm::vec2 offset, float extent);
    /// The generator, made on first use from the weights read at construction; null (and
    /// m_ortho_problem set) when the weights or the driver do not allow it.
    OrthoGenerator* orthoGenerator();
    /// Starts the orthoimages of `wanted` (tiles without one, nearest first) and steps the generator.
    void updateOrthoimages(std::span<const std::pair<GpuTile*, std::shared_ptr<const map::Tile>>> wanted,
                           MapFrameStats& stats);

    RendererOptions m_options;
    std::optional<map::ortho::OrthoNetwork> m_ortho_network;  // read at construction, until uploaded
    std::string m_ortho_file_problem;                         // why the weights could not be read
    std::unique_ptr<OrthoGenerator> m_ortho;                  // before m_tiles: their textures cancel with it
    bool m_ortho_tried = false;                               // m_ortho made or refused
    std::string m_ortho_problem;                              // to report in the next frame's stats, once
    bool m_no_layers_reported = false;                        // tiles without orthoimage layers were reported
    ShaderProgram m_land_cover;
    GLuint m_raster_fbo = 0;     // the land-cover texture being resolved into
    GLuint m_raster_ms_fbo = 0;  // multisampled land-cover raster, m_raster_ms_size
    GLuint m_raster_ms_rb = 0;
    ScratchSize m_raster_ms_size;
    GLuint m_road_index_buffer = 0;
    std::unordered_map<std::uint64_t, std::unique_ptr<GpuTile>> m_tiles;
    std::vector<GpuTile*> m_drawn;  // acquire(): this frame's tiles
    // Land-cover triangles of the ancestors met by this frame's uploads (upload()).
    std::unordered_map<const map::Tile*, std::vector<LandCoverVertex>> m_ancestor_cover_triangles;
    std::uint64_t m_frame = 0;
    // Target -> m_frame of its latest frame: a tile that any target drew in its latest frame is
    // in use (evict()).
    std::unordered_map<int, std::uint64_t> m_target_frame;
    std::unordered_set<std::uint64_t> m_warned_flat;  // tiles already reported as lacking DEM
    std::size_t m_flat_tiles = 0;
    std::vector<FlatTile> m_new_flat_tiles;
};

}  // namespace navmap::render::gl
