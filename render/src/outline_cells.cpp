// SPDX-License-Identifier: Apache-2.0
#include "outline_cells.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstring>
#include <limits>
#include <stdexcept>
#include <vector>

#include "navmap/render/road_style.h"

namespace navmap::render {

void OutlineCells::reset(int width, int height, int cell_px, float reach_px) {
    m_width = std::max(width, 0);
    m_height = std::max(height, 0);
    m_cell = std::max(cell_px, 1);
    m_reach = std::max(reach_px, 0.0f);
    m_columns = (m_width + m_cell - 1) / m_cell;
    m_rows = (m_height + m_cell - 1) / m_cell;
    m_marked.assign(static_cast<std::size_t>(m_columns) * static_cast<std::size_t>(m_rows), 0);
}

void OutlineCells::setView(const glm::mat4& view, const glm::mat4& projection) {
    m_view = view;
    m_view_projection = projection * view;
    m_eye_clip = projection[3];
}

void OutlineCells::markQuad(glm::vec3 p0, glm::vec3 p1, const QuadShape& shape, glm::vec2 cap_reach) {
    if (m_columns == 0 || m_rows == 0) return;
    // The quad as roads_geo.vert expands it. Its corners are linear in the end points and the
    // offsets along and across, and so are their clip positions: the view-space scale towards the
    // camera, (s v, 1) = s (v, 1) + (1 - s) (0, 0, 0, 1), becomes s c + (1 - s) eye_clip.
    const glm::vec3 mid = 0.5f * (p0 + p1);
    const float dist = glm::length(glm::vec3(m_view * glm::vec4(mid, 1.0f)));
    const float half_width = 0.5f * shape.width_m * distanceWidthScale(dist, shape.scale_threshold_m, shape.max_scale);
    const glm::vec2 d = glm::vec2(p1) - glm::vec2(p0);
    const float len = glm::length(d);
    const glm::vec2 t = len > 1e-6f ? d / len : glm::vec2(1.0f, 0.0f);
    const glm::vec2 n(-t.y, t.x);
    const float keep = 1.0f - shape.z_offset_alpha;
    const glm::vec4 c0 = keep * (m_view_projection * glm::vec4(p0, 1.0f)) + (1.0f - keep) * m_eye_clip;
    const glm::vec4 c1 = keep * (m_view_projection * glm::vec4(p1, 1.0f)) + (1.0f - keep) * m_eye_clip;
    const glm::vec4 across = keep * half_width * (n.x * m_view_projection[0] + n.y * m_view_projection[1]);
    const glm::vec4 along = keep * half_width * (t.x * m_view_projection[0] + t.y * m_view_projection[1]);
    // Around the quad: p0 + n - t, p1 + n + t, p1 - n + t, p0 - n - t (w/2 each, t times the reach).
    // The widest pass is the shortest in half widths: its quads keep whole caps wherever any
    // pass's do (capReach), so its reach bounds every pass's.
    const float half_length = half_width > 0.0f ? capHalfLength(len, 2.0f * half_width) : 0.0f;
    const glm::vec4 back = capReach(cap_reach.x, half_length) * along,
                    ahead = capReach(cap_reach.y, half_length) * along;
    const std::array<glm::vec4, 4> clip{c0 + across - back, c1 + across + ahead, c1 - across + ahead,
                                        c0 - across - back};
    const float reach = m_reach + widening(c0, c1, across, along, shape);
    // Clipped against the near plane (z >= -w) as the GPU clips it; the other planes only cut
    // what lies off the viewport, which the grid drops anyway.
    std::array<glm::vec2, 8> screen;
    int count = 0;
    const float half_w = 0.5f * static_cast<float>(m_width), half_h = 0.5f * static_cast<float>(m_height);
    auto emit = [&](const glm::vec4& c) {
        if (count >= static_cast<int>(screen.size()) || !(c.w > 0.0f)) return;
        const float inv_w = 1.0f / c.w;
        screen[static_cast<std::size_t>(count++)] = {(c.x * inv_w + 1.0f) * half_w, (c.y * inv_w + 1.0f) * half_h};
    };
    for (std::size_t i = 0; i < clip.size(); ++i) {
        const glm::vec4& a = clip[i];
        const glm::vec4& b = clip[(i + 1) % clip.size()];
        const float da = a.z + a.w, db = b.z + b.w;
        if (da >= 0.0f) emit(a);
        if ((da >= 0.0f) != (db >= 0.0f)) emit(a + (b - a) * (da / (da - db)));
    }
    if (count > 0) markPolygon(screen.data(), count, reach);
}

float OutlineCells::widening(const glm::vec4& c0, const glm::vec4& c1, const glm::vec4& across, const glm::vec4& along,
                             const QuadShape& shape) const {
    const float most = leastWidthGrowthPx(shape.min_width_px, shape.width_m, shape.fill_width_m);
    if (!(most > 0.0f)) return 0.0f;
    // The fill's width on screen at each end, to first order as the shader reckons it: the
    // across offset's screen derivative perpendicular to the road's screen direction.
    const glm::vec2 half_viewport(0.5f * static_cast<float>(m_width), 0.5f * static_cast<float>(m_height));
    for (const glm::vec4& c : {c0, c1}) {
        if (!(c.w > 0.0f)) return most;  // behind the camera: as wide as it can get
        auto to_px = [&](const glm::vec4& d) {
            return (glm::vec2(d) * c.w - glm::vec2(c) * d.w) / (c.w * c.w) * half_viewport;
        };
        const glm::vec2 st = to_px(along), sn = to_px(across);
        const float len = glm::length(st);
        if (!(len > 1e-9f)) continue;  // seen end-on: not widened
        const float half_outer = std::abs(st.x * sn.y - st.y * sn.x) / len;
        if (2.0f * half_outer * shape.fill_width_m / shape.width_m < shape.min_width_px) return most;
    }
    return 0.0f;
}

void OutlineCells::markPolygon(const glm::vec2* points, int count, float reach) {
    glm::vec2 lo = points[0], hi = points[0];
    for (int i = 0; i < count; ++i) {
        if (!std::isfinite(points[i].x) || !std::isfinite(points[i].y)) return;
        lo = glm::min(lo, points[i]);
        hi = glm::max(hi, points[i]);
    }
    const float cell = static_cast<float>(m_cell), inv_cell = 1.0f / cell;
    // Cells are indexed after clamping in float, so far-off corners cannot overflow an int.
    auto index = [&](float v, int n) {
        return static_cast<int>(std::floor(std::clamp(v * inv_cell, -1.0f, static_cast<float>(n))));
    };
    const int row_lo = std::max(index(lo.y - reach, m_rows), 0);
    const int row_hi = std::min(index(hi.y + reach, m_rows), m_rows - 1);
    // Each edge's x as a function of y, for the rows whose band holds only part of the polygon.
    std::array<float, 8> slope{};
    for (int i = 0; row_lo < row_hi && i < count; ++i) {
        const glm::vec2 a = points[i], b = points[(i + 1) % count];
        slope[static_cast<std::size_t>(i)] = a.y != b.y ? (b.x - a.x) / (b.y - a.y) : 0.0f;
    }
    for (int row = row_lo; row <= row_hi; ++row) {
        // The polygon's x-extent within the row's band grown by the reach: a convex polygon meets
        // a band in a convex piece, whose x-extent its clipped edges give (all of the polygon's
        // where the band holds it whole, as it does for most pieces, which are small on screen).
        const float band_lo = static_cast<float>(row) * cell - reach,
                    band_hi = static_cast<float>(row + 1) * cell + reach;
        float x_lo = lo.x, x_hi = hi.x;
        if (band_lo > lo.y || band_hi < hi.y) {
            x_lo = std::numeric_limits<float>::max();
            x_hi = std::numeric_limits<float>::lowest();
            for (int i = 0; i < count; ++i) {
                const glm::vec2 a = points[i], b = points[(i + 1) % count];
                const float y0 = std::max(std::min(a.y, b.y), band_lo), y1 = std::min(std::max(a.y, b.y), band_hi);
                if (y0 > y1) continue;
                float xa = a.x, xb = b.x;
                if (a.y != b.y) {
                    const float k = slope[static_cast<std::size_t>(i)];
                    xa = a.x + (y0 - a.y) * k;
                    xb = a.x + (y1 - a.y) * k;
                }
                x_lo = std::min({x_lo, xa, xb});
                x_hi = std::max({x_hi, xa, xb});
            }
            if (x_lo > x_hi) continue;
        }
        const int c0 = std::max(index(x_lo - reach, m_columns), 0);
        const int c1 = std::min(index(x_hi + reach, m_columns), m_columns - 1);
        if (c0 > c1) continue;
        std::uint8_t* cells = m_marked.data() + static_cast<std::size_t>(row) * static_cast<std::size_t>(m_columns);
        std::fill(cells + c0, cells + c1 + 1, std::uint8_t{1});
    }
}

std::vector<CellRect> OutlineCells::rects(int group) const {
    group = std::max(group, 1);
    const int groups = (m_columns + group - 1) / group, width = group * m_cell;
    std::vector<CellRect> done, open, next;
    for (int row = 0; row < m_rows; ++row) {
        const std::uint8_t* cells =
            m_marked.data() + static_cast<std::size_t>(row) * static_cast<std::size_t>(m_columns);
        auto marked = [&](int g) {
            const int c1 = std::min((g + 1) * group, m_columns);
            return std::find(cells + g * group, cells + c1, std::uint8_t{1}) != cells + c1;
        };
        const int y0 = row * m_cell, y1 = std::min((row + 1) * m_cell, m_height);
        next.clear();
        std::size_t o = 0;  // open rects and runs both run left to right
        for (int c = 0; c < groups;) {
            if (!marked(c)) {
                ++c;
                continue;
            }
            const int c0 = c;
            while (c < groups && marked(c)) ++c;
            const int x0 = c0 * width, x1 = std::min(c * width, m_width);
            while (o < open.size() && open[o].x0 < x0) done.push_back(open[o++]);
            if (o < open.size() && open[o].x0 == x0 && open[o].x1 == x1) {
                next.push_back(open[o++]);
                next.back().y1 = y1;
            } else {
                next.push_back({x0, y0, x1, y1});
            }
        }
        done.insert(done.end(), open.begin() + static_cast<std::ptrdiff_t>(o), open.end());
        open.swap(next);
    }
    done.insert(done.end(), open.begin(), open.end());
    return done;
}

bool OutlineCells::covers(int x, int y) const {
    if (x < 0 || y < 0 || x >= m_width || y >= m_height) return false;
    return m_marked[static_cast<std::size_t>(y / m_cell) * static_cast<std::size_t>(m_columns) +
                    static_cast<std::size_t>(x / m_cell)] != 0;
}

namespace {

// Bit k: whether byte k of the 8 at `p` is above 127. The top bits, masked, are gathered into
// one byte by a multiply (byte k's bit lands in bit 56 + k).
std::uint64_t topBits(const std::uint8_t* p) {
    std::uint64_t v;
    if constexpr (std::endian::native == std::endian::little) {
        std::memcpy(&v, p, 8);
    } else {
        v = 0;
        for (int k = 0; k < 8; ++k) v |= std::uint64_t{p[k]} << (8 * k);
    }
    return ((v & 0x8080808080808080ull) * 0x0002040810204081ull) >> 56;
}

// Bit k: whether byte k of the 64 at `p` is above 127 (written out: the compiler does not unroll
// at -O2, and variable shifts cost more than the gathering).
std::uint64_t topBits64(const std::uint8_t* p) {
    return topBits(p) | topBits(p + 8) << 8 | topBits(p + 16) << 16 | topBits(p + 24) << 24 | topBits(p + 32) << 32 |
           topBits(p + 40) << 40 | topBits(p + 48) << 48 | topBits(p + 56) << 56;
}

}  // namespace

void outlineEdges(const std::uint8_t* mask, int width, int height, std::uint16_t* edges) {
    if (width <= 0 || height <= 0) return;
    // Each row as a bit set, pixel x at bit x % 64 of word x / 64, zero beyond the width. Zero
    // beyond the border is the clamp: the clamped neighbour of a border pixel is the pixel itself
    // (or one of its row), which is a road pixel only where the pixel is no edge anyway.
    const int groups = packedMaskWidth(width);
    const int words = (width + 63) / 64;
    const auto row_words = static_cast<std::size_t>(words);
    std::vector<std::uint64_t> bits(row_words * static_cast<std::size_t>(height + 2), 0);  // rows -1 .. height
    for (int y = 0; y < height; ++y) {
        const std::uint8_t* row = mask + static_cast<std::size_t>(y) * static_cast<std::size_t>(width);
        std::uint64_t* out = bits.data() + row_words * static_cast<std::size_t>(y + 1);
        const int whole = width / 64;  // words of 64 pixels: the bits gathered in a register
        for (int j = 0; j < whole; ++j) out[j] = topBits64(row + 64 * j);
        if (whole < words) {  // the last, partial word
            std::uint8_t tail[64] = {};
            std::copy(row + 64 * whole, row + width, tail);
            out[whole] = topBits64(tail);
        }
    }
    std::vector<std::uint64_t> near(row_words);
    for (int y = 0; y < height; ++y) {
        const std::uint64_t* below = bits.data() + row_words * static_cast<std::size_t>(y);
        const std::uint64_t* here = below + row_words;
        const std::uint64_t* above = here + row_words;
        for (std::size_t j = 0; j < row_words; ++j) near[j] = below[j] | here[j] | above[j];
        std::uint16_t* out = edges + static_cast<std::size_t>(y) * static_cast<std::size_t>(groups);
        for (std::size_t j = 0; j < row_words; ++j) {
            // The left and right neighbours: shifts carrying across the words.
            const std::uint64_t left = near[j] << 1 | (j > 0 ? near[j - 1] >> 63 : 0);
            const std::uint64_t right = near[j] >> 1 | (j + 1 < row_words ? near[j + 1] << 63 : 0);
            std::uint64_t e = (near[j] | left | right) & ~here[j];
            const int end = width - 64 * static_cast<int>(j);  // pixels of the row in this word
            if (end >= 64) {
                std::uint16_t* o = out + 8 * j;
                o[0] = static_cast<std::uint16_t>(e & 0xFFu), o[1] = static_cast<std::uint16_t>(e >> 8 & 0xFFu);
                o[2] = static_cast<std::uint16_t>(e >> 16 & 0xFFu), o[3] = static_cast<std::uint16_t>(e >> 24 & 0xFFu);
                o[4] = static_cast<std::uint16_t>(e >> 32 & 0xFFu), o[5] = static_cast<std::uint16_t>(e >> 40 & 0xFFu);
                o[6] = static_cast<std::uint16_t>(e >> 48 & 0xFFu), o[7] = static_cast<std::uint16_t>(e >> 56);
                continue;
            }
            e &= (std::uint64_t{1} << end) - 1;
            for (int k = 0; 8 * k < end; ++k)
                out[8 * j + static_cast<std::size_t>(k)] = static_cast<std::uint16_t>(e >> (8 * k) & 0xFFu);
        }
    }
}

void OutlineCells::markEdges(const std::uint16_t* edges, int groups) {
    // A texel of the edge mask is one row of one cell.
    if (m_cell != kPackedMaskPixels) throw std::logic_error("OutlineCells::markEdges needs cells of kPackedMaskPixels");
    for (int y = 0; y < m_height; ++y) {
        const std::uint16_t* row = edges + static_cast<std::size_t>(y) * static_cast<std::size_t>(groups);
        std::uint8_t* cells =
            m_marked.data() + static_cast<std::size_t>(y / m_cell) * static_cast<std::size_t>(m_columns);
        for (int g = 0; g < groups && g < m_columns; ++g) cells[g] |= row[g] != 0;
    }
}

}  // namespace navmap::render
