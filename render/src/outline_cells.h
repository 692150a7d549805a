// SPDX-License-Identifier: Apache-2.0
#pragma once
// Where the screen-space road outlines can be (seed 3.6.3 "Outlines"): a coarse grid of screen
// cells marked on the CPU from the road and route quads in view, so that the 3x3 max filter runs
// only there. It replaces a marking pass on the GPU: on a software rasterizer that pass cost the
// render thread the vertex work of every piece again and the rasterizer its stencil writes.

#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

namespace navmap::render {

/// A marked screen rectangle, in pixels from the lower-left corner (GL window coordinates).
struct CellRect {
    int x0 = 0, y0 = 0, x1 = 0, y1 = 0;  ///< [x0, x1) x [y0, y1)
};

/// How roads_geo.vert turns a piece into its quad: the width on the ground and its distance
/// scaling (seed 3.6.3), and the view-space scale towards the camera against z-fighting (3.6.2).
struct QuadShape {
    float width_m = 0.0f;  ///< full width, casing included
    float scale_threshold_m = 0.0f;
    float max_scale = 1.0f;
    float z_offset_alpha = 0.0f;
    /// The least on-screen width of the fill (RoadStyle::min_width_px, 0: none) and the fill's
    /// width on the ground: where the fill is narrower on screen, the shader moves the quad's
    /// upper side up by as much as min_width_px * width_m / fill_width_m.
    float min_width_px = 0.0f;
    float fill_width_m = 0.0f;
};

/// Pixels of a row per texel of the bit-packed road mask (outline_pack.frag) and of the edge mask.
inline constexpr int kPackedMaskPixels = 8;
[[nodiscard]] inline int packedMaskWidth(int width) { return (width + kPackedMaskPixels - 1) / kPackedMaskPixels; }

/// The outline's pixels of a binary road mask, found on the CPU (seed 3.6.3: the 3x3 maximum of
/// road intensity minus the pixel's own, for a mask of 0 and 1; MapLayers::OutlineMask::Cpu):
/// texel (g, y) of `edges` holds as bits 0..7 whether the pixels 8g .. 8g + 7 of row y are not
/// road pixels (a mask byte above 127, the shaders' > 0.5) and have one among the 3x3 around
/// them, the screen's border clamped as the filter's fetches clamp it. `mask`: width x height
/// bytes, row after row; `edges`: packedMaskWidth(width) x height texels in the same row order.
void outlineEdges(const std::uint8_t* mask, int width, int height, std::uint16_t* edges);

class OutlineCells {
public:
    /// Starts a frame: a viewport of `width` x `height` pixels, `cell_px` square cells, and the
    /// filter's reach around every projected quad, in pixels.
    void reset(int width, int height, int cell_px, float reach_px);

    /// The camera for the following markQuad calls: `view` relative to the pieces' origin.
    void setView(const glm::mat4& view, const glm::mat4& projection);

    /// Marks the cells that the quad of the piece p0-p1 (roads_geo.vert: caps included, corners
    /// at p0 +- w/2 (n +- t) and p1 likewise) can touch on screen, grown by the reach, and by the
    /// shader's widening to the least on-screen width where the piece's fill is narrower. The part
    /// of the quad behind the near plane is clipped away as the GPU clips it.
    /// `cap_reach`: how far the quad reaches beyond p0 and p1, in half widths
    /// (RoadInstance::cap_reach).
    void markQuad(glm::vec3 p0, glm::vec3 p1, const QuadShape& shape, glm::vec2 cap_reach = glm::vec2(1.0f));

    /// Marks the cells that hold an edge pixel of outlineEdges' `edges` (`groups` texels per row
    /// of the reset height): where the road mask is known, the filter runs exactly there. Needs
    /// cells of kPackedMaskPixels (reset's `cell_px`, one texel per cell row); throws
    /// std::logic_error otherwise.
    void markEdges(const std::uint16_t* edges, int groups);

    /// The marked cells as rectangles: runs of cells along a row, with equal runs of the rows
    /// above merged into one rectangle. With `group` > 1 the cells of a row go in groups of that
    /// many from the left edge, a group counting as marked when any of its cells is: coarser
    /// rectangles over a superset (the outline mask's packing pass, whose cells are one texel wide).
    [[nodiscard]] std::vector<CellRect> rects(int group = 1) const;

    /// Whether the pixel (x, y) lies in a marked cell.
    [[nodiscard]] bool covers(int x, int y) const;

private:
    void markPolygon(const glm::vec2* points, int count, float reach);
    /// How far roads_geo.vert may move the quad's upper side beyond its projection, in pixels:
    /// 0 where the fill is at least QuadShape::min_width_px wide on screen at both ends.
    [[nodiscard]] float widening(const glm::vec4& c0, const glm::vec4& c1, const glm::vec4& across,
                                 const glm::vec4& along, const QuadShape& shape) const;

    int m_width = 0, m_height = 0, m_cell = 8;
    int m_columns = 0, m_rows = 0;
    float m_reach = 0.0f;
    glm::mat4 m_view{1.0f}, m_view_projection{1.0f};
    glm::vec4 m_eye_clip{0.0f};          // the camera's position in clip space: projection * (0, 0, 0, 1)
    std::vector<std::uint8_t> m_marked;  // m_rows x m_columns
};

}  // namespace navmap::render
