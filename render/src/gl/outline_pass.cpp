// SPDX-License-Identifier: Apache-2.0
#include "outline_pass.h"

#include <cmath>
#include <cstddef>

#include <glm/gtc/type_ptr.hpp>

#include "gl/gl_work.h"
#include "gpu_tile.h"
#include "map_culling.h"

namespace navmap::render::gl {

namespace {

// How far (pixels) the outline filter reaches from a road pixel: the 3x3 filter's 1 px, half a
// pixel to the centre of the pixel that reads the road, and room for the GPU's rounding.
constexpr float kOutlineReachPx = 2.0f;
// Side of the screen cells marked for the outline filter (OutlineCells), pixels: llvmpipe shades
// blocks of 4 x 4 pixels in tiles of 64, so multiples of 4 waste no partial blocks; smaller cells
// follow the roads closer but cost more CPU to mark.
constexpr int kOutlineCellPx = 8;
static_assert(kOutlineCellPx == kPackedMaskPixels, "the packing pass turns a cell into one column of texels");
// Cells per rectangle of the outline mask's packing pass (markCells).
constexpr int kOutlinePackGroup = 4;
// Stencil bit the road and route passes set on the pixels they draw, so that the outline filter
// leaves them out: a road pixel holds its neighbourhood's maximum intensity itself, its edge
// strength is 0. llvmpipe then skips the 4x4 blocks inside roads before shading. (The glow uses
// bit 7, occlusion_effects.cpp.)
constexpr GLuint kRoadStencilBit = 0x40;

}  // namespace

OutlinePass::OutlinePass(bool software)
    : m_software(software),
      m_full(ShaderProgram::fromEmbedded("screen_outline.vert", "screen_outline.frag")),
      m_cells_program(ShaderProgram::fromEmbedded("screen_cells.vert", "screen_outline.frag")),
      m_packed(
          ShaderProgram::fromEmbedded("screen_cells.vert", "screen_outline.frag", "#define NAVMAP_PACKED_MASK 1\n")),
      m_pack(ShaderProgram::fromEmbedded("screen_cells.vert", "outline_pack.frag")),
      m_edges(ShaderProgram::fromEmbedded("screen_cells.vert", "screen_outline.frag", "#define NAVMAP_EDGE_MASK 1\n")) {
    glGenVertexArrays(1, &m_empty_vao);
    glGenVertexArrays(1, &m_cell_vao);
    glGenBuffers(1, &m_cell_vbo);
    glBindVertexArray(m_cell_vao);
    glBindBuffer(GL_ARRAY_BUFFER, m_cell_vbo);
    glEnableVertexAttribArray(0);
    glVertexAttribPointer(0, 2, GL_FLOAT, GL_FALSE, 0, nullptr);
    glBindVertexArray(0);
}

OutlinePass::~OutlinePass() {
    glDeleteVertexArrays(1, &m_empty_vao);
    glDeleteVertexArrays(1, &m_cell_vao);
    glDeleteBuffers(1, &m_cell_vbo);
}

void OutlinePass::begin(const FrameContext& ctx, bool sv_roads) {
    const MapLayers& layers = ctx.layers();
    m_on = layers.outlines && (layers.roads || layers.route);
    m_cells_on = m_on && layers.outlines_near_roads && !sv_roads;
    // On a software rasterizer the cells come from the road mask itself, read back after the
    // roads (markEdgeCells); elsewhere from the quads (markCells), and the GPU packs.
    using OutlineMask = MapLayers::OutlineMask;
    const OutlineMask mask_at = layers.outline_mask;
    m_edges_on_cpu = m_cells_on && (mask_at == OutlineMask::Cpu || (mask_at == OutlineMask::Auto && m_software)) &&
                     ctx.target.readsMaskBytes();
    // With the outline cells from the quads, the road and route pixels also mark kRoadStencilBit
    // for the filter: the same pixels as the mask (drawn, not discarded, depth test passed). Not
    // when multisampled: the filter's stencil test would then be per sample, unlike its mask. Not
    // with the edges found on the CPU, which leave out the road pixels themselves. The full-screen
    // filter stays without either, the reference the cells are tested against.
    m_mark_roads = m_cells_on && ctx.target.samples() == 0 && !m_edges_on_cpu;
}

void OutlinePass::beginRoadMarking() const {
    if (!m_mark_roads) return;
    glEnable(GL_STENCIL_TEST);
    glStencilMask(kRoadStencilBit);
    glStencilFunc(GL_ALWAYS, kRoadStencilBit, kRoadStencilBit);
    glStencilOp(GL_KEEP, GL_KEEP, GL_REPLACE);
}

GLuint OutlinePass::roadMarkBits() const { return m_mark_roads ? kRoadStencilBit : 0; }

void OutlinePass::endRoadMarking() const {
    if (!m_mark_roads) return;
    glDisable(GL_STENCIL_TEST);
    glStencilMask(0xFF);
}

void OutlinePass::draw(const FrameContext& ctx, SideTask& side) {
    const RenderTarget& target = ctx.target;
    GLuint edges = 0;
    if (m_edges_on_cpu) {
        edges = markEdgeCells(target);
        ctx.stats.outline_mask_on_cpu = true;
    }
    target.resolveMask();
    glDisable(GL_DEPTH_TEST);
    if (m_cells_on) {
        side.wait();  // markCells, when it runs
        ctx.stats.outline_pixels = m_cell_pixels;
        ctx.stats.outline_cells_ms = m_cell_ms;
        glBindVertexArray(m_cell_vao);
        glBindBuffer(GL_ARRAY_BUFFER, m_cell_vbo);
        countedBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(m_cell_vertices.size() * sizeof(glm::vec2)),
                          m_cell_vertices.data(), GL_STREAM_DRAW);
        glBindBuffer(GL_ARRAY_BUFFER, 0);
    } else {
        ctx.stats.outline_pixels = static_cast<std::size_t>(target.width()) * static_cast<std::size_t>(target.height());
        glBindVertexArray(m_empty_vao);
    }
    // Vertices [first, end) of m_cell_vertices: the filter's cells, then the packing pass's.
    auto draw_cells = [](std::size_t first, std::size_t end) {
        if (end > first) countedDrawArrays(GL_TRIANGLES, static_cast<GLint>(first), static_cast<GLsizei>(end - first));
    };
    glActiveTexture(GL_TEXTURE0);
    GLuint mask = m_edges_on_cpu ? edges : target.maskTexture();
    if (m_mark_roads) {
        // The mask bit-packed over the cells (outline_pack.frag); the rest of the packed
        // texture is 0, as the mask is outside the cells (every road quad lies in them).
        mask = target.bindPackedMask();
        const GLuint zero[4] = {0, 0, 0, 0};
        glClearBufferuiv(GL_COLOR, 0, zero);
        glUseProgram(m_pack.id());
        glBindTexture(GL_TEXTURE_2D, target.maskTexture());
        glUniform1i(m_pack.uniform("u_road_mask"), 0);
        // Pixel x maps to texel x / kPackedMaskPixels: a cell is one column of texels.
        glUniform2f(m_pack.uniform("u_viewport"), static_cast<float>(kPackedMaskPixels * target.packedMaskWidth()),
                    static_cast<float>(target.height()));
        draw_cells(m_pack_first, m_cell_vertices.size());
        target.bindForDrawing(false);
    }
    ShaderProgram& p = m_edges_on_cpu ? m_edges : m_mark_roads ? m_packed : m_cells_on ? m_cells_program : m_full;
    glEnable(GL_BLEND);
    glBlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA);
    glUseProgram(p.id());
    glBindTexture(GL_TEXTURE_2D, mask);
    glUniform1i(p.uniform("u_mask"), 0);
    glUniform3fv(p.uniform("u_outline_color"), 1, glm::value_ptr(ctx.style.roads.outline));
    glUniform1f(p.uniform("u_strength"), ctx.style.roads.outline_strength);
    if (m_cells_on) {
        glUniform2f(p.uniform("u_viewport"), static_cast<float>(target.width()), static_cast<float>(target.height()));
    }
    if (m_mark_roads) {
        glEnable(GL_STENCIL_TEST);
        glStencilFunc(GL_NOTEQUAL, kRoadStencilBit, kRoadStencilBit);
        glStencilOp(GL_KEEP, GL_KEEP, GL_KEEP);
    }
    if (m_cells_on) {
        draw_cells(0, m_pack_first);
    } else {
        countedDrawArrays(GL_TRIANGLES, 0, 3);  // full screen
    }
    glBindTexture(GL_TEXTURE_2D, 0);
    glDisable(GL_BLEND);
    glDisable(GL_STENCIL_TEST);
}

