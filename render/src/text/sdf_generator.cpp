// SPDX-License-Identifier: Apache-2.0
#include "navmap/render/text/sdf_generator.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace navmap::render::text {

namespace {

constexpr float kInf = 1e20f;

// One-dimensional squared Euclidean distance transform of sampled function f (Felzenszwalb &
// Huttenlocher 2012, "Distance Transforms of Sampled Functions"): lower envelope of parabolas.
void edt1d(const float* f, int n, float* d, int* v, float* z) {
    int k = 0;
    v[0] = 0;
    z[0] = -kInf;
    z[1] = kInf;
    for (int q = 1; q < n; ++q) {
        float s = 0.0f;
        for (;;) {
            const int p = v[k];
            s = ((f[q] + static_cast<float>(q) * static_cast<float>(q)) -
                 (f[p] + static_cast<float>(p) * static_cast<float>(p))) /
                (2.0f * static_cast<float>(q - p));
            if (s > z[k] || k == 0) break;
            --k;
        }
        if (s <= z[k] && k == 0) {
            v[0] = q;
            z[0] = -kInf;
            z[1] = kInf;
            continue;
        }
        ++k;
        v[k] = q;
        z[k] = s;
        z[k + 1] = kInf;
    }
    k = 0;
    for (int q = 0; q < n; ++q) {
        while (z[k + 1] < static_cast<float>(q)) ++k;
        const float dq = static_cast<float>(q - v[k]);
        d[q] = dq * dq + f[v[k]];
    }
}

// Squared distance from every pixel to the nearest pixel where `feature` is true.
std::vector<float> edt2d(const std::vector<std::uint8_t>& feature, int w, int h) {
    std::vector<float> grid(static_cast<std::size_t>(w) * h);
    for (std::size_t i = 0; i < grid.size(); ++i) grid[i] = feature[i] ? 0.0f : kInf;
    const int n = std::max(w, h);
    std::vector<float> f(static_cast<std::size_t>(n)), d(static_cast<std::size_t>(n)),
        z(static_cast<std::size_t>(n) + 1);
    std::vector<int> v(static_cast<std::size_t>(n));
    for (int x = 0; x < w; ++x) {
        for (int y = 0; y < h; ++y) f[static_cast<std::size_t>(y)] = grid[static_cast<std::size_t>(y) * w + x];
        edt1d(f.data(), h, d.data(), v.data(), z.data());
        for (int y = 0; y < h; ++y) grid[static_cast<std::size_t>(y) * w + x] = d[static_cast<std::size_t>(y)];
    }
    for (int y = 0; y < h; ++y) {
        float* row = &grid[static_cast<std::size_t>(y) * w];
        std::copy(row, row + w, f.begin());
        edt1d(f.data(), w, d.data(), v.data(), z.data());
        std::copy(d.begin(), d.begin() + w, row);
    }
    return grid;
}

}  // namespace

GrayImage makeSdf(std::span<const std::uint8_t> coverage, int width, int height, int pitch, int downsample,
                  float spread_px) {
    GrayImage out;
    if (width <= 0 || height <= 0 || downsample <= 0 || width % downsample || height % downsample) return out;
    const std::size_t count = static_cast<std::size_t>(width) * height;
    std::vector<std::uint8_t> inside(count), outside(count);
    for (int y = 0; y < height; ++y) {
        for (int x = 0; x < width; ++x) {
            const bool in = coverage[static_cast<std::size_t>(y) * pitch + x] >= 128;
            inside[static_cast<std::size_t>(y) * width + x] = in;
            outside[static_cast<std::size_t>(y) * width + x] = !in;
        }
    }
    const std::vector<float> to_inside = edt2d(inside, width, height);
    const std::vector<float> to_outside = edt2d(outside, width, height);

    out.width = width / downsample;
    out.height = height / downsample;
    out.pixels.resize(static_cast<std::size_t>(out.width) * out.height);
    const float inv_block = 1.0f / static_cast<float>(downsample * downsample);
    const float scale = 1.0f / (static_cast<float>(downsample) * 2.0f * spread_px);
    for (int oy = 0; oy < out.height; ++oy) {
        for (int ox = 0; ox < out.width; ++ox) {
            // Mean of the block's signed distances approximates the distance at its center.
            float sum = 0.0f;
            for (int by = 0; by < downsample; ++by) {
                for (int bx = 0; bx < downsample; ++bx) {
                    const std::size_t i =
                        static_cast<std::size_t>(oy * downsample + by) * width + (ox * downsample + bx);
                    // Pixel centers: the edge lies half a pixel from the nearest opposite one.
                    sum += inside[i] ? std::sqrt(to_outside[i]) - 0.5f : 0.5f - std::sqrt(to_inside[i]);
                }
            }
            const float v = 0.5f + sum * inv_block * scale;
            out.pixels[static_cast<std::size_t>(oy) * out.width + ox] =
                static_cast<std::uint8_t>(std::lround(std::clamp(v, 0.0f, 1.0f) * 255.0f));
        }
    }
    return out;
}

}  // namespace navmap::render::text
