// SPDX-License-Identifier: Apache-2.0
#include "utf8.h"

namespace navmap::render::text {

std::vector<DecodedChar> decodeUtf8(std::string_view text) {
    std::vector<DecodedChar> out;
    out.reserve(text.size());
    const auto* s = reinterpret_cast<const unsigned char*>(text.data());
    const std::size_t n = text.size();
    std::size_t i = 0;
    while (i < n) {
        const unsigned char b = s[i];
        DecodedChar c;
        c.offset = static_cast<std::uint32_t>(i);
        int len = 0;
        char32_t cp = 0;
        char32_t min = 0;
        if (b < 0x80) {
            len = 1;
            cp = b;
        } else if ((b & 0xE0) == 0xC0) {
            len = 2;
            cp = b & 0x1F;
            min = 0x80;
        } else if ((b & 0xF0) == 0xE0) {
            len = 3;
            cp = b & 0x0F;
            min = 0x800;
        } else if ((b & 0xF8) == 0xF0) {
            len = 4;
            cp = b & 0x07;
            min = 0x10000;
        }
        bool ok = len > 0 && i + static_cast<std::size_t>(len) <= n;
        for (int k = 1; ok && k < len; ++k) {
            const unsigned char cb = s[i + static_cast<std::size_t>(k)];
            if ((cb & 0xC0) != 0x80)
                ok = false;
            else
                cp = (cp << 6) | (cb & 0x3F);
        }
        if (ok && (cp < min || cp > 0x10FFFF || (cp >= 0xD800 && cp <= 0xDFFF))) ok = false;
        if (ok) {
            c.codepoint = cp;
            c.length = static_cast<std::uint32_t>(len);
        } else {
            c.codepoint = 0xFFFD;
            c.length = 1;
            c.valid = false;
        }
        out.push_back(c);
        i += c.length;
    }
    return out;
}

}  // namespace navmap::render::text
