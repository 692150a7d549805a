// SPDX-License-Identifier: Apache-2.0
#pragma once
// The CPU text pipeline in one object for the renderer: fonts, shaping with a cache of shaped
// runs, the SDF atlas, layout and metrics. GL-free; one per render thread.

#include <cstdint>
#include <memory>
#include <string>
#include <string_view>
#include <unordered_map>
#include <vector>

#include "navmap/render/text/font_collection.h"
#include "navmap/render/text/glyph_atlas.h"
#include "navmap/render/text/shaped_text.h"
#include "navmap/render/text/text_layout.h"
#include "navmap/render/text/text_shaper.h"

namespace navmap::render::text {

/// Handle of a shaped run kept by a TextEngine.
using RunId = std::uint32_t;

struct TextEngineOptions {
    FontFiles fonts = debianFontFiles();
    AtlasParams atlas;
    /// Shaped runs kept; beyond it the cache is emptied at the next beginFrame (run ids stay
    /// valid within a frame, see TextEngine::runsGeneration()).
    std::size_t max_runs = 65536;
};

class TextEngine {
public:
    /// Loads the fonts; throws TextError when they are unusable.
    explicit TextEngine(const TextEngineOptions& options = {});

    /// Shapes `utf8` once per (text, style) and returns its run.
    RunId run(std::string_view utf8, FontStyle style = FontStyle::Regular);
    [[nodiscard]] const ShapedText& shaped(RunId id) const { return m_runs.at(id); }
    [[nodiscard]] TextMetrics measure(RunId id, float size_px) const { return measureText(shaped(id), size_px); }
    /// Quads of a run at `size_px` (call after beginFrame, every frame the label is drawn).
    LaidOutText layout(RunId id, float size_px, TextAnchor anchor = TextAnchor::Center);
    LaidOutText layoutWithIcon(RunId icon, RunId id, float size_px);

    /// Per frame, before any run() or layout: lets the atlas evict glyphs unused for long and
    /// empties the run cache when it is over max_runs.
    void beginFrame();
    /// Increments when the run cache was emptied (all RunIds invalid).
    [[nodiscard]] std::uint64_t runsGeneration() const { return m_runs_generation; }

    /// Makes the glyphs of `codepoints` on a background thread ahead of their first use
    /// (GlyphAtlas::prefetch). Once per engine.
    void prefetchGlyphs(std::u32string codepoints) { m_atlas.prefetch(m_font_files, std::move(codepoints)); }
    /// Printable ASCII and the Latin-1 letters: the map labels of western European regions.
    static std::u32string latinCodepoints();

    [[nodiscard]] const FontCollection& fonts() const { return *m_fonts; }
    [[nodiscard]] GlyphAtlas& atlas() { return m_atlas; }
    [[nodiscard]] const GlyphAtlas& atlas() const { return m_atlas; }

private:
    FontFiles m_font_files;
    std::unique_ptr<FontCollection> m_fonts;
    TextShaper m_shaper;
    GlyphAtlas m_atlas;
    std::size_t m_max_runs;
    std::vector<ShapedText> m_runs;
    std::unordered_map<std::string, RunId> m_index;
    std::uint64_t m_runs_generation = 0;
};

}  // namespace navmap::render::text
