// SPDX-License-Identifier: Apache-2.0
#include "navmap/render/text/text_engine.h"

namespace navmap::render::text {

TextEngine::TextEngine(const TextEngineOptions& options)
    : m_fonts(std::make_unique<FontCollection>(options.fonts)),
      m_shaper(*m_fonts),
      m_atlas(*m_fonts, options.atlas),
      m_max_runs(options.max_runs) {}

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
