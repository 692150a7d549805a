#pragma once
// Draws map frames from tiles: per-tile GPU resources (terrain + skirts, land-cover texture,
// road instances, buildings), the route and the vehicle marker, with the screen-space road
// outlines. Private to render/.

#include <GLES3/gl3.h>

#include <array>
#include <memory>
#include <optional>
#include <span>
#include <unordered_map>
#include <unordered_set>
#include <vector>

#include "navmap/render/map_frame.h"
#include "outline_cells.h"
#include "navmap/render/renderer.h"
#include "navmap/render/road_style.h"
#include "terrain_horizon.h"
#include "tile_mesh.h"
#include "label_pass.h"
#include "quad_indices.h"
#include "occlusion_effects.h"
#include "render_target.h"
#include "shader_program.h"
#include "side_task.h"

namespace navmap::render::gl {

class SvRoads;

inline constexpr std::uint32_t kQuadIndices[6] = {0, 1, 2, 2, 1, 3};

class MapRenderer {
public:
    /// `software`: the context renders on a software rasterizer (DeviceInfo::software).
    MapRenderer(const RendererOptions& options, bool software);
    ~MapRenderer();
    MapRenderer(const MapRenderer&) = delete;
    MapRenderer& operator=(const MapRenderer&) = delete;

    void setStyle(const MapStyle& style) { m_style = style; }
    void render(const MapFrame& frame, const RenderTarget& target);
    [[nodiscard]] const MapFrameStats& stats() const { return m_stats; }
    /// GlRenderer names its current target before each render(). Per target: the label layout
    /// state (temporal coherence, seed 4.3; the others' are kept aside) and the frame of its
    /// latest render, which keeps that frame's tiles on the GPU (evict()).
    void selectTarget(int key) {
        if (key == m_target_key) return;
        m_label_parked[m_target_key] = std::move(m_label_pass);
        auto it = m_label_parked.find(key);
        if (it != m_label_parked.end()) {
            m_label_pass = std::move(it->second);
            m_label_parked.erase(it);
        }
        m_target_key = key;
    }
    void dropTarget(int key) {
        m_label_parked.erase(key);
        m_target_frame.erase(key);
    }

private:
    struct GpuTile;

