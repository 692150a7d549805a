// SPDX-License-Identifier: Apache-2.0
#pragma once
// Screen-space dark outlines around roads and route (seed 3.6.3): a 3x3 filter over the road
// mask that the road passes write. The filter runs only on the screen cells where road pixels can
// be: found from the road and route quads in view (on a thread beside the render thread, the
// mask then packed on the GPU and the road pixels left out by a stencil bit the road passes set),
// or on software rasterizers from the mask read back; else over the whole screen.
// Private to render/.

#include <GLES3/gl3.h>

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include <glm/glm.hpp>

#include "frame_context.h"
#include "outline_cells.h"
#include "shader_program.h"
#include "side_task.h"

namespace navmap::render::gl {

class OutlinePass {
public:
    /// `software`: the context renders on a software rasterizer (DeviceInfo::software).
    /// Compiles the filter programs (throws RenderError).
    explicit OutlinePass(bool software);
    ~OutlinePass();
    OutlinePass(const OutlinePass&) = delete;
    OutlinePass& operator=(const OutlinePass&) = delete;

    /// How this frame's outlines are found (from the layers, the target and whether the roads are
    /// shadow volumes, which have no quads); call first in every frame.
    void begin(const FrameContext& ctx, bool sv_roads);
    [[nodiscard]] bool enabled() const { return m_on; }
    /// Whether markCells() is to run this frame (the cells from the quads).
    [[nodiscard]] bool cellsFromQuads() const { return m_cells_on && !m_edges_on_cpu; }
    /// The screen cells where the filter can find road pixels: the quads of the road pieces in
    /// view (`road_indices`: RoadPass::indices() after its cull) and of the route, grown by the
    /// filter's reach. No GL calls: it runs beside the render thread.
    void markCells(const FrameContext& ctx, std::span<const std::uint32_t> road_indices);
    /// Around the road and route passes: with the cells from the quads (not multisampled), their
    /// pixels also set the stencil bit that keeps the filter off the road pixels themselves.
    void beginRoadMarking() const;
    /// The stencil bits the road and route pixels set between beginRoadMarking() and
    /// endRoadMarking() (0: none), which a pass drawn over a road after it clears.
    [[nodiscard]] GLuint roadMarkBits() const;
    void endRoadMarking() const;
    /// The filter over the frame (after the roads and route); waits on `side` for markCells().
    void draw(const FrameContext& ctx, SideTask& side);

private:
    /// The cells from the road mask itself, on software rasterizers (MapLayers::outline_mask): the
    /// mask read back, its edge pixels (outlineEdges) uploaded into the packed mask's texture, and
    /// the cells that hold them into m_cells and m_cell_vertices. Needs target.readsMaskBytes();
    /// returns the texture.
    GLuint markEdgeCells(const RenderTarget& target);
    /// m_cell_vertices anew with the filter's cells, m_cells' rectangles, and m_cell_pixels their area.
    void filterCellVertices();
    /// Appends the rectangle's two triangles to m_cell_vertices (whole cells at the right edge).
    void addCellRect(const CellRect& r);

    bool m_software = false;
    ShaderProgram m_full;           // the filter over the whole screen
    ShaderProgram m_cells_program;  // the filter over the cells near roads (markCells)
    ShaderProgram m_packed;         // the same over the packed mask, road pixels left out by the stencil
    ShaderProgram m_pack;           // packs the mask over the cells (outline_pack.frag)
    ShaderProgram m_edges;          // the filter over edge pixels found on the CPU (markEdgeCells)
    GLuint m_empty_vao = 0;
    GLuint m_cell_vao = 0, m_cell_vbo = 0;
    // This frame (begin()).
    bool m_on = false, m_cells_on = false, m_edges_on_cpu = false, m_mark_roads = false;
    OutlineCells m_cells;                    // where the outlines can be
    std::vector<glm::vec2> m_cell_vertices;  // its rectangles, two triangles each, pixels
    std::size_t m_pack_first = 0;            // from here: the packing pass's rectangles
    std::size_t m_cell_pixels = 0;           // their area
    std::vector<std::uint8_t> m_mask_bytes;  // markEdgeCells: the road mask read back
    std::vector<std::uint16_t> m_edge_mask;  // and its edge pixels
    double m_cell_ms = 0;                    // CPU time of markCells or markEdgeCells
};

}  // namespace navmap::render::gl
