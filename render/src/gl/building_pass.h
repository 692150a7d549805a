// SPDX-License-Identifier: Apache-2.0
#pragma once
// The extruded buildings of the map frame (buildings.vert/.frag): per tile the blocks in view,
// lit and fogged like the terrain, small far buildings culled in the shader. Private to render/.

#include <cstddef>

#include "frame_context.h"
#include "gpu_tile.h"
#include "shader_program.h"

namespace navmap::render::gl {

class BuildingPass {
public:
    /// Compiles the buildings program (throws RenderError).
    BuildingPass();
    BuildingPass(const BuildingPass&) = delete;
    BuildingPass& operator=(const BuildingPass&) = delete;

    /// Draws the buildings of ctx.tiles (depth test and face culling set here, depth writes by the
    /// caller); counts their triangles into ctx.stats.
    void draw(const FrameContext& ctx);
    /// With a buildings program bound (buildings.vert: this pass's or the label aura's): its
    /// uniforms, then the buildings of ctx.tiles in view; returns the triangles drawn.
    std::size_t drawWith(ShaderProgram& program, const FrameContext& ctx);

private:
    /// With a buildings program bound: the buildings of the tile's blocks in view; returns the
    /// triangles drawn.
    std::size_t drawTile(ShaderProgram& program, const FrameContext& ctx, const GpuTile& tile);

    ShaderProgram m_program;
};

}  // namespace navmap::render::gl
