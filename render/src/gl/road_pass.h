// SPDX-License-Identifier: Apache-2.0
#pragma once
// The geometric roads (seed 3.6): draped road pieces drawn as screen-widened quads with casing
// and fill (roads_geo.vert/.frag), least important class first. Each frame the pieces in view
// are culled on the CPU (frustum, blocks hidden behind the terrain, seed 7.3's selection, road
// levels of detail) into one index buffer that every tile's road vertex array reads.
// Private to render/.

#include <GLES3/gl3.h>

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "frame_context.h"
#include "shader_program.h"
#include "terrain_horizon.h"

namespace navmap::render::gl {

class RoadPass {
public:
    /// `index_buffer`: GpuTileCache::roadIndexBuffer(), bound to every tile's road vertex array.
    /// Compiles the road program (throws RenderError).
    explicit RoadPass(GLuint index_buffer);
    RoadPass(const RoadPass&) = delete;
    RoadPass& operator=(const RoadPass&) = delete;

    /// The road pieces of the blocks in view, per tile (GpuTile::visible_*), into indices(); with
    /// `hidden`, not those of blocks the drawn terrain hides (a TerrainHorizon). No GL calls: it
    /// runs beside the render thread.
    void cull(const FrameContext& ctx, bool hidden);
    /// Hands the GPU this frame's indices (after cull(), on the render thread).
    void uploadIndices();
    /// Casing then fill pass of the pieces in view (depth and stencil state set by the caller);
    /// returns the pieces drawn in the fill pass.
    std::size_t draw(const FrameContext& ctx);
    /// With `program` (a roads_geo.vert program) bound: sets its uniforms for `pass` (0 casing, 1
    /// fill, 2 outline footprint) and draws the pieces in view; returns how many.
    std::size_t drawWith(ShaderProgram& program, int pass, const FrameContext& ctx);
    [[nodiscard]] ShaderProgram& program() { return m_program; }
    /// This frame's quads in view (after cull()), 6 indices each: a tile's run from its
    /// visible_first.
    [[nodiscard]] std::span<const std::uint32_t> indices() const { return m_indices; }

private:
    /// m_horizon from the eye over the azimuths the view spans, from the tiles' TerrainFloor.
    void buildHorizon(const FrameContext& ctx);

    ShaderProgram m_program;
    GLuint m_index_buffer = 0;  // GpuTileCache's
    std::vector<std::uint32_t> m_indices;
    TerrainHorizon m_horizon;  // this frame's (cull)
    std::vector<const TerrainFloor*> m_floors;
};

}  // namespace navmap::render::gl
