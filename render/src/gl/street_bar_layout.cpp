// SPDX-License-Identifier: Apache-2.0
#include "street_bar_layout.h"

#include <algorithm>
#include <vector>

#include "guidance_overlay_pass.h"

namespace navmap::render::gl {

namespace {

constexpr float kTextPx = 22.0f;                   // layout pixels (800 x 240)
constexpr float kPadX = 16.0f;                     // panel beside the text
constexpr float kPadY = 6.0f;                      // panel above and below the text's line box
constexpr float kBottom = 10.0f;                   // from the frame's bottom edge
constexpr float kCorner = 10.0f;                   // corner radius
constexpr float kMaxWidth = 0.60f;                 // of the frame's width
constexpr const char* kEllipsis = "\xE2\x80\xA6";  // U+2026

float widthOf(text::TextEngine& engine, const std::string& utf8, float px) {
    return engine.measure(engine.run(utf8, kStreetBarFont), px).width;
}

// The longest start of `text`, cut before a character (UTF-8: not before a continuation byte)
// and without trailing blanks, that fits `max_px` with the ellipsis after it. Binary search on
// the number of characters: the width grows with it.
std::string cutToWidth(text::TextEngine& engine, const std::string& text, float px, float max_px) {
    std::vector<std::size_t> starts;  // byte offset of each character
    for (std::size_t i = 0; i < text.size(); ++i)
        if ((static_cast<unsigned char>(text[i]) & 0xC0u) != 0x80u) starts.push_back(i);
    auto candidate = [&](std::size_t chars) {
        std::string s = text.substr(0, chars < starts.size() ? starts[chars] : text.size());
        while (!s.empty() && (s.back() == ' ' || s.back() == '\t')) s.pop_back();
        return s + kEllipsis;
    };
    std::size_t lo = 0, hi = starts.size();  // candidate(lo) fits (or lo == 0), candidate(hi) is the whole
    while (hi - lo > 1) {
        const std::size_t mid = lo + (hi - lo) / 2;
        if (widthOf(engine, candidate(mid), px) <= max_px)
            lo = mid;
        else
            hi = mid;
    }
    return candidate(lo);
}

}  // namespace

std::string streetBarText(const StreetBar& bar) {
    if (bar.name.empty() || bar.ref.empty() || bar.name == bar.ref) return bar.name.empty() ? bar.ref : bar.name;
    return bar.name + " \xC2\xB7 " + bar.ref;  // U+00B7 middle dot
}

StreetBarLayout streetBarLayout(text::TextEngine& engine, const StreetBar& bar, int width, int height) {
    StreetBarLayout l;
    l.text = streetBarText(bar);
    if (l.text.empty() || width <= 0 || height <= 0) {
        l.text.clear();
        return l;
    }
    const float unit = guidanceLayout(width, height).unit;
    l.text_px = kTextPx * unit;
    l.max_width_px = kMaxWidth * float(width);
    const float pad_x = kPadX * unit, pad_y = kPadY * unit;
    const float max_text = l.max_width_px - 2.0f * pad_x;
    text::TextMetrics m = engine.measure(engine.run(l.text, kStreetBarFont), l.text_px);
    if (m.width > max_text) {
        l.text = cutToWidth(engine, l.text, l.text_px, max_text);
        l.cut = true;
        m = engine.measure(engine.run(l.text, kStreetBarFont), l.text_px);
    }
    const glm::vec2 half(0.5f * m.width + pad_x, 0.5f * m.height + pad_y);
    const glm::vec2 centre(0.5f * float(width), float(height) - kBottom * unit - half.y);
    l.lo = centre - half;
    l.hi = centre + half;
    l.text_centre = centre;
    l.corner_px = std::min(kCorner * unit, half.y);
    return l;
}

}  // namespace navmap::render::gl
