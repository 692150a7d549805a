// SPDX-License-Identifier: Apache-2.0
#pragma once
// FreeType and HarfBuzz objects behind FontCollection. Private to render/src/text.

#include <ft2build.h>
#include FT_FREETYPE_H
#include <hb.h>

#include <filesystem>
#include <vector>

#include "navmap/render/text/font_collection.h"

namespace navmap::render::text {

struct LoadedFont {
    std::filesystem::path path;
    FT_Face face = nullptr;   // rasterizing (GlyphAtlas); its pixel size changes per glyph
    hb_font_t* hb = nullptr;  // shaping in font units (hb-ot functions, scale = units per em)
    float units_per_em = 1000.0f;
    FontMetrics metrics;
};

struct FontCollection::Impl {
    FT_Library library = nullptr;
    std::vector<LoadedFont> fonts;
    std::vector<FontId> chains[kFontStyleCount];
};

}  // namespace navmap::render::text
