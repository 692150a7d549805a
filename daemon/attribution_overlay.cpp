// SPDX-License-Identifier: Apache-2.0
#include "attribution_overlay.h"

#include <algorithm>
#include <cmath>

#include "navmap/render/text/text_engine.h"

namespace navmap::daemon {

namespace {

constexpr std::uint8_t kText[3] = {240, 242, 245};  // near white
constexpr std::uint8_t kBox[3] = {20, 22, 26};      // near black, ...
constexpr int kBoxAlpha = 150;                      // ... at 59 %: the map stays visible behind it

// Bilinear sample of the single-channel atlas at texel coordinates (x, y), 0..1.
float sample(const render::text::GlyphAtlas& atlas, float x, float y) {
    const auto& px = atlas.pixels();
    const int w = atlas.width();
    const int h = atlas.height();
    x = std::clamp(x - 0.5f, 0.0f, static_cast<float>(w - 1));
    y = std::clamp(y - 0.5f, 0.0f, static_cast<float>(h - 1));
    const int x0 = static_cast<int>(x);
    const int y0 = static_cast<int>(y);
    const int x1 = std::min(x0 + 1, w - 1);
    const int y1 = std::min(y0 + 1, h - 1);
    const float fx = x - static_cast<float>(x0);
    const float fy = y - static_cast<float>(y0);
    const auto at = [&](int xx, int yy) {
        return static_cast<float>(px[static_cast<std::size_t>(yy) * w + xx]) / 255.0f;
    };
    return (at(x0, y0) * (1 - fx) + at(x1, y0) * fx) * (1 - fy) + (at(x0, y1) * (1 - fx) + at(x1, y1) * fx) * fy;
}

}  // namespace

AttributionOverlay::AttributionOverlay(render::text::TextEngine& engine, const std::string& text, int width, int height)
    : m_width(width), m_height(height) {
    const float size_px = std::clamp(std::round(static_cast<float>(height) * 0.03f), 10.0f, 16.0f);
    engine.beginFrame();
    const auto run = engine.run(text);
    const auto laid = engine.layout(run, size_px, render::text::TextAnchor::BaselineLeft);
    const int pad = std::max(2, static_cast<int>(size_px / 4));
    const int margin = pad;
    m_w = std::min(width - 2 * margin, static_cast<int>(std::ceil(laid.metrics.width)) + 2 * pad);
    m_h = std::min(height - 2 * margin, static_cast<int>(std::ceil(laid.metrics.height)) + 2 * pad);
    m_w = std::max(m_w, 0);
    m_h = std::max(m_h, 0);
    m_x = width - margin - m_w;
    m_y = height - margin - m_h;
    m_coverage.assign(static_cast<std::size_t>(m_w) * static_cast<std::size_t>(m_h), 0);
    // The text engine's SDF glyphs, drawn as its shader does (text_sdf.frag): the stored value
    // 0.5 + d / (2 * spread) at the atlas' base size, d scaled to screen pixels, about one pixel
    // of antialiasing around the edge.
    const auto& atlas = engine.atlas();
    const float dist_scale =
        2.0f * static_cast<float>(atlas.params().spread_px) * size_px / static_cast<float>(atlas.params().base_em_px);
    const float baseline_x = static_cast<float>(pad);
    const float baseline_y = static_cast<float>(pad) + laid.metrics.ascent;
    for (const auto& q : laid.quads) {
        const int qx0 = std::max(0, static_cast<int>(std::floor(baseline_x + q.p0.x)));
        const int qy0 = std::max(0, static_cast<int>(std::floor(baseline_y + q.p0.y)));
        const int qx1 = std::min(m_w, static_cast<int>(std::ceil(baseline_x + q.p1.x)));
        const int qy1 = std::min(m_h, static_cast<int>(std::ceil(baseline_y + q.p1.y)));
        const float qw = q.p1.x - q.p0.x;
        const float qh = q.p1.y - q.p0.y;
        if (qw <= 0.0f || qh <= 0.0f) continue;
        for (int y = qy0; y < qy1; ++y) {
            for (int x = qx0; x < qx1; ++x) {
                const float u = (static_cast<float>(x) + 0.5f - baseline_x - q.p0.x) / qw;
                const float v = (static_cast<float>(y) + 0.5f - baseline_y - q.p0.y) / qh;
                if (u < 0.0f || u > 1.0f || v < 0.0f || v > 1.0f) continue;
                const float d =
                    (sample(atlas, q.t0.x + u * (q.t1.x - q.t0.x), q.t0.y + v * (q.t1.y - q.t0.y)) - 0.5f) * dist_scale;
                const float a = std::clamp(d + 0.5f, 0.0f, 1.0f);
                auto& c = m_coverage[static_cast<std::size_t>(y) * m_w + x];
                c = std::max(c, static_cast<std::uint8_t>(std::lround(a * 255.0f)));
            }
        }
    }
}

render::Image AttributionOverlay::premultiplied() const {
    render::Image img;
    img.width = m_w;
    img.height = m_h;
    img.rgba.resize(static_cast<std::size_t>(m_w) * m_h * 4);
    for (std::size_t i = 0; i < m_coverage.size(); ++i) {
        const int a = m_coverage[i];
        // apply(): p' = (p (1 - box_a) + box box_a)(1 - a) + text a = src + p (1 - src_a).
        const int keep = (255 - kBoxAlpha) * (255 - a);  // (1 - src_a), scaled by 255^2
        for (int k = 0; k < 3; ++k) {
            img.rgba[i * 4 + k] = static_cast<std::uint8_t>(
                (kBox[k] * kBoxAlpha * (255 - a) + kText[k] * a * 255 + 255 * 255 / 2) / (255 * 255));
        }
        img.rgba[i * 4 + 3] = static_cast<std::uint8_t>(255 - (keep + 127) / 255);
    }
    return img;
}

void AttributionOverlay::apply(std::uint8_t* rgba, int stride) const {
    for (int y = 0; y < m_h; ++y) {
        std::uint8_t* row = rgba + static_cast<std::size_t>(m_y + y) * stride + static_cast<std::size_t>(m_x) * 4;
        const std::uint8_t* cov = m_coverage.data() + static_cast<std::size_t>(y) * m_w;
        for (int x = 0; x < m_w; ++x) {
            std::uint8_t* p = row + x * 4;
            const int a = cov[x];
            for (int k = 0; k < 3; ++k) {
                const int boxed = (p[k] * (255 - kBoxAlpha) + kBox[k] * kBoxAlpha + 127) / 255;
                p[k] = static_cast<std::uint8_t>((boxed * (255 - a) + kText[k] * a + 127) / 255);
            }
            p[3] = 255;
        }
    }
}

}  // namespace navmap::daemon
