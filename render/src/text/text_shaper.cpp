// SPDX-License-Identifier: Apache-2.0
#include "navmap/render/text/text_shaper.h"

#include "font_backend.h"
#include "utf8.h"

namespace navmap::render::text {

struct TextShaper::Buffer {
    hb_buffer_t* hb = nullptr;
};

namespace {

// Characters that should not start a new font run: they belong to the preceding character
// (combining marks, joiners, variation selectors) or are neutral (spaces, punctuation the
// current font has).
bool sticksToPrevious(char32_t cp) {
    if (cp == 0x200C || cp == 0x200D) return true;                                        // ZWNJ, ZWJ
    if ((cp >= 0xFE00 && cp <= 0xFE0F) || (cp >= 0xE0100 && cp <= 0xE01EF)) return true;  // variation selectors
    const hb_unicode_general_category_t gc = hb_unicode_general_category(hb_unicode_funcs_get_default(), cp);
    return gc == HB_UNICODE_GENERAL_CATEGORY_NON_SPACING_MARK || gc == HB_UNICODE_GENERAL_CATEGORY_SPACING_MARK ||
           gc == HB_UNICODE_GENERAL_CATEGORY_ENCLOSING_MARK;
}

bool isSpace(char32_t cp) {
    return hb_unicode_general_category(hb_unicode_funcs_get_default(), cp) ==
           HB_UNICODE_GENERAL_CATEGORY_SPACE_SEPARATOR;
}

}  // namespace

TextShaper::TextShaper(const FontCollection& fonts) : m_fonts(fonts), m_buffer(new Buffer) {
    m_buffer->hb = hb_buffer_create();
}

TextShaper::~TextShaper() {
    hb_buffer_destroy(m_buffer->hb);
    delete m_buffer;
}

ShapedText TextShaper::shape(std::string_view utf8, FontStyle style) {
    const FontCollection::Impl& impl = m_fonts.impl();
    const std::vector<FontId>& chain = m_fonts.chain(style);
    const FontId primary = chain.front();
    ShapedText out;
    out.style = style;
    out.ascender = impl.fonts[primary].metrics.ascender;
    out.descender = impl.fonts[primary].metrics.descender;
    out.cap_height = impl.fonts[primary].metrics.cap_height;

    // 1. One font per character: the first of the chain that has it.
    const std::vector<DecodedChar> chars = decodeUtf8(utf8);
    std::vector<FontId> font_of(chars.size(), primary);
    for (std::size_t i = 0; i < chars.size(); ++i) {
        const char32_t cp = chars[i].codepoint;
        if (!chars[i].valid) ++out.invalid_bytes;
        if (i > 0 && (sticksToPrevious(cp) || isSpace(cp)) && m_fonts.hasCodepoint(font_of[i - 1], cp)) {
            font_of[i] = font_of[i - 1];
            continue;
        }
        const int f = m_fonts.fontFor(style, cp);
        font_of[i] = f >= 0 ? static_cast<FontId>(f) : (i > 0 ? font_of[i - 1] : primary);
    }
    // A space between two runs of the fallback font shapes with it (no run break for it).
    for (std::size_t i = 1; i + 1 < chars.size(); ++i) {
        if (isSpace(chars[i].codepoint) && font_of[i - 1] == font_of[i + 1] &&
            m_fonts.hasCodepoint(font_of[i - 1], chars[i].codepoint)) {
            font_of[i] = font_of[i - 1];
        }
    }

    // 2. Shape each run of one font with the whole string as context. Malformed bytes are
    // replaced before shaping so HarfBuzz sees the same code points as the font choice.
    std::string clean;
    bool needs_clean = out.invalid_bytes > 0;
    if (needs_clean) {
        clean.reserve(utf8.size());
        for (const DecodedChar& c : chars) {
            if (c.valid)
                clean.append(utf8.substr(c.offset, c.length));
            else
                clean.append("\xEF\xBF\xBD", 3);  // U+FFFD: 3 bytes instead of 1; clusters remapped below
        }
    }
    std::vector<std::uint32_t> clean_to_src;  // byte offset in `clean` -> byte offset in utf8
    if (needs_clean) {
        clean_to_src.resize(clean.size() + 1, 0);
        std::size_t o = 0;
        for (const DecodedChar& c : chars) {
            const std::size_t len = c.valid ? c.length : 3;
            for (std::size_t k = 0; k < len; ++k) clean_to_src[o + k] = c.offset;
            o += len;
        }
        clean_to_src[o] = static_cast<std::uint32_t>(utf8.size());
    }
    const std::string_view text = needs_clean ? std::string_view(clean) : utf8;
    std::vector<std::uint32_t> char_offset(chars.size() + 1);
    {
        std::uint32_t o = 0;
        for (std::size_t i = 0; i < chars.size(); ++i) {
            char_offset[i] = o;
            o += chars[i].valid ? chars[i].length : 3;
        }
        char_offset[chars.size()] = o;
    }

    hb_buffer_t* buf = m_buffer->hb;
    std::size_t start = 0;
    while (start < chars.size()) {
        std::size_t end = start + 1;
        while (end < chars.size() && font_of[end] == font_of[start]) ++end;
        const LoadedFont& font = impl.fonts[font_of[start]];
        hb_buffer_clear_contents(buf);
        hb_buffer_add_utf8(buf, text.data(), static_cast<int>(text.size()), char_offset[start],
                           static_cast<int>(char_offset[end] - char_offset[start]));
        hb_buffer_guess_segment_properties(buf);
        // Single-line labels are laid out left to right; right-to-left runs keep HarfBuzz's
        // visual order inside the run (no bidi reordering between runs).
        hb_shape(font.hb, buf, nullptr, 0);
        unsigned int count = 0;
        const hb_glyph_info_t* info = hb_buffer_get_glyph_infos(buf, &count);
        const hb_glyph_position_t* pos = hb_buffer_get_glyph_positions(buf, &count);
        const float inv = 1.0f / font.units_per_em;
        for (unsigned int g = 0; g < count; ++g) {
            ShapedGlyph sg;
            sg.font = font_of[start];
            sg.glyph = info[g].codepoint;
            sg.cluster = needs_clean ? clean_to_src[info[g].cluster] : info[g].cluster;
            sg.x_advance = static_cast<float>(pos[g].x_advance) * inv;
            sg.y_advance = static_cast<float>(pos[g].y_advance) * inv;
            sg.x_offset = static_cast<float>(pos[g].x_offset) * inv;
            sg.y_offset = static_cast<float>(pos[g].y_offset) * inv;
            if (sg.glyph == 0) ++out.missing;
            out.advance += sg.x_advance;
            out.glyphs.push_back(sg);
        }
        start = end;
    }
    return out;
}

}  // namespace navmap::render::text
