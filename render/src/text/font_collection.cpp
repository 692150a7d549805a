// SPDX-License-Identifier: Apache-2.0
#include "navmap/render/text/font_collection.h"

#include <cstdlib>
#include <string>
#include <system_error>

#include <hb-ot.h>

#include "font_backend.h"

namespace navmap::render::text {

namespace {

std::string ftErrorText(FT_Error error) {
    const char* s = FT_Error_String(error);
    return s ? std::string(s) : "FreeType error " + std::to_string(error);
}

std::filesystem::path findFont(const std::vector<std::filesystem::path>& dirs, const std::string& file) {
    for (const auto& dir : dirs) {
        std::error_code ec;
        for (auto it = std::filesystem::recursive_directory_iterator(dir, ec);
             !ec && it != std::filesystem::recursive_directory_iterator(); it.increment(ec)) {
            if (it->path().filename() == file) return it->path();
        }
    }
    return {};
}

FontId loadFont(FontCollection::Impl& impl, const std::filesystem::path& path) {
    for (std::size_t i = 0; i < impl.fonts.size(); ++i) {
        if (impl.fonts[i].path == path) return static_cast<FontId>(i);
    }
    LoadedFont font;
    font.path = path;
    const FT_Error err = FT_New_Face(impl.library, path.c_str(), 0, &font.face);
    if (err) throw TextError(path.string() + ": " + ftErrorText(err));
    if (!FT_IS_SCALABLE(font.face)) {
        FT_Done_Face(font.face);
        throw TextError(path.string() + ": not a scalable (outline) font");
    }
    hb_blob_t* blob = hb_blob_create_from_file_or_fail(path.c_str());
    if (!blob) {
        FT_Done_Face(font.face);
        throw TextError(path.string() + ": HarfBuzz cannot read the file");
    }
    hb_face_t* face = hb_face_create(blob, 0);
    hb_blob_destroy(blob);
    font.hb = hb_font_create(face);  // hb-ot font functions; scale defaults to units per em
    hb_face_destroy(face);
    font.units_per_em = static_cast<float>(font.face->units_per_EM ? font.face->units_per_EM : 1000);
    hb_font_extents_t ext{};
    if (hb_font_get_h_extents(font.hb, &ext)) {
        font.metrics.ascender = static_cast<float>(ext.ascender) / font.units_per_em;
        font.metrics.descender = static_cast<float>(ext.descender) / font.units_per_em;
        font.metrics.line_gap = static_cast<float>(ext.line_gap) / font.units_per_em;
    }
    // Cap height from the OS/2 table; fonts without it measure a capital H.
    hb_position_t cap = 0;
    if (hb_ot_metrics_get_position(font.hb, HB_OT_METRICS_TAG_CAP_HEIGHT, &cap) && cap > 0) {
        font.metrics.cap_height = static_cast<float>(cap) / font.units_per_em;
    } else if (hb_codepoint_t h = 0; hb_font_get_nominal_glyph(font.hb, 'H', &h)) {
        hb_glyph_extents_t e{};
        if (hb_font_get_glyph_extents(font.hb, h, &e) && e.y_bearing > 0) {
            font.metrics.cap_height = static_cast<float>(e.y_bearing) / font.units_per_em;
        }
    }
    impl.fonts.push_back(font);
    return static_cast<FontId>(impl.fonts.size() - 1);
}

}  // namespace

FontFiles debianFontFiles() {
    std::vector<std::filesystem::path> dirs;
    if (const char* env = std::getenv("NAVMAP_FONT_DIR"); env && *env) dirs.emplace_back(env);
    dirs.emplace_back("/usr/share/fonts/truetype/dejavu");
    dirs.emplace_back("/usr/share/fonts/truetype/droid");
    dirs.emplace_back("/usr/share/fonts");
    // seed 4.5.2: a sans-serif screen typeface (DejaVu Sans, a Verdana relative); CJK from the
    // Android fallback font (fonts-droid-fallback, about 4 MB) which DejaVu lacks.
    const std::filesystem::path regular = findFont(dirs, "DejaVuSans.ttf");
    const std::filesystem::path bold = findFont(dirs, "DejaVuSans-Bold.ttf");
    const std::filesystem::path cjk = findFont(dirs, "DroidSansFallbackFull.ttf");
    FontFiles files;
    if (!regular.empty()) files.regular.push_back(regular);
    if (!bold.empty())
        files.bold.push_back(bold);
    else if (!regular.empty())
        files.bold.push_back(regular);
    if (!cjk.empty()) {
        files.regular.push_back(cjk);
        files.bold.push_back(cjk);
    }
    return files;
}

FontCollection::FontCollection(const FontFiles& files) : m_impl(std::make_unique<Impl>()) {
    const FT_Error err = FT_Init_FreeType(&m_impl->library);
    if (err) throw TextError("FT_Init_FreeType: " + ftErrorText(err));
    try {
        const std::vector<std::filesystem::path>* lists[kFontStyleCount] = {&files.regular, &files.bold};
        for (int s = 0; s < kFontStyleCount; ++s) {
            if (lists[s]->empty()) {
                throw TextError(std::string("font chain '") + (s == 0 ? "regular" : "bold") +
                                "' is empty (install fonts-dejavu-core)");
            }
            for (const auto& p : *lists[s]) m_impl->chains[s].push_back(loadFont(*m_impl, p));
        }
    } catch (...) {
        for (auto& f : m_impl->fonts) {
            hb_font_destroy(f.hb);
            FT_Done_Face(f.face);
        }
        FT_Done_FreeType(m_impl->library);
        throw;
    }
}

FontCollection::~FontCollection() {
    for (auto& f : m_impl->fonts) {
        hb_font_destroy(f.hb);
        FT_Done_Face(f.face);
    }
    FT_Done_FreeType(m_impl->library);
}

const std::vector<FontId>& FontCollection::chain(FontStyle style) const {
    return m_impl->chains[static_cast<int>(style)];
}

std::size_t FontCollection::size() const { return m_impl->fonts.size(); }

const std::filesystem::path& FontCollection::path(FontId font) const { return m_impl->fonts.at(font).path; }

std::string FontCollection::name(FontId font) const {
    const FT_Face f = m_impl->fonts.at(font).face;
    std::string n = f->family_name ? f->family_name : "?";
    if (f->style_name && std::string(f->style_name) != "Book" && std::string(f->style_name) != "Regular") {
        n += " ";
        n += f->style_name;
    }
    return n;
}

FontMetrics FontCollection::metrics(FontId font) const { return m_impl->fonts.at(font).metrics; }

bool FontCollection::hasCodepoint(FontId font, char32_t codepoint) const {
    hb_codepoint_t glyph = 0;
    return hb_font_get_nominal_glyph(m_impl->fonts.at(font).hb, codepoint, &glyph) && glyph != 0;
}

int FontCollection::fontFor(FontStyle style, char32_t codepoint) const {
    for (FontId f : chain(style)) {
        if (hasCodepoint(f, codepoint)) return f;
    }
    return -1;
}

}  // namespace navmap::render::text
