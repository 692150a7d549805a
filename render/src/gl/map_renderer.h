// SPDX-License-Identifier: Apache-2.0
#pragma once
// Draws map frames from tiles as an ordered list of passes, each a class of its own that owns its
// programs and buffers: terrain with land cover, buildings, roads (geometric or shadow volumes),
// route, screen-space outlines, occlusion effects, labels and the vehicle marker. The tiles' GPU
// resources are shared by every display target (GpuTileCache); the label state is per target.
// Private to render/.

#include <memory>

#include "building_pass.h"
#include "far_ground_pass.h"
#include "frame_context.h"
#include "gl_features.h"
#include "gpu_tile_cache.h"
#include "guidance_overlay_pass.h"
#include "maneuver_arrow_pass.h"
#include "map_label_pass.h"
#include "marker_pass.h"
#include "navmap/render/map_frame.h"
#include "navmap/render/renderer.h"
#include "occlusion_effects.h"
#include "outline_pass.h"
#include "render_target.h"
#include "road_pass.h"
#include "route_pass.h"
#include "side_task.h"
#include "terrain_pass.h"

namespace navmap::render::gl {

class SvRoads;
class PassClock;

class MapRenderer {
public:
    /// `software`: the context renders on a software rasterizer (DeviceInfo::software);
    /// `features`: what the context offers beyond ES 3.0 core.
    MapRenderer(const RendererOptions& options, bool software, const GlFeatures& features);
    ~MapRenderer();
    MapRenderer(const MapRenderer&) = delete;
    MapRenderer& operator=(const MapRenderer&) = delete;

    void setStyle(const MapStyle& style) { m_style = style; }
    /// Renders `frame` into `target`, the offscreen target of display `target_id`: that display's
    /// label layout continues from its own previous frame (temporal coherence, seed 4.3), and the
    /// tiles of its latest frame stay on the GPU.
    void render(const MapFrame& frame, const RenderTarget& target, int target_id);
    [[nodiscard]] const MapFrameStats& stats() const { return m_stats; }
    /// The route's work in the last frame (RoutePass).
    [[nodiscard]] const RouteWork& routeWork() const { return m_route.work(); }
    /// Forgets display `target_id`: its label state, and its latest frame no longer holds tiles.
    void dropTarget(int target_id) {
        m_labels.dropTarget(target_id);
        m_cache.dropTarget(target_id);
    }

private:
    /// The frame's tiles on the GPU (uploads), the camera per tile and the route draped on them.
    FrameContext beginFrame(const MapFrame& frame, const RenderTarget& target, int target_id);
    /// Roads (geometric or shadow volumes, `sv`) and route, marking the road pixels for the outlines.
    /// Roads and route; with `glow_terrain_depth` (the terrain-only depth) their fill pass also marks
    /// the glow's stencil bit where a building hides it.
    void drawRoadsAndRoute(const FrameContext& ctx, SvRoads* sv, PassClock& clock, GLuint glow_terrain_depth);
    /// The roads' or the route's program with the terrain cut (NAVMAP_TERRAIN_CUT: fragments behind
    /// u_terrain_depth discarded), made when first used.
    ShaderProgram& terrainCutProgram(bool route);
    /// Label aura and glowing roads (seed 5.5), between the label layout and the label text.
    void runOcclusionEffects(const FrameContext& ctx);
    /// Manoeuvre arrows and guidance roads (ManeuverArrowPass), after the route and its glow.
    void drawArrows(const FrameContext& ctx);

    RendererOptions m_options;
    GlFeatures m_features;
    MapStyle m_style;
    MapFrameStats m_stats;
    GpuTileCache m_cache;
    TerrainPass m_terrain;
    FarGroundPass m_far_ground;
    BuildingPass m_buildings;
    RoadPass m_roads;
    std::unique_ptr<SvRoads> m_sv_roads;  // shadow-volume roads (seed 3.5): created when first used
    RoutePass m_route;
    OutlinePass m_outlines;
    std::unique_ptr<OcclusionEffects> m_effects;  // glowing roads, label aura: created when first used
    // The roads' and the route's programs with the terrain cut (terrainCutProgram()).
    std::unique_ptr<ShaderProgram> m_roads_cut, m_route_cut;
    bool m_glow_from_stencil = false;  // this frame's glow: OcclusionEffects::glowFromStencil()
    MapLabelPass m_labels;
    MarkerPass m_marker;
    std::unique_ptr<ManeuverArrowPass> m_arrows;      // created on the first frame with arrows
    std::unique_ptr<GuidanceOverlayPass> m_guidance;  // created on the first frame with an overlay, sign or bar
    SideTask m_side;  // runs RoadPass::cull, then OutlinePass::markCells, beside the render thread
};

}  // namespace navmap::render::gl
