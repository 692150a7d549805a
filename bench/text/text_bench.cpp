// SPDX-License-Identifier: Apache-2.0
// Label text costs: CPU shaping and layout per label, building the SDF atlas, and the GPU
// draw of a cluster-sized frame of labels (1280x480, ~150 labels, screen and world space).
#include <chrono>
#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include <benchmark/benchmark.h>
#include <glm/gtc/matrix_transform.hpp>

#include "gl/egl_context.h"
#include "gl/render_target.h"
#include "gl/text_layer.h"
#include "navmap/render/text/text_engine.h"
#include "navmap/render/text/text_layout.h"
#include "navmap/render/text/text_shaper.h"

namespace nt = navmap::render::text;

namespace {

// Names as they appear in the Andorra extract (accents, l·l, one CJK name).
const std::vector<std::string>& names() {
    static const std::vector<std::string> kNames = {"Andorra la Vella",
                                                    "Sant Julià de Lòria",
                                                    "Escaldes-Engordany",
                                                    "Encamp",
                                                    "La Massana",
                                                    "Ordino",
                                                    "Canillo",
                                                    "Col·legi",
                                                    "Avinguda Meritxell",
                                                    "Carrer de la Unió",
                                                    "Avinguda Carlemany",
                                                    "Carretera General 2",
                                                    "Pas de la Casa",
                                                    "Soldeu",
                                                    "El Tarter",
                                                    "Arinsal",
                                                    "Pal",
                                                    "Erts",
                                                    "Santa Coloma",
                                                    "Museu del Tabac",
                                                    "Estany d'Engolasters",
                                                    "Parc Central",
                                                    "Caldea",
                                                    "Plaça del Poble",
                                                    "Església de Sant Esteve",
                                                    "Pont de la Margineda",
                                                    "Riu Valira",
                                                    "Bordes d'Envalira",
                                                    "利奥尔茨小镇停车场",
                                                    "Coma Pedrosa"};
    return kNames;
}

bool haveFonts() { return nt::debianFontFiles().regular.size() >= 2; }

void BM_ShapeLabel(benchmark::State& state) {
    if (!haveFonts()) return state.SkipWithError("needs fonts-dejavu-core and fonts-droid-fallback");
    nt::FontCollection fonts(nt::debianFontFiles());
    nt::TextShaper shaper(fonts);
    std::size_t i = 0, glyphs = 0;
    for (auto _ : state) {
        const nt::ShapedText t = shaper.shape(names()[i++ % names().size()]);
        glyphs += t.glyphs.size();
        benchmark::DoNotOptimize(t.advance);
    }
    state.counters["glyphs_per_label"] = static_cast<double>(glyphs) / static_cast<double>(state.iterations());
}
BENCHMARK(BM_ShapeLabel);

// Layout of an already shaped label with a warm atlas (what runs per label per frame).
void BM_LayoutLabel(benchmark::State& state) {
    if (!haveFonts()) return state.SkipWithError("needs fonts-dejavu-core and fonts-droid-fallback");
    nt::FontCollection fonts(nt::debianFontFiles());
    nt::TextShaper shaper(fonts);
    nt::GlyphAtlas atlas(fonts);
    std::vector<nt::ShapedText> shaped;
    for (const auto& n : names()) shaped.push_back(shaper.shape(n));
    for (const auto& s : shaped) benchmark::DoNotOptimize(nt::layoutText(s, atlas, 16.0f).quads.size());
    std::size_t i = 0;
    for (auto _ : state) {
        const nt::LaidOutText l = nt::layoutText(shaped[i++ % shaped.size()], atlas, 16.0f);
        benchmark::DoNotOptimize(l.quads.data());
    }
}
BENCHMARK(BM_LayoutLabel);

// Shaping + layout of a label never seen before (cold run cache, warm atlas).
void BM_ShapeAndLayoutLabel(benchmark::State& state) {
    if (!haveFonts()) return state.SkipWithError("needs fonts-dejavu-core and fonts-droid-fallback");
    nt::FontCollection fonts(nt::debianFontFiles());
    nt::TextShaper shaper(fonts);
    nt::GlyphAtlas atlas(fonts);
    for (const auto& n : names()) benchmark::DoNotOptimize(nt::layoutText(shaper.shape(n), atlas, 16.0f).quads.size());
    std::size_t i = 0;
    for (auto _ : state) {
        const nt::LaidOutText l = nt::layoutText(shaper.shape(names()[i++ % names().size()]), atlas, 16.0f);
        benchmark::DoNotOptimize(l.quads.data());
    }
}
BENCHMARK(BM_ShapeAndLayoutLabel);

// Building the atlas for all glyphs of the name list (Latin + the CJK name).
void BM_AtlasBuild(benchmark::State& state) {
    if (!haveFonts()) return state.SkipWithError("needs fonts-dejavu-core and fonts-droid-fallback");
    nt::FontCollection fonts(nt::debianFontFiles());
    nt::TextShaper shaper(fonts);
    std::vector<nt::ShapedText> shaped;
    for (const auto& n : names()) shaped.push_back(shaper.shape(n));
    std::size_t glyphs = 0;
    for (auto _ : state) {
        nt::GlyphAtlas atlas(fonts);
        for (const auto& s : shaped)
            for (const auto& g : s.glyphs) benchmark::DoNotOptimize(atlas.glyph(g.font, g.glyph));
        glyphs = atlas.stats().rasterized;
    }
    state.counters["glyphs"] = static_cast<double>(glyphs);
    // Glyphs rasterized per second of CPU time (1 / cost per glyph).
    state.counters["glyphs_per_s"] = benchmark::Counter(
        static_cast<double>(glyphs) * static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_AtlasBuild)->Unit(benchmark::kMillisecond);

// GPU draw of `range(0)` labels at 1280x480 (cluster), screen (arg 1 = 0) or world space (1).
void BM_GpuDraw(benchmark::State& state) {
    if (!haveFonts()) return state.SkipWithError("needs fonts-dejavu-core and fonts-droid-fallback");
    std::unique_ptr<navmap::render::gl::EglContext> context;
    try {
        context = std::make_unique<navmap::render::gl::EglContext>(navmap::render::Platform::Auto);
    } catch (const std::exception& e) {
        return state.SkipWithError(e.what());
    }
    const int w = 1280, h = 480;
    const auto count = static_cast<std::size_t>(state.range(0));
    const bool world = state.range(1) != 0;
    navmap::render::gl::RenderTarget target(w, h, 4);
    nt::TextEngine engine;
    navmap::render::gl::TextLayer layer(engine.atlas());
    engine.beginFrame();
    std::vector<nt::LaidOutText> laid;
    std::vector<nt::TextDraw> screen;
    std::vector<nt::WorldTextDraw> worlds;
    for (std::size_t i = 0; i < count; ++i)
        laid.push_back(engine.layout(engine.run(names()[i % names().size()]), 14.0f));
    std::size_t glyphs = 0;
    for (std::size_t i = 0; i < count; ++i) {
        glyphs += laid[i].quads.size();
        const float fx = static_cast<float>((i * 37) % 12) / 12.0f, fy = static_cast<float>((i * 11) % 13) / 13.0f;
        nt::TextDraw d;
        d.quads = laid[i].quads;
        d.size_px = laid[i].size_px;
        d.position = {60.0f + fx * (w - 120), 20.0f + fy * (h - 40)};
        d.angle_rad = (i % 5 == 0) ? 0.3f : 0.0f;
        d.style.outline = {0.1f, 0.1f, 0.1f, 1.0f};
        d.style.outline_px = 1.2f;
        screen.push_back(d);
        nt::WorldTextDraw wd;
        wd.quads = d.quads;
        wd.size_px = d.size_px;
        wd.position = {(fx - 0.5f) * 2000.0f, -20.0f, -200.0f - fy * 3000.0f};
        wd.right = {1.0f, 0.0f, 0.0f};
        wd.up = {0.0f, 1.0f, 0.0f};
        wd.em_m = 15.0f;
        wd.style = d.style;
        worlds.push_back(wd);
    }
    const glm::mat4 projection = glm::perspective(glm::radians(45.0f), float(w) / h, 1.0f, 20000.0f);
    const glm::mat4 view =
        glm::lookAt(glm::vec3(0.0f, 30.0f, 0.0f), glm::vec3(0.0f, 0.0f, -1000.0f), glm::vec3(0.0f, 1.0f, 0.0f));
    target.clear(0.5f, 0.5f, 0.5f);
    target.bindForDrawing(false);
    for (auto _ : state) {
        if (world)
            layer.drawWorld(worlds, view, projection, {w, h});
        else
            layer.drawScreen(screen, {w, h});
        glFinish();
    }
    state.counters["labels"] = static_cast<double>(count);
    state.counters["glyphs"] = static_cast<double>(glyphs);
}
BENCHMARK(BM_GpuDraw)->Args({150, 0})->Args({150, 1})->Args({600, 0})->Unit(benchmark::kMicrosecond)->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
