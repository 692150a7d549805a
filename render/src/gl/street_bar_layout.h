// SPDX-License-Identifier: Apache-2.0
#pragma once
// Where the current street's bar (MapFrame::street_bar) stands and what it says: its text
// ("name · ref", or the one there is), cut with an ellipsis to the bar's widest, and the panel
// sized to that text at the bottom centre of the frame. Laid out for 800 x 240 and scaled like
// the guidance overlay (guidanceLayout's unit). The overlay pass draws it, the label pass keeps
// labels out of it: both lay it out with their own text engine (the same fonts, the same result).
// Private to render/.

#include <string>

#include <glm/vec2.hpp>

#include "navmap/render/map_frame.h"
#include "navmap/render/text/text_engine.h"

namespace navmap::render::gl {

/// The bar on a target (screen pixels, origin top left, y down).
struct StreetBarLayout {
    std::string text;           ///< what is drawn (UTF-8); empty: no bar
    bool cut = false;           ///< the text was cut and ends with "…"
    float text_px = 0.0f;       ///< em size of the text
    glm::vec2 text_centre{0};   ///< centre of the text's box
    glm::vec2 lo{0}, hi{0};     ///< the panel's corners
    float corner_px = 0.0f;     ///< radius of the panel's rounded corners
    float max_width_px = 0.0f;  ///< the widest the panel gets
};

/// "name · ref"; the one there is when the other is empty (or the same); "" when both are.
std::string streetBarText(const StreetBar& bar);

/// Font the bar's text is set in.
inline constexpr text::FontStyle kStreetBarFont = text::FontStyle::Bold;

/// The bar for `bar` on a width x height target: text 22 px in the 800 x 240 layout, 16 px of
/// panel either side and 6 px above and below it, 10 px above the bottom edge, centred; at most
/// 60 % of the width (a longer text is cut at a character and ends with "…"). Measures with
/// `engine` (call after its beginFrame for the frame).
StreetBarLayout streetBarLayout(text::TextEngine& engine, const StreetBar& bar, int width, int height);

}  // namespace navmap::render::gl
