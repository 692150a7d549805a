// SPDX-License-Identifier: Apache-2.0
#pragma once
// The terrain of the map frame: each tile's surface in blocks, frustum-culled and nearest first,
// geomorphed towards its ancestors (terrain_lod.h) with the land cover of the levels each block
// reaches, relief-shaded and fogged (terrain_tile.vert/.frag). Private to render/.

#include <GLES3/gl3.h>

#include <cstddef>
#include <vector>

#include "frame_context.h"
#include "shader_program.h"

namespace navmap::render::gl {

class TerrainPass {
public:
    /// Compiles the terrain programs (throws RenderError).
    TerrainPass();
    ~TerrainPass();
    TerrainPass(const TerrainPass&) = delete;
    TerrainPass& operator=(const TerrainPass&) = delete;

    /// Draws the terrain of ctx.tiles into the bound framebuffer (depth test and culling set by
    /// the caller); counts its triangles into ctx.stats.
    void draw(const FrameContext& ctx);

private:
    ShaderProgram m_plain;
    ShaderProgram m_cover[2];                // + land cover morphing over 2 or 3 levels (terrain_tile.frag)
    GLuint m_empty_texture = 0;              // bound where a level has no land cover
    std::vector<std::size_t> m_block_order;  // a tile's blocks, nearest first
};

}  // namespace navmap::render::gl