void OutlinePass::markCells(const FrameContext& ctx, std::span<const std::uint32_t> road_indices) {
    const MapFrame& frame = ctx.frame;
    const auto t0 = Clock::now();
    m_cells.reset(ctx.target.width(), ctx.target.height(), kOutlineCellPx, kOutlineReachPx);
    const RoadStyle& rs = ctx.style.roads;
    QuadShape shape{0.0f, rs.scale_threshold_m, rs.max_scale, rs.z_offset_alpha, rs.min_width_px, 0.0f};
    // Roads: the pieces RoadPass::cull kept, each with its widest pass (fill and casing).
    for (const GpuTile* g : ctx.tiles) {
        if (!frame.layers.roads) break;
        m_cells.setView(g->view, ctx.projection);
        for (GLsizei k = g->visible_first; k < g->visible_first + g->visible_count; ++k) {
            const RoadInstance& r = g->road_pieces[road_indices[6 * static_cast<std::size_t>(k)] / 4];
            const RoadClassStyle& c = rs.of(static_cast<int>(std::lround(r.road_class)));
            shape.width_m = c.outerWidth();
            shape.fill_width_m = c.width_m;
            m_cells.markQuad(r.p0, r.p1, shape, ctx.whole_caps ? glm::vec2(1.0f) : r.cap_reach);
        }
    }
    // The route with its casing and its larger offset (road_uniforms.h), as drawn this frame.
    if (frame.layers.route && frame.route) {
        shape.width_m = routeOuterWidth(ctx.style.route_width_m);
        shape.fill_width_m = ctx.style.route_width_m;
        shape.z_offset_alpha = 1.5f * rs.z_offset_alpha;
        for (const GpuTile* g : ctx.tiles) {
            if (!g->route_count || !g->route_in_view) continue;
            m_cells.setView(g->view, ctx.projection);
            for (const RoadInstance& r : g->route_instances) m_cells.markQuad(r.p0, r.p1, shape);
        }
    }
    filterCellVertices();
    // The packing pass's rectangles: cells in groups of four along a row, so that its texels
    // (one per cell and row) fill llvmpipe's 4 x 4 blocks; a block costs the same, covered in
    // part or whole.
    m_pack_first = m_cell_vertices.size();
    for (const CellRect& r : m_cells.rects(kOutlinePackGroup)) addCellRect(r);
    m_cell_ms = msSince(t0);
}

