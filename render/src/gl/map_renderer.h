#pragma once
// Draws map frames from tiles: per-tile GPU resources (terrain + skirts, land-cover texture,
// road instances, buildings), the route and the vehicle marker, with the screen-space road
// outlines. Private to render/.

#include <GLES3/gl3.h>

#include <memory>
#include <unordered_map>
#include <unordered_set>
#include <vector>

#include "navmap/render/map_frame.h"
#include "navmap/render/renderer.h"
#include "navmap/render/tile_mesh.h"
#include "label_pass.h"
#include "render_target.h"
#include "shader_program.h"

namespace navmap::render::gl {

class MapRenderer {
public:
    explicit MapRenderer(const RendererOptions& options);
    ~MapRenderer();
    MapRenderer(const MapRenderer&) = delete;
    MapRenderer& operator=(const MapRenderer&) = delete;

    void setStyle(const MapStyle& style) { m_style = style; }
    void render(const MapFrame& frame, const RenderTarget& target);
    [[nodiscard]] const MapFrameStats& stats() const { return m_stats; }

private:
    struct GpuTile;
    struct GpuRoute;

    GpuTile* upload(const std::shared_ptr<const map::Tile>& tile);
    void rasterizeLandCover(GpuTile& gpu, const TileMesh& mesh);
    void updateRoute(const RouteGeometry& route);
    /// Binds the shared quad index buffer to the bound vertex array, grown to `quads` quads.
    void bindQuadIndices(std::size_t quads);
    /// Draws quads [first, first + count) of the bound road vertex array.
    static void drawQuads(GLsizei first, GLsizei count);
    void setRoadUniforms(ShaderProgram& program, int pass, bool route);
    void drawMarker(const MapFrame& frame, const RenderTarget& target);
    void evict();

    RendererOptions m_options;
    MapStyle m_style;
    MapFrameStats m_stats;
    ShaderProgram m_terrain;
    ShaderProgram m_land_cover;
    ShaderProgram m_roads;
    ShaderProgram m_outline;
    ShaderProgram m_buildings;
    ShaderProgram m_marker;
    GLuint m_empty_texture = 0;
    GLuint m_raster_fbo = 0;
    GLuint m_empty_vao = 0;
    GLuint m_marker_vao = 0;
    GLuint m_marker_vbo = 0;
    GLuint m_quad_ibo = 0;  // two triangles per road quad, shared by every road vertex array
    std::size_t m_quad_capacity = 0;
    std::unordered_map<std::uint64_t, std::unique_ptr<GpuTile>> m_tiles;
    std::unique_ptr<GpuRoute> m_route;
    std::uint64_t m_frame = 0;
    std::unordered_set<std::uint64_t> m_warned_flat;  // tiles already reported as lacking DEM
    std::size_t m_stats_flat_tiles = 0;
    std::vector<FlatTile> m_new_flat_tiles;
    std::unique_ptr<LabelPass> m_label_pass;  // created on the first frame with labels on
    std::vector<TileLabels> m_tile_labels;
};

}  // namespace navmap::render::gl
