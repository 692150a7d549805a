// SPDX-License-Identifier: Apache-2.0
#pragma once
// SDF glyph atlas: glyphs rasterized on demand from their FreeType outlines into one
// single-channel texture, packed on shelves, growing in height, with eviction of glyphs not
// used recently. GL-free: the renderer uploads image() when version() changes.

#include <cstdint>
#include <memory>
#include <string>
#include <unordered_map>
#include <vector>

#include "navmap/render/text/atlas_packer.h"
#include "navmap/render/text/font_collection.h"
#include "navmap/render/text/sdf_generator.h"

namespace navmap::render::text {

struct AtlasParams {
    /// Em size glyphs are stored at, texels. Text of any size is drawn from it (seed 4.3.3:
    /// freely scalable labels).
    int base_em_px = 32;
    /// Distance range stored around each glyph, texels at base size: outline + halo can reach
    /// spread_px * size / base_em_px pixels on screen.
    int spread_px = 8;
    /// Outlines are rasterized at base * supersample and the distance transform downsampled.
    int supersample = 4;
    int width = 1024;
    int initial_height = 256;
    int max_height = 2048;
};

/// Where a glyph lies in the atlas and how its quad sits relative to the pen position.
struct AtlasGlyph {
    bool empty = true;  ///< no outline (space): nothing to draw
    AtlasRect texels;   ///< rectangle in the atlas, texels (including the spread margin)
    /// Quad left edge and top edge relative to the pen position, and its size, em units, y up
    /// (top > bottom). Includes the spread margin.
    float left = 0.0f, top = 0.0f, width = 0.0f, height = 0.0f;
};

struct AtlasStats {
    std::size_t glyphs = 0;      ///< resident glyphs
    std::size_t rasterized = 0;  ///< glyphs rasterized since creation
    std::size_t evicted = 0;     ///< glyphs evicted since creation
    std::size_t overflows = 0;   ///< requests refused because the atlas was full this frame
    std::size_t repacks = 0;
    std::size_t prefetched = 0;  ///< glyphs taken from prefetch() instead of rasterized when asked for
};

/// Not thread-safe; owned by the render thread. The FontCollection must outlive it.
class GlyphAtlas {
public:
    GlyphAtlas(const FontCollection& fonts, const AtlasParams& params = {});
    ~GlyphAtlas();
    GlyphAtlas(const GlyphAtlas&) = delete;
    GlyphAtlas& operator=(const GlyphAtlas&) = delete;

    /// Rasterizes the glyphs of `codepoints` in both styles' first fonts that have them on a
    /// background thread (low priority, with fonts of its own loaded from `files`, the files
    /// `fonts` was made from), so that the first frames with text find their distance fields made
    /// (a glyph costs about 1 ms: start-up). glyph() takes a prefetched glyph when it is ready and
    /// rasterizes it itself otherwise; the atlas is the same either way. Once per atlas.
    void prefetch(const FontFiles& files, std::u32string codepoints);
    /// Blocks until prefetch()'s thread has made every glyph (tests, benchmarks).
    void waitForPrefetch();

    /// Starts a frame: glyphs requested from now on count as used in it. When the atlas is
    /// nearly full at its maximum height, glyphs not used in the last `keep_frames` frames
    /// are evicted and the rest repacked (texel rectangles change: lay text out again after
    /// beginFrame, never keep quads across frames).
    void beginFrame(std::uint32_t keep_frames = 60);

    /// The glyph, rasterized on first use. nullptr when the atlas is full for this frame
    /// (counted in stats().overflows; room is made at the next beginFrame). Pointers stay
    /// valid until the next beginFrame.
    const AtlasGlyph* glyph(FontId font, std::uint32_t glyph_index);

    [[nodiscard]] const AtlasParams& params() const { return m_params; }
    [[nodiscard]] int width() const { return m_params.width; }
    [[nodiscard]] int height() const { return m_height; }
    /// width() x height() texels, rows top to bottom.
    [[nodiscard]] const std::vector<std::uint8_t>& pixels() const { return m_pixels; }
    /// Increments whenever pixels or texel rectangles change.
    [[nodiscard]] std::uint64_t version() const { return m_version; }
    /// Rows changed since the last clearDirty() ([first, last), empty when first >= last).
    [[nodiscard]] int dirtyFirstRow() const { return m_dirty_first; }
    [[nodiscard]] int dirtyEndRow() const { return m_dirty_end; }
    void clearDirty();
    [[nodiscard]] const AtlasStats& stats() const { return m_stats; }
    /// Fraction of the maximum height taken by shelves.
    [[nodiscard]] float fill() const;

private:
    struct Entry {
        AtlasGlyph glyph;
        std::uint32_t last_used = 0;
        GrayImage sdf;  // kept so repacking does not rasterize again
    };
    static std::uint64_t key(FontId font, std::uint32_t glyph) { return (std::uint64_t{font} << 32) | glyph; }
    Entry rasterize(FontId font, std::uint32_t glyph_index);
    Entry rasterize(const FontCollection& fonts, FontId font, std::uint32_t glyph_index) const;
    bool place(Entry& e);
    void blit(const Entry& e);
    void markDirty(int first, int end);

    struct Prefetch;
    std::unique_ptr<Prefetch> m_prefetch;
    const FontCollection& m_fonts;
    AtlasParams m_params;
    int m_height;
    AtlasPacker m_packer;
    std::vector<std::uint8_t> m_pixels;
    std::unordered_map<std::uint64_t, Entry> m_entries;
    std::uint32_t m_frame = 1;
    std::uint32_t m_overflow_frame = 0;
    std::uint64_t m_version = 1;
    int m_dirty_first = 0;
    int m_dirty_end = 0;
    AtlasStats m_stats;
};

}  // namespace navmap::render::text