void OutlinePass::filterCellVertices() {
    m_cell_vertices.clear();
    m_cell_pixels = 0;
    for (const CellRect& r : m_cells.rects()) {
        m_cell_pixels += static_cast<std::size_t>(r.x1 - r.x0) * static_cast<std::size_t>(r.y1 - r.y0);
        addCellRect(r);
    }
}

void OutlinePass::addCellRect(const CellRect& r) {
    // Whole cells even at the right edge of the screen (the GPU clips the overhang): the packing
    // pass turns each into a column of packed texels.
    const int x1 = (r.x1 + kOutlineCellPx - 1) / kOutlineCellPx * kOutlineCellPx;
    const glm::vec2 lo(static_cast<float>(r.x0), static_cast<float>(r.y0)),
        hi(static_cast<float>(x1), static_cast<float>(r.y1));
    m_cell_vertices.insert(m_cell_vertices.end(), {lo, {hi.x, lo.y}, {lo.x, hi.y}, {lo.x, hi.y}, {hi.x, lo.y}, hi});
}

GLuint OutlinePass::markEdgeCells(const RenderTarget& target) {
    // On llvmpipe the read is a copy in memory once the roads are rasterized (the packing pass
    // would wait for them too); finding the edges costs a multiply per 8 pixels and a few bit
    // operations per 64. The filter then reads one texel per pixel, over the cells that hold an
    // edge only.
    target.readMask(m_mask_bytes);
    const auto t0 = Clock::now();
    const int w = target.width(), h = target.height(), groups = target.packedMaskWidth();
    m_edge_mask.resize(static_cast<std::size_t>(groups) * static_cast<std::size_t>(h));
    outlineEdges(m_mask_bytes.data(), w, h, m_edge_mask.data());
    m_cells.reset(w, h, kOutlineCellPx, 0.0f);
    m_cells.markEdges(m_edge_mask.data(), groups);
    filterCellVertices();
    m_pack_first = m_cell_vertices.size();  // no packing pass
    m_cell_ms = msSince(t0);
    return target.uploadPackedMask(m_edge_mask.data());
}

}  // namespace navmap::render::gl
