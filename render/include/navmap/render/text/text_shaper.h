// SPDX-License-Identifier: Apache-2.0
#pragma once
// HarfBuzz shaping of UTF-8 label text with per-character font fallback.

#include <string_view>

#include "navmap/render/text/font_collection.h"
#include "navmap/render/text/shaped_text.h"

namespace navmap::render::text {

/// Shapes strings against a FontCollection. Each character goes to the first font of the
/// style's chain that has it (combining marks, joiners, variation selectors and spaces stay
/// with the font of the preceding character so runs are not split needlessly); each run of
/// one font is shaped by HarfBuzz with the whole string as context. Malformed UTF-8 never
/// fails: bad bytes become U+FFFD and are counted. Single-threaded; deterministic.
class TextShaper {
public:
    explicit TextShaper(const FontCollection& fonts);
    ~TextShaper();
    TextShaper(const TextShaper&) = delete;
    TextShaper& operator=(const TextShaper&) = delete;

    [[nodiscard]] ShapedText shape(std::string_view utf8, FontStyle style = FontStyle::Regular);

private:
    const FontCollection& m_fonts;
    struct Buffer;
    Buffer* m_buffer = nullptr;  // reused hb_buffer_t
};

}  // namespace navmap::render::text