    /// `morph` (may be null): the geomorph targets (TileMorph::ancestors).
    GpuTile* upload(const std::shared_ptr<const map::Tile>& tile, const TileMorph* morph = nullptr);
    /// A new RGBA4 texture (size^2, mipmapped) with the land-cover triangles (tile-local metres)
    /// of the square [offset, offset + extent] of their tile.
    GLuint rasterizeLandCover(std::span<const LandCoverVertex> triangles, int size, glm::vec2 offset, float extent);
    /// Drapes the frame's route onto one tile (cached per route object and version) and, where
    /// the tile's part of it is in view, applies the tile's geomorph of this frame.
    void updateRoute(GpuTile& tile, const MapFrame& frame);
    /// With `program` (a roads_geo.vert program) bound: sets its uniforms for `pass` (0 casing, 1
    /// fill, 2 outline footprint) and draws the road pieces of `tiles`; returns how many.
    std::size_t drawRoads(ShaderProgram& program, int pass, const glm::mat4& projection,
                          const std::vector<GpuTile*>& tiles);
    /// The same for the route pieces (the part behind route_progress_m dimmed).
    void drawRoute(ShaderProgram& program, int pass, const MapFrame& frame, const glm::mat4& projection,
                   const std::vector<GpuTile*>& tiles);
    void setRoadUniforms(ShaderProgram& program, int pass, bool route, const glm::mat4& projection);
    /// The vehicle marker as it will be drawn: projected anchor, heading on screen and the
    /// screen outline; none without a marker or behind the camera.
    struct MarkerOnScreen {
        glm::vec4 anchor_clip{0.0f};
        glm::vec2 screen_dir{0.0f, 1.0f};  ///< unit, pixels, y up
        std::vector<glm::vec2> outline;    ///< screen pixels, y down
    };
    [[nodiscard]] std::optional<MarkerOnScreen> markerOnScreen(const MapFrame& frame, const RenderTarget& target) const;
    void drawMarker(const MapFrame& frame, const MarkerOnScreen& marker, const RenderTarget& target);
    /// With a buildings program bound (buildings.vert: the scene's or the aura's): its uniforms,
    /// then the buildings of `tiles` in view; returns the triangles drawn.
    std::size_t drawBuildings(ShaderProgram& program, const MapFrame& frame, const glm::mat4& projection,
                              const std::vector<GpuTile*>& tiles);
    /// With a buildings program bound: the buildings of the tile's blocks in view; returns the
    /// triangles drawn.
    std::size_t drawBuildingsOf(ShaderProgram& program, const MapFrame& frame, const GpuTile& tile);
    /// The terrain of `tiles` in blocks: frustum-culled, each with the land-cover levels it reaches.
    void drawTerrain(const MapFrame& frame, const glm::mat4& projection, const glm::vec3& light,
                     const std::vector<GpuTile*>& tiles);
    /// The road pieces of the blocks in view, per tile, into m_road_indices (drawRoads); with
    /// `hidden`, not those of blocks the drawn terrain hides (m_horizon). No GL calls: it runs
    /// beside the render thread.
    void cullRoads(const MapFrame& frame, const glm::mat4& projection, int height, const std::vector<GpuTile*>& tiles,
                   bool hidden);
    /// m_horizon from the eye over the azimuths the view spans, from the tiles' TerrainFloor.
    void buildHorizon(const MapFrame& frame, const glm::mat4& projection, const std::vector<GpuTile*>& tiles);
    /// Hands the GPU this frame's m_road_indices (after cullRoads, on the render thread).
    void uploadRoadIndices();
    /// The screen cells where the outline filter can find road pixels (seed 3.6.3): the quads of
    /// the road pieces in view (after cullRoads) and of the route, grown by the filter's reach,
    /// into m_cells and m_cell_vertices. No GL calls: it runs beside the render thread.
    void markOutlineCells(const MapFrame& frame, const glm::mat4& projection, int width, int height,
                          const std::vector<GpuTile*>& tiles);
    /// The same from the road mask itself, on software rasterizers (MapLayers::outline_mask): the
    /// mask read back, its edge pixels (outlineEdges) uploaded into the packed mask's texture, and
    /// the cells that hold them into m_cells and m_cell_vertices.
    /// Needs target.readsMaskBytes(); returns the texture.
    GLuint markEdgeCells(const RenderTarget& target);
    /// m_cell_vertices anew with the filter's cells, m_cells' rectangles, and m_cell_pixels their area.
    void filterCellVertices();
    /// Appends the rectangle's two triangles to m_cell_vertices (whole cells at the right edge).
    void addCellRect(const CellRect& r);
    /// Label aura and glowing roads (seed 5.5), between the label layout and the label text.
    void runOcclusionEffects(const MapFrame& frame, const RenderTarget& target, const glm::mat4& projection,
                             const std::vector<GpuTile*>& tiles);
    void evict();

