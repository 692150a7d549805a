// SPDX-License-Identifier: Apache-2.0
#include "navmap/render/text/glyph_atlas.h"

#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cstring>
#include <exception>
#include <mutex>
#include <thread>

#include "font_backend.h"

namespace navmap::render::text {

namespace {

int floorDiv(int a, int b) { return a >= 0 ? a / b : -((-a + b - 1) / b); }
int ceilDiv(int a, int b) { return -floorDiv(-a, b); }

constexpr float kEvictFill = 0.9f;

}  // namespace

// The background rasterizer of prefetch(): its own FreeType faces (a face is not shared between
// threads), results handed over under the mutex.
struct GlyphAtlas::Prefetch {
    std::mutex mutex;
    std::unordered_map<std::uint64_t, Entry> ready;
    std::atomic<bool> stop{false};
    std::thread worker;
};

GlyphAtlas::GlyphAtlas(const FontCollection& fonts, const AtlasParams& params)
    : m_fonts(fonts),
      m_params(params),
      m_height(std::clamp(params.initial_height, 1, std::max(params.max_height, 1))),
      m_packer(params.width, m_height),
      m_pixels(static_cast<std::size_t>(params.width) * m_height, 0) {
    m_params.max_height = std::max(m_params.max_height, m_height);
    m_params.supersample = std::max(m_params.supersample, 1);
    m_params.spread_px = std::max(m_params.spread_px, 1);
    m_params.base_em_px = std::max(m_params.base_em_px, 4);
    markDirty(0, m_height);
}

GlyphAtlas::~GlyphAtlas() {
    if (m_prefetch) {
        m_prefetch->stop = true;
        if (m_prefetch->worker.joinable()) m_prefetch->worker.join();
    }
}

void GlyphAtlas::waitForPrefetch() {
    if (m_prefetch && m_prefetch->worker.joinable()) m_prefetch->worker.join();
}

void GlyphAtlas::prefetch(const FontFiles& files, std::u32string codepoints) {
    if (m_prefetch) return;
    m_prefetch = std::make_unique<Prefetch>();
    m_prefetch->worker = std::thread([this, files, codepoints = std::move(codepoints), p = m_prefetch.get()] {
        // Below the render thread: it uses only what the render thread and its rasterizer leave.
        ::setpriority(PRIO_PROCESS, static_cast<id_t>(::gettid()), 10);
        try {
            const FontCollection fonts(files);
            for (const FontStyle style : {FontStyle::Regular, FontStyle::Bold}) {
                for (const char32_t c : codepoints) {
                    if (p->stop) return;
                    for (const FontId font : fonts.chain(style)) {
                        if (!fonts.hasCodepoint(font, c)) continue;
                        const FT_UInt index = FT_Get_Char_Index(fonts.impl().fonts.at(font).face, c);
                        const std::uint64_t k = key(font, index);
                        {
                            const std::lock_guard lock(p->mutex);
                            if (p->ready.count(k)) break;
                        }
                        Entry e = rasterize(fonts, font, index);
                        const std::lock_guard lock(p->mutex);
                        p->ready.emplace(k, std::move(e));
                        break;
                    }
                }
            }
        } catch (const std::exception&) {
            // Fonts that cannot be loaded again: glyph() rasterizes everything itself.
        }
    });
}

float GlyphAtlas::fill() const {
    return static_cast<float>(m_packer.usedHeight()) / static_cast<float>(m_params.max_height);
}

void GlyphAtlas::markDirty(int first, int end) {
    if (m_dirty_first >= m_dirty_end) {
        m_dirty_first = first;
        m_dirty_end = end;
    } else {
        m_dirty_first = std::min(m_dirty_first, first);
        m_dirty_end = std::max(m_dirty_end, end);
    }
    ++m_version;
}

void GlyphAtlas::clearDirty() { m_dirty_first = m_dirty_end = 0; }

void GlyphAtlas::beginFrame(std::uint32_t keep_frames) {
    const bool overflowed = m_stats.overflows != 0 && m_overflow_frame == m_frame;
    ++m_frame;
    if (fill() < kEvictFill && !overflowed) return;
    // Evict what was not used recently; under pressure (last frame overflowed) everything not
    // used in the last frame.
    const std::uint32_t keep = overflowed ? 1u : std::max(keep_frames, 1u);
    std::vector<std::uint64_t> survivors;
    std::size_t evicted = 0;
    for (auto it = m_entries.begin(); it != m_entries.end();) {
        if (m_frame - it->second.last_used > keep) {
            it = m_entries.erase(it);
            ++evicted;
        } else {
            survivors.push_back(it->first);
            ++it;
        }
    }
    if (evicted == 0) return;
    m_stats.evicted += evicted;
    ++m_stats.repacks;
    // Repack in key order so the result does not depend on hash order (determinism).
    std::sort(survivors.begin(), survivors.end());
    m_packer.clear();
    std::fill(m_pixels.begin(), m_pixels.end(), 0);
    for (std::uint64_t k : survivors) {
        Entry& e = m_entries.at(k);
        if (e.glyph.empty) continue;
        if (!place(e)) {
            m_entries.erase(k);
            ++m_stats.evicted;
        }
    }
    m_stats.glyphs = m_entries.size();
    markDirty(0, m_height);
}

GlyphAtlas::Entry GlyphAtlas::rasterize(FontId font, std::uint32_t glyph_index) {
    Entry e = rasterize(m_fonts, font, glyph_index);
    if (!e.glyph.empty) ++m_stats.rasterized;
    return e;
}

GlyphAtlas::Entry GlyphAtlas::rasterize(const FontCollection& fonts, FontId font, std::uint32_t glyph_index) const {
    Entry e;
    const int ss = m_params.supersample;
    const int spread = m_params.spread_px;
    const float base = static_cast<float>(m_params.base_em_px);
    FT_Face face = fonts.impl().fonts.at(font).face;
    if (FT_Set_Pixel_Sizes(face, 0, static_cast<FT_UInt>(m_params.base_em_px * ss))) return e;
    // Unhinted outlines: the field is scaled freely, hinting for one size would distort others.
    if (FT_Load_Glyph(face, glyph_index, FT_LOAD_NO_HINTING | FT_LOAD_NO_BITMAP)) return e;
    if (face->glyph->format != FT_GLYPH_FORMAT_OUTLINE || face->glyph->outline.n_points == 0) return e;
    if (FT_Render_Glyph(face->glyph, FT_RENDER_MODE_NORMAL)) return e;
    const FT_Bitmap& bm = face->glyph->bitmap;
    if (bm.width == 0 || bm.rows == 0) return e;
    const int bl = face->glyph->bitmap_left;
    const int bt = face->glyph->bitmap_top;
    const int bw = static_cast<int>(bm.width);
    const int bh = static_cast<int>(bm.rows);
    // Low-resolution texel grid around the glyph with `spread` texels of margin.
    const int left = floorDiv(bl, ss) - spread;
    const int right = ceilDiv(bl + bw, ss) + spread;
    const int top = ceilDiv(bt, ss) + spread;
    const int bottom = floorDiv(bt - bh, ss) - spread;
    const int w = right - left;
    const int h = top - bottom;
    const int cw = w * ss;
    const int ch = h * ss;
    std::vector<std::uint8_t> canvas(static_cast<std::size_t>(cw) * ch, 0);
    const int ox = bl - left * ss;
    const int oy = top * ss - bt;
    for (int y = 0; y < bh; ++y) {
        const std::uint8_t* src = bm.buffer + static_cast<std::ptrdiff_t>(y) * bm.pitch;
        std::memcpy(&canvas[static_cast<std::size_t>(oy + y) * cw + ox], src, static_cast<std::size_t>(bw));
    }
    e.sdf = makeSdf(canvas, cw, ch, cw, ss, static_cast<float>(spread));
    e.glyph.empty = false;
    e.glyph.left = static_cast<float>(left) / base;
    e.glyph.top = static_cast<float>(top) / base;
    e.glyph.width = static_cast<float>(w) / base;
    e.glyph.height = static_cast<float>(h) / base;
    return e;
}

bool GlyphAtlas::place(Entry& e) {
    for (;;) {
        if (auto r = m_packer.pack(e.sdf.width, e.sdf.height)) {
            e.glyph.texels = *r;
            blit(e);
            return true;
        }
        if (m_height >= m_params.max_height) return false;
        // Grow downwards: existing rows and texel rectangles stay where they are.
        const int old = m_height;
        m_height = std::min(m_height * 2, m_params.max_height);
        m_pixels.resize(static_cast<std::size_t>(m_params.width) * m_height, 0);
        m_packer.grow(m_height);
        markDirty(old, m_height);
    }
}

void GlyphAtlas::blit(const Entry& e) {
    const AtlasRect& r = e.glyph.texels;
    for (int y = 0; y < r.h; ++y) {
        std::memcpy(&m_pixels[static_cast<std::size_t>(r.y + y) * m_params.width + r.x],
                    &e.sdf.pixels[static_cast<std::size_t>(y) * r.w], static_cast<std::size_t>(r.w));
    }
    markDirty(r.y, r.y + r.h);
}

const AtlasGlyph* GlyphAtlas::glyph(FontId font, std::uint32_t glyph_index) {
    const std::uint64_t k = key(font, glyph_index);
    auto it = m_entries.find(k);
    if (it != m_entries.end()) {
        it->second.last_used = m_frame;
        return &it->second.glyph;
    }
    if (font >= m_fonts.size()) return nullptr;
    Entry e;
    bool made = false;
    if (m_prefetch) {
        const std::lock_guard lock(m_prefetch->mutex);
        if (auto p = m_prefetch->ready.find(k); p != m_prefetch->ready.end()) {
            e = std::move(p->second);
            m_prefetch->ready.erase(p);
            made = true;
            ++m_stats.prefetched;
        }
    }
    if (!made) e = rasterize(font, glyph_index);
    if (!e.glyph.empty && !place(e)) {
        ++m_stats.overflows;
        m_overflow_frame = m_frame;
        return nullptr;
    }
    e.last_used = m_frame;
    auto [pos, inserted] = m_entries.emplace(k, std::move(e));
    m_stats.glyphs = m_entries.size();
    return &pos->second.glyph;
}

}  // namespace navmap::render::text
