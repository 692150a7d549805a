// SPDX-License-Identifier: Apache-2.0
#pragma once
// Fonts for label text: a set of font files loaded once at setup, ordered into fallback chains
// (DejaVu Sans first, a CJK-capable fallback after it). GL-, FreeType- and HarfBuzz-free header.

#include <cstdint>
#include <filesystem>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

namespace navmap::render::text {

/// Raised at setup when a font file cannot be read or is not a usable font. The message names
/// the file and the reason (`/usr/share/fonts/x.ttf: cannot open resource`).
class TextError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

/// Index of a loaded font inside its FontCollection.
using FontId = std::uint16_t;

/// Style of a fallback chain: label kinds pick one (places and POIs bold, roads regular).
enum class FontStyle : std::uint8_t { Regular = 0, Bold = 1 };
inline constexpr int kFontStyleCount = 2;

/// Font files a collection is built from; each chain is tried first to last per character.
struct FontFiles {
    std::vector<std::filesystem::path> regular;  ///< e.g. DejaVuSans.ttf, DroidSansFallbackFull.ttf
    std::vector<std::filesystem::path> bold;     ///< e.g. DejaVuSans-Bold.ttf, DroidSansFallbackFull.ttf
};

/// The Debian fonts navmap uses (fonts-dejavu-core, fonts-droid-fallback). Files that do not
/// exist are left out of the chains (so a missing fallback only loses CJK coverage); the
/// environment variable NAVMAP_FONT_DIR, when set, is searched before /usr/share/fonts.
FontFiles debianFontFiles();

/// Vertical metrics of a font in em units (1 em = the font size), y up.
struct FontMetrics {
    float ascender = 0.8f;
    float descender = -0.2f;  ///< negative: below the baseline
    float line_gap = 0.0f;
    float cap_height = 0.73f;  ///< height of capital letters above the baseline (OS/2 sCapHeight)
};

/// Loaded fonts. Construct at setup (throws TextError); afterwards read-only and safe to share
/// between threads for lookups, but the shaper and atlas that use it are single-threaded.
/// A file named in both chains is loaded once.
class FontCollection {
public:
    /// Loads every file. Throws TextError when a file cannot be loaded or a chain is empty.
    explicit FontCollection(const FontFiles& files);
    ~FontCollection();
    FontCollection(const FontCollection&) = delete;
    FontCollection& operator=(const FontCollection&) = delete;

    /// The fallback chain of a style, primary font first.
    [[nodiscard]] const std::vector<FontId>& chain(FontStyle style) const;
    [[nodiscard]] std::size_t size() const;
    [[nodiscard]] const std::filesystem::path& path(FontId font) const;
    /// Family and style name as the font reports them ("DejaVu Sans Bold").
    [[nodiscard]] std::string name(FontId font) const;
    [[nodiscard]] FontMetrics metrics(FontId font) const;
    /// Whether the font maps the Unicode code point to a glyph (not .notdef).
    [[nodiscard]] bool hasCodepoint(FontId font, char32_t codepoint) const;
    /// First font of the style's chain that covers the code point; nullopt-like -1 when none.
    [[nodiscard]] int fontFor(FontStyle style, char32_t codepoint) const;

    /// Backend access for the shaper and the atlas (render/src/text/font_backend.h).
    struct Impl;
    [[nodiscard]] Impl& impl() const { return *m_impl; }

private:
    std::unique_ptr<Impl> m_impl;
};

}  // namespace navmap::render::text
