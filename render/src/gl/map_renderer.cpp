// SPDX-License-Identifier: Apache-2.0
#include "map_renderer.h"

#include <GLES3/gl3.h>
#ifdef __GLIBC__
#include <malloc.h>
#endif

#include <optional>
#include <span>

#include <glm/gtc/matrix_transform.hpp>

#include "gl/gl_work.h"
#include "gpu_tile.h"
#include "map_culling.h"
#include "sv_roads.h"

namespace navmap::render::gl {

namespace {

// seed 5.5: which occlusion effects a frame gets (glow needs something to hide roads and
// roads to show; the aura needs labels and buildings to fade).
bool wantsGlow(const MapLayers& l) { return l.glow_roads && l.buildings && (l.roads || l.route); }
bool wantsAura(const MapLayers& l) { return l.label_aura && l.labels && l.buildings; }

}  // namespace

// Times the passes one after another (RendererOptions::profile_passes): each lap waits for the GPU
// and adds the time since the previous lap to a slot of MapFrameStats (a pass drawn in two
// places adds up). The GL work since the previous lap (gl_work.h) is added on every frame; the
// times are free when off.
class PassClock {
public:
    explicit PassClock(bool on) : m_on(on), m_work(glWork()) {}
    void lap(double& slot, PassWork& work) {
        const PassWork now = glWork();
        work.draw_calls += now.draw_calls - m_work.draw_calls;
        work.vertices += now.vertices - m_work.vertices;
        work.bytes_uploaded += now.bytes_uploaded - m_work.bytes_uploaded;
        m_work = now;
        if (!m_on) return;
        glFinish();
        slot += msSince(m_t);
        m_t = Clock::now();
    }
    /// Charges nothing for the time and work since the last lap (a part with a clock of its own).
    void skip() {
        m_work = glWork();
        if (m_on) m_t = Clock::now();
    }

private:
    bool m_on = false;
    PassWork m_work;
    Clock::time_point m_t = Clock::now();
};

MapRenderer::MapRenderer(const RendererOptions& options, bool software, const GlFeatures& features)
    : m_options(options),
      m_features(features),
      m_style(MapStyle::day()),
      m_cache(options),
      m_roads(m_cache.roadIndexBuffer()),
      m_outlines(software) {
    if (options.warm_up) m_labels.warmUp();
}

MapRenderer::~MapRenderer() = default;

FrameContext MapRenderer::beginFrame(const MapFrame& frame, const RenderTarget& target, int target_id) {
    const std::span<GpuTile* const> tiles = m_cache.acquire(frame, target_id, m_stats, m_style.ground);
    const double aspect = static_cast<double>(target.width()) / target.height();
    const glm::mat4 projection = frame.camera.projection(aspect);
    const FrameContext ctx{
        .frame = frame,
        .target = target,
        .target_id = target_id,
        .style = m_style,
        .projection = projection,
        .viewport = {static_cast<float>(target.width()), static_cast<float>(target.height())},
        .frame_dt_s = frame.frame_dt_s,
        .tiles = tiles,
        .selection = selectionFades(m_style.roads, projection[1][1] * 0.5f * static_cast<float>(target.height()),
                                    frame.layers.road_selection),
        .whole_caps = !frame.layers.trim_joint_caps,
        .stats = m_stats,
    };
    // Clip x and y scaled down so that the planes x = +-w, y = +-w lie the widening further out.
    const float widening_px = roadWideningPx(m_style);
    const glm::mat4 grow = glm::scale(
        glm::mat4(1.0f), glm::vec3(1.0f / (1.0f + 2.0f * widening_px / static_cast<float>(target.width())),
                                   1.0f / (1.0f + 2.0f * widening_px / static_cast<float>(target.height())), 1.0f));
    for (GpuTile* g : tiles) {
        g->view = frame.camera.viewRelativeTo(g->origin);
        g->view_projection = projection * g->view;
        g->road_cull = grow * g->view_projection;
    }
    m_route.beginFrame();
    if (m_route.routeChanged(frame.route)) {
        // Another route, or none (clear_route): what the tiles kept of the old one goes now, on
        // every tile held, not when each is drawn again or evicted; and the allocator hands the
        // freed pages back.
        m_cache.forEachTile([&](GpuTile& g) { m_route.release(g); });
#ifdef __GLIBC__
        if (m_route.work().bytes_released > 0) ::malloc_trim(0);
#endif
    }
    if (ctx.routeShown()) m_route.update(ctx);
    return ctx;
}

void MapRenderer::render(const MapFrame& frame, const RenderTarget& target, int target_id) {
    m_stats = {};
    const auto t_frame = Clock::now();
    const PassWork work_start = glWork();
    PassClock clock(m_options.profile_passes || frame.profile_passes);
    const MapLayers& layers = frame.layers;

    const FrameContext ctx = beginFrame(frame, target, target_id);
    clock.lap(m_stats.uploads_ms, m_stats.uploads_work);

    SvRoads* sv =
        SvRoads::forFrame(m_sv_roads, frame, target, m_features);  // shadow-volume roads (seed 3.5), else null
    m_outlines.begin(ctx, sv != nullptr);
    // The road pieces in view are picked on another thread while this one sets up the buildings
    // and the terrain: llvmpipe rasterizes only after the whole scene is set up, so a core is
    // free meanwhile. The culling writes only the tiles' visible_* and the road pass's indices,
    // which nothing before the road passes reads.
    // Hidden blocks are left out where the whole terrain in view is drawn (none waits for upload).
    const bool cull_hidden = layers.cull_hidden_roads && layers.terrain && m_stats.tiles_pending == 0;
    if (layers.roads) m_side.start([&] { m_roads.cull(ctx, cull_hidden); });
    const SideTask::Scope side_scope(m_side);

    target.clear(m_style.sky_color.r, m_style.sky_color.g, m_style.sky_color.b);
    target.bindForDrawing(false);
    glDisable(GL_BLEND);
    glEnable(GL_DEPTH_TEST);
    glDepthMask(GL_TRUE);

    // Buildings before the roads, which test against terrain and buildings without writing depth
    // (junctions stay clean, buildings hide the roads behind them); and before the terrain where
    // nothing needs the terrain alone: the terrain behind them then fails the depth test before it
    // is shaded (llvmpipe tests depth before the fragment shader). Glowing roads and the label
    // aura (seed 5.5) keep the terrain's depth (the aura also its colour) before the buildings for
    // runOcclusionEffects(); the shadow-volume roads keep it in a target of their own (SvRoads).
    const bool terrain_alone = sv || wantsGlow(layers) || wantsAura(layers);
    // Glowing roads from the stencil (seed 5.5.2): the roads' fill pass marks where it is hidden
    // and not by the terrain, and the glow is one screen pass over those marks, with no road
    // drawn again. The road colour mode, the shadow-volume roads and a filter that marks the
    // road pixels in the stencil itself keep the glow that draws the road fill again.
    m_glow_from_stencil = wantsGlow(layers) && !sv && layers.glow_mode == MapLayers::GlowMode::SingleColor &&
                          m_outlines.roadMarkBits() == 0;
    if (layers.buildings && !terrain_alone) {
        m_buildings.draw(ctx);
        clock.lap(m_stats.buildings_ms, m_stats.buildings_work);
    }
    if (layers.terrain) {
        if (sv) sv->beginTerrain(target);  // + the terrain depth target (seed 3.5.2)
        glDepthFunc(GL_LESS);
        glEnable(GL_CULL_FACE);
        glCullFace(GL_BACK);
        m_terrain.draw(ctx);
        if (sv) sv->endTerrain(target);
        clock.lap(m_stats.terrain_ms, m_stats.terrain_work);
    }
    if (wantsGlow(layers) || wantsAura(layers)) {
        if (!m_effects) m_effects = std::make_unique<OcclusionEffects>();
        m_effects->captureTerrainDepth(target, wantsGlow(layers), wantsAura(layers));
    }
    if (layers.buildings && terrain_alone) {  // after the terrain (see above)
        // The label aura changes only the pixels where a building is seen (the stencil).
        OcclusionEffects::markBuildings(wantsAura(layers));
        m_buildings.draw(ctx);
        OcclusionEffects::markBuildings(false);
        clock.lap(m_stats.buildings_ms, m_stats.buildings_work);
    }
    if (layers.terrain && layers.far_ground) {  // what is still clear below the horizon: beyond the data
        m_far_ground.draw(ctx);
        clock.lap(m_stats.terrain_ms, m_stats.terrain_work);
    }
    drawRoadsAndRoute(ctx, sv, clock, m_glow_from_stencil ? m_effects->terrainDepth(target) : 0);
    // Screen-space dark outlines around roads and route (seed 3.6.3).
    if (m_outlines.enabled()) {
        m_outlines.draw(ctx, m_side);
        clock.lap(m_stats.outlines_ms, m_stats.outlines_work);
    }
    if (!layers.labels) {
        runOcclusionEffects(ctx);
        clock.skip();
        drawArrows(ctx);
    }
    // Labels (seed ch. 4, 5.5): after the outlines so they lie above the roads, before the marker,
    // and out of the marker's way.
    const std::optional<MarkerPass::OnScreen> marker = m_marker.place(ctx);
    if (layers.labels) {
        m_labels.layout(ctx, marker ? std::span<const glm::vec2>(marker->outline) : std::span<const glm::vec2>());
        clock.lap(m_stats.label_block_ms,
                  m_stats.labels_work);  // labels_ms is the pass's own CPU time; keep it out of marker_ms
        runOcclusionEffects(ctx);        // seed 5.5.2: composited before the labels (aura_ms, glow_ms)
        clock.skip();
        drawArrows(ctx);
        m_labels.draw(ctx);
        clock.lap(m_stats.label_block_ms, m_stats.labels_work);
    }
    // The street bar under the marker: where the view puts the car low in the frame (steep
    // ground), the car stays visible over the bar.
    if (frame.street_bar && (!frame.street_bar->name.empty() || !frame.street_bar->ref.empty())) {
        if (!m_guidance) m_guidance = std::make_unique<GuidanceOverlayPass>();
        m_guidance->drawStreetBar(*frame.street_bar, m_style, target);
        clock.skip();  // not the marker's time (the overlays after it are in total_ms only)
    }
    if (marker) m_marker.draw(ctx, *marker);
    clock.lap(m_stats.marker_ms, m_stats.marker_work);
    if (frame.guidance) {
        if (!m_guidance) m_guidance = std::make_unique<GuidanceOverlayPass>();
        m_guidance->draw(*frame.guidance, m_style, target);
    }
    if (frame.speed_limit && frame.speed_limit->kmh > 0) {
        if (!m_guidance) m_guidance = std::make_unique<GuidanceOverlayPass>();
        m_guidance->drawSpeedLimit(*frame.speed_limit, target);
    }
    if (frame.lanes && !frame.lanes->lanes.empty()) {
        if (!m_guidance) m_guidance = std::make_unique<GuidanceOverlayPass>();
        m_guidance->drawLanes(*frame.lanes, m_style, target);
    }

    glBindVertexArray(0);
    glBindTexture(GL_TEXTURE_2D, 0);
    m_cache.evict();
    m_stats.total_ms = msSince(t_frame);
    const PassWork work_end = glWork();
    m_stats.frame_work = {work_end.draw_calls - work_start.draw_calls, work_end.vertices - work_start.vertices,
                          work_end.bytes_uploaded - work_start.bytes_uploaded};
}

void MapRenderer::drawRoadsAndRoute(const FrameContext& ctx, SvRoads* sv, PassClock& clock, GLuint glow_terrain_depth) {
    if (ctx.layers().roads) {
        m_side.wait();  // RoadPass::cull
        m_roads.uploadIndices();
    }
    // Where the screen-space outlines can be (seed 3.6.3), worked out on the other thread after
    // the culling, while this one sets up the road passes. It reads what the culling and
    // RoutePass::update wrote and nothing the passes change.
    if (m_outlines.cellsFromQuads()) m_side.start([this, &ctx] { m_outlines.markCells(ctx, m_roads.indices()); });

    // Roads (seed 3.6.3): no blending, least important first, casing pass then fill pass.
    ctx.target.bindForDrawing(true);
    glDisable(GL_CULL_FACE);
    glDepthMask(GL_FALSE);
    glDepthFunc(GL_LEQUAL);
    m_outlines.beginRoadMarking();
    if (sv) {
        m_stats.road_segments += sv->draw(ctx.frame, ctx.projection, ctx.target, m_style.roads);
        m_stats.sv_roads = true;
        clock.lap(m_stats.sv_roads_ms, m_stats.sv_roads_work);
    }
    // With `glow_terrain_depth`, the fill pass (1) marks OcclusionEffects::kRoadFillStencilBit where
    // its fragments fail the depth test, drawn with the program's NAVMAP_TERRAIN_CUT variant, which
    // leaves out those behind the terrain alone (they fail the test anyway: no pixel changes). The
    // stencil then holds the road pixels a building hides (seed 5.5.2).
    const auto fill_pass = [&](bool route, const auto& draw) {
        if (!glow_terrain_depth) return draw(nullptr);
        ShaderProgram& cut = terrainCutProgram(route);
        glUseProgram(cut.id());
        glActiveTexture(GL_TEXTURE3);
        glBindTexture(GL_TEXTURE_2D, glow_terrain_depth);
        glActiveTexture(GL_TEXTURE0);
        glUniform1i(cut.uniform("u_terrain_depth"), 3);
        glEnable(GL_STENCIL_TEST);
        glStencilMask(OcclusionEffects::kRoadFillStencilBit);
        glStencilFunc(GL_ALWAYS, OcclusionEffects::kRoadFillStencilBit, OcclusionEffects::kRoadFillStencilBit);
        glStencilOp(GL_KEEP, GL_REPLACE, GL_KEEP);
        const auto drawn = draw(&cut);
        glDisable(GL_STENCIL_TEST);
        glStencilMask(0xFF);
        glActiveTexture(GL_TEXTURE3);
        glBindTexture(GL_TEXTURE_2D, 0);
        glActiveTexture(GL_TEXTURE0);
        return drawn;
    };
    if (ctx.layers().roads && !sv) {
        ShaderProgram& p = m_roads.program();
        glUseProgram(p.id());
        m_roads.drawWith(p, 0, ctx);
        m_stats.road_segments +=
            fill_pass(false, [&](ShaderProgram* cut) { return m_roads.drawWith(cut ? *cut : p, 1, ctx); });
        clock.lap(m_stats.roads_ms, m_stats.roads_work);
    }
    if (ctx.routeShown()) {
        ShaderProgram& p = m_route.program();
        glUseProgram(p.id());
        m_route.drawWith(p, 0, ctx);
        fill_pass(true, [&](ShaderProgram* cut) {
            m_route.drawWith(cut ? *cut : p, 1, ctx);
            return std::size_t{0};
        });
        clock.lap(m_stats.route_ms, m_stats.route_work);
    }
    m_outlines.endRoadMarking();
    glDepthMask(GL_TRUE);
}

ShaderProgram& MapRenderer::terrainCutProgram(bool route) {
    std::unique_ptr<ShaderProgram>& cut = route ? m_route_cut : m_roads_cut;
    if (!cut) {
        const char* defines = route ? "#define NAVMAP_ROUTE_PROGRESS 1\n#define NAVMAP_TERRAIN_CUT 1\n"
                                    : "#define NAVMAP_TERRAIN_CUT 1\n";
        cut = std::make_unique<ShaderProgram>(ShaderProgram::fromEmbedded("roads_geo.vert", "roads_geo.frag", defines));
    }
    return *cut;
}

void MapRenderer::runOcclusionEffects(const FrameContext& ctx) {
    const MapLayers& layers = ctx.layers();
    const bool glow = wantsGlow(layers), aura = wantsAura(layers);
    if (!m_effects || (!glow && !aura)) return;
    const bool profile = m_options.profile_passes || ctx.frame.profile_passes;
    if (profile) glFinish();
    PassClock clock(profile);
    if (aura) {
        // seed 5.5.1 step 2: the buildings (with the aura's program) and then the roads and the
        // route over them, as the scene draws them, into the layer behind the labels.
        auto buildings = [&](ShaderProgram& p) { m_buildings.drawWith(p, ctx); };
        // Over the far plane inside the auras: the terrain cut variants (terrain depth on unit 3).
        auto roads = [&] {
            for (const bool route : {false, true}) {
                if (route ? !ctx.routeShown() : !layers.roads) continue;
                ShaderProgram& p = terrainCutProgram(route);
                glUseProgram(p.id());
                glUniform1i(p.uniform("u_terrain_depth"), 3);
                for (int pass = 0; pass < 2; ++pass) {
                    if (route)
                        m_route.drawWith(p, pass, ctx);
                    else
                        m_roads.drawWith(p, pass, ctx);
                }
            }
        };
        m_effects->aura(ctx.target, m_labels.occluders(ctx), ctx.projection, m_style, buildings, roads);
        clock.lap(m_stats.aura_ms, m_stats.aura_work);
    }
    if (glow && m_glow_from_stencil) {
        m_effects->glowFromStencil(ctx.target, layers, m_style);
        clock.lap(m_stats.glow_ms, m_stats.glow_work);
    } else if (glow) {
        // seed 5.5.2: the fill of the roads and the route again, for the hidden parts.
        auto roads = [&](ShaderProgram& p) {
            if (layers.roads) m_roads.drawWith(p, 1, ctx);
            if (ctx.routeShown()) m_route.drawWith(p, 1, ctx);
        };
        m_effects->glow(ctx.target, layers, m_style, roads);
        clock.lap(m_stats.glow_ms, m_stats.glow_work);
    }
    ctx.target.bindForDrawing(false);
}

void MapRenderer::drawArrows(const FrameContext& ctx) {
    if (!ManeuverArrowPass::wanted(ctx.frame)) return;
    if (!m_arrows) m_arrows = std::make_unique<ManeuverArrowPass>();
    std::vector<ArrowTile> arrow_tiles(ctx.tiles.size());
    for (std::size_t i = 0; i < ctx.tiles.size(); ++i) {
        const GpuTile& g = *ctx.tiles[i];
        ArrowTile& a = arrow_tiles[i];
        a.origin = g.origin;
        a.morph = g.morph;
        a.view = g.view;
        if (g.grid_size < 2) continue;
        const double spacing = g.size_m / double(g.grid_size - 1);
        a.grid = {g.grid_size, spacing, g.heights.data()};
        for (std::size_t j = 0; j < a.ancestors.size(); ++j)
            a.ancestors[j] = {g.grid_size, spacing, g.ancestor_heights[j].data()};
    }
    const GLuint terrain_depth = m_effects && wantsGlow(ctx.layers()) ? m_effects->terrainDepth(ctx.target) : 0;
    m_arrows->draw(ctx.frame, m_style, ctx.target, ctx.projection, arrow_tiles, terrain_depth);
}

}  // namespace navmap::render::gl