    RendererOptions m_options;
    bool m_software = false;
    MapStyle m_style;
    MapFrameStats m_stats;
    ShaderProgram m_terrain;
    ShaderProgram m_terrain_cover[2];  // + land cover morphing over 2 or 3 levels (terrain_tile.frag)
    ShaderProgram m_land_cover;
    ShaderProgram m_roads;
    ShaderProgram m_route;          // the same, dimming the part driven (NAVMAP_ROUTE_PROGRESS)
    bool m_whole_caps = false;      // this frame: !MapLayers::trim_joint_caps (setRoadUniforms)
    // This frame's selection of road classes (seed 7.3; cullRoads, setRoadUniforms).
    std::array<SelectionFade, kStyledRoadClasses> m_selection{};
    glm::vec2 m_viewport{0.0f};     // this frame's target, pixels (setRoadUniforms)
    ShaderProgram m_outline;        // the filter over the whole screen
    ShaderProgram m_outline_cells;  // the filter over the cells near roads (markOutlineCells)
    ShaderProgram m_outline_packed;  // the same over the packed mask, road pixels left out by the stencil
    ShaderProgram m_outline_pack;    // packs the mask over the cells (outline_pack.frag)
    ShaderProgram m_outline_edges;   // the filter over edge pixels found on the CPU (markEdgeCells)
    ShaderProgram m_buildings;
    ShaderProgram m_marker;
    GLuint m_empty_texture = 0;
    GLuint m_raster_fbo = 0;     // the land-cover texture being resolved into
    GLuint m_raster_ms_fbo = 0;  // multisampled land-cover raster, m_raster_ms_size
    GLuint m_raster_ms_rb = 0;
    ScratchSize m_raster_ms_size;
    GLuint m_empty_vao = 0;
    GLuint m_marker_vao = 0;
    GLuint m_marker_vbo = 0;
    // Two triangles per road quad (corners 0 (-,+) 1 (-,-) 2 (+,+) 3 (+,-)), shared by every road
    // and route vertex array.
    RepeatedIndices m_quad_indices{kQuadIndices, 4};
    std::vector<std::size_t> m_block_order;  // drawTerrain: a tile's blocks, nearest first
    TerrainHorizon m_horizon;                // this frame's (cullRoads)
    std::vector<const TerrainFloor*> m_floors;
    // This frame's road quads in view (cullRoads), 6 indices each, bound to every road vertex array.
    std::vector<std::uint32_t> m_road_indices;
    GLuint m_road_index_buffer = 0;
    OutlineCells m_cells;                   // where the outlines can be (markOutlineCells)
    std::vector<glm::vec2> m_cell_vertices;  // its rectangles, two triangles each, pixels
    std::size_t m_pack_first = 0;            // from here: the packing pass's rectangles
    std::size_t m_cell_pixels = 0;           // their area
    std::vector<std::uint8_t> m_mask_bytes;  // markEdgeCells: the road mask read back
    std::vector<std::uint16_t> m_edge_mask;  // and its edge pixels
    double m_cell_ms = 0;                    // CPU time of markOutlineCells or markEdgeCells
    SideTask m_side;                         // runs cullRoads, then markOutlineCells, beside the render thread
    GLuint m_cell_vao = 0, m_cell_vbo = 0;
    std::unordered_map<std::uint64_t, std::unique_ptr<GpuTile>> m_tiles;
    // Land-cover triangles of the ancestors met by this frame's uploads (upload()).
    std::unordered_map<const map::Tile*, std::vector<LandCoverVertex>> m_ancestor_cover_triangles;
    std::uint64_t m_frame = 0;
    // Target (label key) -> m_frame of its latest render: a tile that any target drew in its
    // latest frame is in use (evict()).
    std::unordered_map<int, std::uint64_t> m_target_frame;
    std::unordered_set<std::uint64_t> m_warned_flat;  // tiles already reported as lacking DEM
    std::size_t m_stats_flat_tiles = 0;
    std::vector<FlatTile> m_new_flat_tiles;
    std::shared_ptr<LabelText> m_label_text;  // fonts and glyph atlas of every target's label pass
    std::unique_ptr<LabelPass> m_label_pass;  // created on the first frame with labels on
    int m_target_key = 0;  // the current target (selectTarget); m_label_pass is its label state
    std::unordered_map<int, std::unique_ptr<LabelPass>> m_label_parked;  // other targets' states
    std::vector<TileLabels> m_tile_labels;
    std::unique_ptr<OcclusionEffects> m_effects;  // glowing roads, label aura: created when first used
    std::unique_ptr<SvRoads> m_sv_roads;  // shadow-volume roads (seed 3.5): created when first used
};

}  // namespace navmap::render::gl
