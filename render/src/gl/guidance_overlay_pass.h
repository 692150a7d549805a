// SPDX-License-Identifier: Apache-2.0
#pragma once
// The guidance overlay (MapFrame::guidance), drawn last over the map frame in screen space: the
// next manoeuvre as a large symbol (guidance_symbol.h: plain triangles), the distance to it in
// large text, the street to turn into, and the remaining distance and time, with the SDF text of
// navmap_text. Laid out for the head-up display's 800 x 240 and scaled with the target. Owns its
// own text engine and atlas, so that it works without the label pass (the HUD has no labels).
// Also the speed limit sign (MapFrame::speed_limit): a white disc in a red ring with the limit
// in black, in a corner, on the same layout scale; and the current street's bar
// (MapFrame::street_bar, street_bar_layout.h). Private to render/.

#include <GLES3/gl3.h>

#include <cstddef>
#include <memory>
#include <utility>
#include <vector>

#include <glm/vec2.hpp>

#include "navmap/render/map_frame.h"
#include "navmap/render/text/text_engine.h"
#include "render_target.h"
#include "shader_program.h"

namespace navmap::render::gl {

class TextLayer;

/// Where the overlay puts its parts on a target (screen pixels, origin top left, y down).
struct GuidanceLayout {
    float unit = 1.0f;  ///< pixels per pixel of the 800 x 240 layout
    glm::vec2 symbol_centre{0.0f};
    float symbol_px = 0.0f;       ///< side of the symbol's square
    glm::vec2 distance_at{0.0f};  ///< baseline start of the distance text
    float distance_px = 0.0f;     ///< its em size
    glm::vec2 street_at{0.0f};
    float street_px = 0.0f;
    glm::vec2 remaining_right{0.0f};  ///< baseline end (right-aligned) of the remaining distance and time
    float remaining_px = 0.0f;
};

/// The layout for a width x height target.
GuidanceLayout guidanceLayout(int width, int height);

/// Where the speed limit sign stands (screen pixels, origin top left, y down).
struct SpeedLimitSignLayout {
    glm::vec2 centre{0.0f};
    float radius = 0.0f;        ///< outer edge of the red ring
    float inner_radius = 0.0f;  ///< inner edge of the ring: the white disc
    float text_px = 0.0f;       ///< em size of the number
};

/// The sign's place in `corner` of a width x height target: 72 px across in the 800 x 240
/// layout (guidanceLayout's unit), 14 px from both edges; the number's size by its digits.
SpeedLimitSignLayout speedLimitSignLayout(int width, int height, SignCorner corner, int digits);

/// Where a lane row's boxes stand (screen pixels, origin top left, y down).
struct LaneRowLayout {
    glm::vec2 origin{0.0f};  ///< top left of the first box
    glm::vec2 box{0.0f};     ///< one lane's box
    float gap = 0.0f;        ///< between boxes
    float pad = 0.0f;        ///< the panel around the row (top centre only)
    [[nodiscard]] float width(std::size_t lanes) const {
        return lanes == 0 ? 0.0f : float(lanes) * box.x + float(lanes - 1) * gap;
    }
};
/// The row in the HUD's guidance panel: right of the symbol, from its top edge (26 x 28 px boxes
/// in the 800 x 240 layout).
LaneRowLayout laneRowInPanel(const GuidanceLayout& l);
/// The row on its own at the top centre of a width x height target (34 x 40 px boxes in the
/// 800 x 240 layout, its panel 14 px below the top edge): MapFrame::lanes.
LaneRowLayout laneRowAtTop(int width, int height, std::size_t lanes);
/// The panel behind a top-centre row (lo, hi corners) that labels keep out of.
std::pair<glm::vec2, glm::vec2> laneRowPanel(const LaneRowLayout& l, std::size_t lanes);

/// Needs a current GLES 3 context (create, use, destroy on its thread).
class GuidanceOverlayPass {
public:
    /// Loads the fonts and compiles the shaders; throws TextError / RenderError.
    GuidanceOverlayPass();
    ~GuidanceOverlayPass();
    GuidanceOverlayPass(const GuidanceOverlayPass&) = delete;
    GuidanceOverlayPass& operator=(const GuidanceOverlayPass&) = delete;

    /// Draws `overlay` over `target` (no depth test). Leaves `target` bound for drawing.
    void draw(const GuidanceOverlay& overlay, const MapStyle& style, const RenderTarget& target);
    /// Draws the speed limit sign over `target` (nothing when sign.kmh <= 0). Leaves `target`
    /// bound for drawing.
    void drawSpeedLimit(const SpeedLimitSign& sign, const RenderTarget& target);
    /// Draws the current street's bar over `target` in `style`'s street bar colours (nothing when
    /// its texts are empty). Leaves `target` bound for drawing.
    void drawStreetBar(const StreetBar& bar, const MapStyle& style, const RenderTarget& target);
    /// Draws MapFrame::lanes at the top centre on its panel (nothing without lanes). Leaves
    /// `target` bound for drawing.
    void drawLanes(const LaneRow& row, const MapStyle& style, const RenderTarget& target);

private:
    /// The boxes and arrows of `row` laid out by `l` (blending set up by the caller).
    void drawLaneBoxes(const LaneRow& row, const LaneRowLayout& l, const MapStyle& style, glm::vec2 viewport);
    void drawTriangles(const std::vector<glm::vec2>& vertices, glm::vec4 color, glm::vec2 viewport);

    text::TextEngine m_engine;
    std::unique_ptr<TextLayer> m_text;
    ShaderProgram m_program;
    GLuint m_vao = 0, m_vbo = 0;
};

}  // namespace navmap::render::gl
