// SPDX-License-Identifier: Apache-2.0
// libFuzzer target: label text (UTF-8 from the map data) through shaping with font fallback,
// the SDF atlas and layout. Built with -DNAVMAP_WITH_FUZZ=ON (clang); navmap_text_test also
// compiles it (NAVMAP_FUZZ_NO_MAIN) and runs navmapFuzzTextShape() on a bad-input corpus.
// Run e.g.: build/tests/fuzz/text_shape_fuzz -max_total_time=60

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string_view>

#include "navmap/render/text/glyph_atlas.h"
#include "navmap/render/text/text_layout.h"
#include "navmap/render/text/text_shaper.h"

int navmapFuzzTextShape(const std::uint8_t* data, std::size_t size) {
    namespace nt = navmap::render::text;
    struct State {
        std::unique_ptr<nt::FontCollection> fonts;
        std::unique_ptr<nt::TextShaper> shaper;
        std::unique_ptr<nt::GlyphAtlas> atlas;
    };
    static State* state = [] {
        auto* s = new State;
        const nt::FontFiles files = nt::debianFontFiles();
        if (files.regular.empty()) return s;
        s->fonts = std::make_unique<nt::FontCollection>(files);
        s->shaper = std::make_unique<nt::TextShaper>(*s->fonts);
        nt::AtlasParams small;
        // Small glyphs: the distance transform of each new glyph dominates the cost of an input,
        // and its size changes no branch (about 10x more inputs per second).
        small.base_em_px = 12;
        small.spread_px = 3;
        small.supersample = 2;
        small.width = 128;
        small.initial_height = 32;
        small.max_height = 128;  // small, so growth, overflow and eviction are exercised
        s->atlas = std::make_unique<nt::GlyphAtlas>(*s->fonts, small);
        return s;
    }();
    if (!state->shaper) return 0;
    const std::string_view text(reinterpret_cast<const char*>(data), size);
    const auto style = size > 0 && (data[0] & 1) ? nt::FontStyle::Bold : nt::FontStyle::Regular;
    const nt::ShapedText shaped = state->shaper->shape(text, style);
    for (const nt::ShapedGlyph& g : shaped.glyphs) {
        if (g.cluster > size) __builtin_trap();  // clusters index the input
    }
    state->atlas->beginFrame(2);
    const nt::LaidOutText laid = nt::layoutText(shaped, *state->atlas, 16.0f);
    if (laid.quads.size() > shaped.glyphs.size()) __builtin_trap();
    return 0;
}

#ifndef NAVMAP_FUZZ_NO_MAIN
extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    return navmapFuzzTextShape(data, size);
}
#endif
