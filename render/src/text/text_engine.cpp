// SPDX-License-Identifier: Apache-2.0
#include "navmap/render/text/text_engine.h"

namespace navmap::render::text {

TextEngine::TextEngine(const TextEngineOptions& options)
    : m_font_files(options.fonts),
      m_fonts(std::make_unique<FontCollection>(options.fonts)),
      m_shaper(*m_fonts),
      m_atlas(*m_fonts, options.atlas),
      m_max_runs(options.max_runs) {}

std::u32string TextEngine::latinCodepoints() {
    // The most frequent first: the first frames take whatever is ready.
    std::u32string out;
    for (char32_t c = U'a'; c <= U'z'; ++c) out.push_back(c);
    for (char32_t c = U'A'; c <= U'Z'; ++c) out.push_back(c);
    for (char32_t c = 0xC0; c <= 0xFF; ++c)
        if (c != 0xD7 && c != 0xF7) out.push_back(c);  // letters, not the multiplication and division signs
    for (char32_t c = U'0'; c <= U'9'; ++c) out.push_back(c);
    for (char32_t c = 0x21; c <= 0x7E; ++c)
        if (out.find(c) == std::u32string::npos) out.push_back(c);
    return out;
}

RunId TextEngine::run(std::string_view utf8, FontStyle style) {
    std::string key;
    key.reserve(utf8.size() + 1);
    key.push_back(static_cast<char>('0' + static_cast<int>(style)));
    key.append(utf8);
    auto it = m_index.find(key);
    if (it != m_index.end()) return it->second;
    const auto id = static_cast<RunId>(m_runs.size());
    m_runs.push_back(m_shaper.shape(utf8, style));
    m_index.emplace(std::move(key), id);
    return id;
}

void TextEngine::beginFrame() {
    if (m_runs.size() > m_max_runs) {
        m_runs.clear();
        m_index.clear();
        ++m_runs_generation;
    }
    m_atlas.beginFrame();
}

LaidOutText TextEngine::layout(RunId id, float size_px, TextAnchor anchor) {
    return layoutText(m_runs.at(id), m_atlas, size_px, anchor);
}

LaidOutText TextEngine::layoutWithIcon(RunId icon, RunId id, float size_px) {
    return layoutIconText(m_runs.at(icon), m_runs.at(id), m_atlas, size_px);
}

}  // namespace navmap::render::text
