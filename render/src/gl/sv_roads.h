// SPDX-License-Identifier: Apache-2.0
#pragma once
// Shadow-volume roads (seed 3.5): the SV program, the segment boxes of each tile and the terrain
// depth target that the terrain pass writes as a secondary render target (seed 3.5.2): the road
// pass of MapRenderer when the frame's RoadTechnique resolves to ShadowVolume, instead of RoadPass
// (geometric), with calls around TerrainPass. Private to render/.

#include <GLES3/gl3.h>

#include <array>
#include <cstdint>
#include <memory>
#include <span>
#include <unordered_map>
#include <vector>

#include <glm/glm.hpp>

#include "gl_features.h"
#include "navmap/map/tile.h"
#include "navmap/render/map_frame.h"
#include "navmap/render/road_style.h"
#include "quad_indices.h"
#include "render_target.h"
#include "shader_program.h"

namespace navmap::render::gl {

/// One road segment (or a piece of a long one) as a shadow volume: end points on the original
/// polyline (no draping pre-process, seed 3.7) and the range of the terrain's height within
/// `reach` of it, measured from a plane that follows the terrain under the piece.
struct SvRoadInstance {
    glm::vec4 segment{0.0f};  ///< p0.xy, p1.xy, tile-local metres
    glm::vec2 z_range{0.0f};  ///< min, max terrain height above the plane near the segment, metres
    float road_class = 0.0f;  ///< map::RoadClass value
    float flags = 0.0f;       ///< map::road_flags bits
    float reach = 0.0f;       ///< metres around the piece that z_range covers
    glm::vec3 plane{0.0f};    ///< height at p0, gradient (dz/dx, dz/dy): z = h0 + g . (xy - p0)

    [[nodiscard]] float planeAt(glm::vec2 xy) const {
        return plane.x + glm::dot(glm::vec2(plane.y, plane.z), xy - glm::vec2(segment.x, segment.y));
    }
};

/// The SV instances of one tile, in the draw order of the geometric roads: least important class
/// first (so junctions take the more important colour, seed 3.6.3), bridges last. GL-free.
struct SvTileRoads {
    std::vector<SvRoadInstance> instances;
    std::array<std::size_t, kStyledRoadClasses> class_first{};  ///< first non-bridge instance of each class
    std::size_t bridge_first = 0;
    float max_slope = 0.0f;  ///< bound on the terrain's |gradient| in the tile (dz / dxy)
};

/// Builds the SV instances of a tile: segments cut into pieces of at most SvRoads::kPieceM, each
/// z range covering the terrain under the piece's road and casing in `style` (plus a metre), on the
/// tile's own surface and on its `ancestors`' (null entries skipped), which the terrain geomorphs
/// to (TileMorph). Wider roads (another style, distance scaling) grow the range in the shader.
SvTileRoads buildSvTileRoads(const map::Tile& tile, const RoadStyle& style,
                             std::span<const map::Tile* const> ancestors = {});

/// Geometric or ShadowVolume for a frame: Auto takes ShadowVolume when any drawn tile's DEM is finer
/// than kShadowVolumeAutoSpacingM.
RoadTechnique resolveRoadTechnique(const MapFrame& frame);

class SvRoads {
public:
    /// Longest piece of a segment with one box (and one height range).
    static constexpr double kPieceM = 40.0;

    /// The SV pass for this frame, or null when roads are geometric (technique, roads or terrain
    /// layer off, or a GL that cannot render the terrain depth for `target`: float colour buffers
    /// missing (GlFeatures::colorBufferFloat, DeviceInfo::features_off), multisampled R32F
    /// unsupported; reported on stderr). Creates `slot` and the depth target on first use, so the
    /// geometric path allocates nothing.
    static SvRoads* forFrame(std::unique_ptr<SvRoads>& slot, const MapFrame& frame, const RenderTarget& target,
                             const GlFeatures& features);

    /// Compiles the program (throws RenderError) when the GL can render the terrain depth
    /// (`color_buffer_float`: ES 3.2, or GL_EXT_color_buffer_float); otherwise forFrame() keeps
    /// returning null.
    explicit SvRoads(bool color_buffer_float);
    ~SvRoads();
    SvRoads(const SvRoads&) = delete;
    SvRoads& operator=(const SvRoads&) = delete;

    /// Binds a framebuffer with `target`'s colour and depth plus the terrain depth texture as draw
    /// buffer 3 (cleared to 0 = no terrain); the terrain pass draws into it.
    void beginTerrain(const RenderTarget& target);
    /// Resolves the terrain depth (multisampled targets) and rebinds `target` for drawing.
    void endTerrain(const RenderTarget& target);
    /// Casing then fill pass of every tile's roads (front faces culled, no depth writes, the
    /// road mask written as output 1). Leaves `target` bound. Returns the segments drawn.
    std::size_t draw(const MapFrame& frame, const glm::mat4& projection, const RenderTarget& target,
                     const RoadStyle& style);

private:
    struct GpuTileRoads;
    GpuTileRoads* tileRoads(const std::shared_ptr<const map::Tile>& tile,
                            const std::vector<const map::Tile*>& ancestors, const RoadStyle& style);
    /// (Re)creates the terrain depth target when `target` changed; false when it cannot be made.
    bool setupTarget(const RenderTarget& target);

    bool m_supported = false;
    ShaderProgram m_program;
    RepeatedIndices m_box_indices;  // 36 per box of 8 corners, shared by every tile's vertex array
    std::unordered_map<std::uint64_t, std::unique_ptr<GpuTileRoads>> m_tiles;
    std::uint64_t m_frame = 0;
    // Terrain depth target (seed 3.5.2), made on the first SV frame and on size changes.
    GLuint m_fbo = 0;            // target colour + depth, terrain depth as attachment 3
    GLuint m_depth_rb = 0;       // multisampled terrain depth (MSAA targets only)
    GLuint m_resolve_fbo = 0;    // m_depth_texture, for the MSAA resolve
    GLuint m_depth_texture = 0;  // R32F view depth, sampled by roads_sv.frag
    struct Key {
        GLint color_type = 0, color = 0, depth_type = 0, depth = 0;
        int width = 0, height = 0, samples = 0;
        bool operator==(const Key&) const = default;
    } m_key;
    bool m_usable = false;     // the depth target for m_key is complete
    ScratchSize m_depth_size;  // m_depth_texture / m_depth_rb
    int m_depth_samples = 0;
};

}  // namespace navmap::render::gl
