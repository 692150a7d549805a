// SPDX-License-Identifier: Apache-2.0
#pragma once
// Visibility techniques of seed chapter 5 for the map renderer: glowing roads (5.3.5, 5.5.2)
// and the transparency label aura (5.3.3, 5.5.1). The map renderer owns the geometry, so it
// passes callbacks that draw roads or buildings with the program given; this class owns the
// offscreen buffers, the label OOBB depth and mask pass, the blur and the composites.
// Private to render/.

#include <GLES3/gl3.h>

#include <cstddef>
#include <functional>
#include <memory>
#include <span>
#include <vector>

#include <glm/mat4x4.hpp>

#include "label_pass.h"
#include "navmap/render/map_frame.h"
#include "render_target.h"
#include "shader_program.h"

namespace navmap::render::gl {

/// Needs a current GLES 3 context (create, use, destroy on its thread). Buffers follow the
/// size and sample count of the targets it is used with (one set per target size).
class OcclusionEffects {
public:
    /// Draws roads or buildings with `program` (bound); the callee sets its uniforms (the
    /// projection too) and issues the draws.
    using DrawWith = std::function<void(ShaderProgram& program)>;

    /// Compiles the glow and aura shaders; throws RenderError.
    OcclusionEffects();
    ~OcclusionEffects();
    OcclusionEffects(const OcclusionEffects&) = delete;
    OcclusionEffects& operator=(const OcclusionEffects&) = delete;

    /// After the terrain pass, before anything else writes depth: keeps the terrain-only depth
    /// (glow: roads behind hills do not glow; aura: the depth inside the auras) and, for the
    /// aura, the terrain colour and the depth its layer behind the labels starts from.
    void captureTerrainDepth(const RenderTarget& target, bool glow, bool aura);

    /// seed 5.5.1, after the scene's buildings, roads and outlines: the label OOBB depth and the
    /// gradient mask, the buildings again with the inverse depth test plus the roads over them
    /// (the scene behind the labels), composited into `target` by the mask; inside the auras, where
    /// a building is seen, the depth becomes the far plane's (multisampled: the terrain's), so the
    /// labels drawn next are not hidden there. Leaves `target`
    /// bound. `draw_buildings` draws every building with the program given (uniforms its own);
    /// `draw_roads` draws roads and route as the scene does (depth state set by the caller).
    void aura(const RenderTarget& target, std::span<const LabelOccluder> labels, const glm::mat4& projection,
              const MapStyle& style, const DrawWith& draw_buildings, const std::function<void()>& draw_roads);

    /// seed 5.5.2: detects the road fragments hidden by buildings (not by the terrain), draws
    /// them in the glow colour (or their own) straight into `target`, or with blur into a glow
    /// buffer that is blurred and composited; nothing glows where a road is visible. Leaves
    /// `target` bound for drawing. `draw_roads` draws the road and route fill with the road
    /// uniforms of the fill pass.
    void glow(const RenderTarget& target, const MapLayers& layers, const MapStyle& style, const DrawWith& draw_roads);

    /// Stencil bit of the frame that the roads' fill pass sets where its fragments fail the depth
    /// test in front of the terrain-only depth: road pixels a building hides (MapRenderer, with the
    /// glow from the stencil). The aura clears it where it composites.
    static constexpr GLuint kRoadFillStencilBit = 0x10;

    /// Around the scene's buildings when the aura is on (they are drawn after the terrain then):
    /// on = true marks, in the frame's stencil, the pixels where a building passes the depth
    /// test, so the visible buildings; aura() changes only those pixels. on = false ends it.
    static void markBuildings(bool on);

    /// seed 5.5.2 without drawing the roads again: glows on the pixels of kRoadFillStencilBit where
    /// no road is seen (the road mask), each once, in the glow colour, straight into `target` or
    /// blurred like glow(). Leaves `target` bound for drawing.
    void glowFromStencil(const RenderTarget& target, const MapLayers& layers, const MapStyle& style);

    /// The terrain-only depth texture that captureTerrainDepth() kept for `target`'s size (0: none
    /// yet), for the roads' fill pass that marks the glow's stencil bit and for passes after the
    /// glow that shine through buildings the same way (the manoeuvre arrows).
    GLuint terrainDepth(const RenderTarget& target);

private:
    struct Buffers;
    Buffers& buffersFor(const RenderTarget& target);
    /// Step 4 of seed 5.5.1: the layer behind the labels blended over `target` by the mask, over the
    /// `instances` auras in the mask buffer; with `depth_kept` false it writes the terrain's depth.
    void compositeAura(const RenderTarget& target, Buffers& b, const MapStyle& style, GLsizei instances,
                       bool depth_kept);
    /// The glow layer of `b` drawn: resolved, blurred at half resolution and composited over
    /// `target` except where a road is visible.
    void blurAndComposite(const RenderTarget& target, Buffers& b, float strength);

    ShaderProgram m_glow_roads;
    ShaderProgram m_glow_blur;
    ShaderProgram m_glow_composite;
    ShaderProgram m_glow_stencil;
    ShaderProgram m_aura_buildings;
    ShaderProgram m_aura_mask;
    ShaderProgram m_aura_depth;
    ShaderProgram m_aura_composite;
    ShaderProgram m_aura_composite_colour;  // the frame's depth kept (NAVMAP_DEPTH_KEPT)
    GLuint m_empty_vao = 0;
    GLuint m_mask_vao = 0;
    GLuint m_mask_vbo = 0;
    std::size_t m_mask_capacity = 0;                  // instances
    std::vector<std::unique_ptr<Buffers>> m_buffers;  // by target size, most recent first
};

}  // namespace navmap::render::gl
