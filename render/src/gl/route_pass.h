// SPDX-License-Identifier: Apache-2.0
#pragma once
// The route (seed 3.6.1): draped per tile against the grid the tile is drawn with, geomorphed with
// the terrain, and drawn like the roads (roads_geo.vert with NAVMAP_ROUTE_PROGRESS: casing, fill,
// the part already driven dimmed) just above them. Its per-tile state lives on the GpuTile.
// Private to render/.

#include <GLES3/gl3.h>

#include <cstddef>
#include <cstdint>

#include "frame_context.h"
#include "gpu_tile.h"
#include "quad_indices.h"
#include "shader_program.h"

namespace navmap::render::gl {

/// The route's work in one frame, bounded per drawn tile whatever the route
/// (kRoutePiecesPerTile): what the tests and benchmarks count.
struct RouteWork {
    std::size_t tiles_draped = 0;       ///< tiles whose route was (re)draped
    std::size_t tiles_deferred = 0;     ///< tiles left to a later frame (kRouteSegmentsPerFrame)
    std::size_t segments_clipped = 0;   ///< route segments overlapping the tiles draped
    std::size_t segments_draped = 0;    ///< route segments draped, after clipping and simplifying
    std::size_t segments_left_out = 0;  ///< of those clipped: covered already, or over the bound
    std::size_t pieces = 0;             ///< draped pieces the frame's tiles hold
    std::size_t pieces_uploaded = 0;    ///< route quads uploaded (4 vertices each)
    std::size_t bytes_released = 0;     ///< CPU memory the tiles let go of (another route, or none)
};

/// Route segments (overlapping a tile, RouteDrapeCounts::segments_clipped) a frame drapes at
/// most before it leaves the remaining tiles to later frames (the nearest tile is always draped):
/// a route that crosses the drawn area again and again takes a few frames to appear instead of
/// stalling one. A normal route is draped whole in one frame.
inline constexpr std::size_t kRouteSegmentsPerFrame = 20000;

class RoutePass {
public:
    /// Compiles the route program (throws RenderError).
    RoutePass();
    RoutePass(const RoutePass&) = delete;
    RoutePass& operator=(const RoutePass&) = delete;

    /// Drapes the frame's route onto each of ctx.tiles (cached per route object and version, and
    /// simplified to the pixel tolerance the view needs at the tile: draped again only when a view
    /// needs it finer) and, where a tile's part of it is in view, applies the tile's geomorph of
    /// this frame. Each tile holds at most kRoutePiecesPerTile pieces. Needs the tiles' view
    /// matrices; call only with a route shown (FrameContext::routeShown).
    void update(const FrameContext& ctx);
    /// Whether the tiles' route state belongs to another route than `route` (the frame's, shown
    /// or not; null: none): the caller then releases it on every tile it holds (release()).
    /// Remembers `route` as the current one.
    bool routeChanged(const RouteGeometry* route);
    /// Frees what `tile` keeps of the route (pieces, instances, its buffer), capacity included;
    /// counted in work().bytes_released.
    void release(GpuTile& tile);
    /// Starts the counts of a frame (work()).
    void beginFrame() { m_work = {}; }
    /// The counts of the frame since beginFrame().
    [[nodiscard]] const RouteWork& work() const { return m_work; }
    /// Casing then fill pass of the route pieces in view (depth and stencil state set by the caller).
    void draw(const FrameContext& ctx);
    /// With `program` (a roads_geo.vert program) bound: its uniforms for `pass`, then the route
    /// pieces in view (the part behind route_progress_m dimmed).
    void drawWith(ShaderProgram& program, int pass, const FrameContext& ctx);
    [[nodiscard]] ShaderProgram& program() { return m_program; }

private:
    void updateTile(GpuTile& tile, const FrameContext& ctx);
    /// Drapes `route` onto `tile` at `tolerance_m` (RouteDrapeOptions) and readies its buffer.
    void drape(GpuTile& tile, const RouteGeometry& route, double tolerance_m);

    ShaderProgram m_program;  // roads_geo with NAVMAP_ROUTE_PROGRESS
    // The route the tiles' route state was made from (routeChanged()).
    const RouteGeometry* m_route = nullptr;
    std::uint64_t m_route_version = 0;
    RouteWork m_work;
    // Two triangles per route quad, shared by every tile's route vertex array.
    RepeatedIndices m_quad_indices{kQuadIndices, 4};
};

}  // namespace navmap::render::gl
