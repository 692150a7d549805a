// SPDX-License-Identifier: Apache-2.0
#include "navmap/render/text/atlas_packer.h"

namespace navmap::render::text {

AtlasPacker::AtlasPacker(int width, int height) : m_width(width), m_height(height) {}

std::optional<AtlasRect> AtlasPacker::pack(int w, int h, int padding) {
    const int pw = w + padding;
    const int ph = h + padding;
    if (pw > m_width || w <= 0 || h <= 0) return std::nullopt;
    for (Shelf& s : m_shelves) {
        if (ph <= s.h && ph * 3 >= s.h * 2 && s.x + pw <= m_width) {
            AtlasRect r{s.x, s.y, w, h};
            s.x += pw;
            return r;
        }
    }
    if (m_next_y + ph > m_height) return std::nullopt;
    m_shelves.push_back({m_next_y, ph, pw});
    AtlasRect r{0, m_next_y, w, h};
    m_next_y += ph;
    return r;
}

void AtlasPacker::clear() {
    m_shelves.clear();
    m_next_y = 0;
}

}  // namespace navmap::render::text
