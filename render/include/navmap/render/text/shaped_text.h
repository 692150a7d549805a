// SPDX-License-Identifier: Apache-2.0
#pragma once
// Result of shaping one UTF-8 string: glyphs with their font, advances and offsets in em units.

#include <cstdint>
#include <vector>

#include "navmap/render/text/font_collection.h"

namespace navmap::render::text {

/// One positioned glyph. Units are em (multiply by the font size in pixels); x to the right,
/// y up (font convention).
struct ShapedGlyph {
    FontId font = 0;
    std::uint32_t glyph = 0;    ///< glyph index in `font`; 0 is .notdef
    std::uint32_t cluster = 0;  ///< byte offset of the source character in the UTF-8 string
    float x_advance = 0.0f;
    float y_advance = 0.0f;
    float x_offset = 0.0f;
    float y_offset = 0.0f;
};

/// A shaped single-line string, glyphs in visual order (left to right).
struct ShapedText {
    std::vector<ShapedGlyph> glyphs;
    float advance = 0.0f;           ///< total pen advance, em
    float ascender = 0.8f;          ///< line box above the baseline (primary font), em
    float descender = -0.2f;        ///< line box below the baseline (negative), em
    float cap_height = 0.73f;       ///< capital letters above the baseline (primary font), em
    std::size_t missing = 0;        ///< glyphs no font of the chain has (.notdef was used)
    std::size_t invalid_bytes = 0;  ///< bytes of malformed UTF-8 (replaced by U+FFFD)
    FontStyle style = FontStyle::Regular;
};

}  // namespace navmap::render::text
