// SPDX-License-Identifier: Apache-2.0
#include "map_label_pass.h"

#include <GLES3/gl3.h>

#include <cstddef>

#include "gpu_tile.h"

namespace navmap::render::gl {

void MapLabelPass::warmUp() {
    if (!m_text) m_text = std::make_shared<LabelText>();
    m_text->engine.prefetchGlyphs(text::TextEngine::latinCodepoints());
}

void MapLabelPass::layout(const FrameContext& ctx, std::span<const glm::vec2> keep_out) {
    if (!m_text) m_text = std::make_shared<LabelText>();
    std::unique_ptr<LabelPass>& pass = m_passes[ctx.target_id];
    if (!pass) pass = std::make_unique<LabelPass>(m_text);
    m_current = pass.get();
    m_tile_labels.clear();
    for (const GpuTile* g : ctx.tiles) {
        HeightGrid grid;
        if (g->grid_size >= 2 && g->heights.size() == static_cast<std::size_t>(g->grid_size) * g->grid_size) {
            grid = {g->grid_size, g->size_m / (g->grid_size - 1), g->heights.data()};
        }
        m_tile_labels.push_back({g->source, g->origin, g->label_points, grid, g->size_m});
    }
    ctx.target.bindForDrawing(false);
    m_current->layout(ctx.frame, m_tile_labels, {ctx.target.width(), ctx.target.height()}, ctx.stats, keep_out,
                      ctx.style);
}

std::span<const LabelOccluder> MapLabelPass::occluders(const FrameContext& ctx) const {
    if (!ctx.layers().labels) return {};
    const auto it = m_passes.find(ctx.target_id);
    return it != m_passes.end() && it->second ? it->second->occluders() : std::span<const LabelOccluder>();
}

void MapLabelPass::draw(const FrameContext& ctx) {
    const RenderTarget& target = ctx.target;
    target.bindForDrawing(false);
    m_current->draw({target.width(), target.height()}, ctx.stats);
    if (ctx.layers().measure_label_occlusion) {
        glFinish();  // the frame's drawing so far is the frame's cost, not the measurement's
        const auto t_occlusion = Clock::now();
        m_current->measureOcclusion(target.depthStencilRenderbuffer(), target.samples(),
                                    {target.width(), target.height()}, ctx.stats);
        target.bindForDrawing(false);
        ctx.stats.label_occlusion_ms = msSince(t_occlusion);
    }
}

}  // namespace navmap::render::gl
