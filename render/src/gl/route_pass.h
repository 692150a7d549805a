// SPDX-License-Identifier: Apache-2.0
#pragma once
// The route (seed 3.6.1): draped per tile against the grid the tile is drawn with, geomorphed with
// the terrain, and drawn like the roads (roads_geo.vert with NAVMAP_ROUTE_PROGRESS: casing, fill,
// the part already driven dimmed) just above them. Its per-tile state lives on the GpuTile.
// Private to render/.

#include <GLES3/gl3.h>

#include "frame_context.h"
#include "gpu_tile.h"
#include "quad_indices.h"
#include "shader_program.h"

namespace navmap::render::gl {

class RoutePass {
public:
    /// Compiles the route program (throws RenderError).
    RoutePass();
    RoutePass(const RoutePass&) = delete;
    RoutePass& operator=(const RoutePass&) = delete;

    /// Drapes the frame's route onto each of ctx.tiles (cached per route object and version)
    /// and, where a tile's part of it is in view, applies the tile's geomorph of this frame.
    /// Needs the tiles' view matrices; call only with a route shown (FrameContext::routeShown).
    void update(const FrameContext& ctx);
    /// Casing then fill pass of the route pieces in view (depth and stencil state set by the caller).
    void draw(const FrameContext& ctx);
    /// With `program` (a roads_geo.vert program) bound: its uniforms for `pass`, then the route
    /// pieces in view (the part behind route_progress_m dimmed).
    void drawWith(ShaderProgram& program, int pass, const FrameContext& ctx);
    [[nodiscard]] ShaderProgram& program() { return m_program; }

private:
    void updateTile(GpuTile& tile, const FrameContext& ctx);

    ShaderProgram m_program;  // roads_geo with NAVMAP_ROUTE_PROGRESS
    // Two triangles per route quad, shared by every tile's route vertex array.
    RepeatedIndices m_quad_indices{kQuadIndices, 4};
};

}  // namespace navmap::render::gl
