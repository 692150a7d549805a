// SPDX-License-Identifier: Apache-2.0
#include "navmap/map/ortho/tile_sampler.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace navmap::map::ortho {

namespace {

float lightsDecode(std::uint8_t v) { return static_cast<float>(v) / 255.0f; }

}  // namespace

std::string orthoLayersProblem(const Tile& tile) {
    const OrthoLayers& o = tile.ortho;
    const std::string where = "tile " + tile.id.toString() + ": ";
    if (o.empty()) return where + "no ortho layers";
    if (!(tile.size_m > 0)) return where + "tile size " + std::to_string(tile.size_m) + " m";
    const std::size_t texels = std::size_t{o.cover_size} * o.cover_size;
    if (o.cover.size() != texels) {
        return where + "ortho layer cover has " + std::to_string(o.cover.size()) + " texels, expected " +
               std::to_string(texels) + " (" + std::to_string(o.cover_size) + "x" + std::to_string(o.cover_size) + ")";
    }
    if (o.grid_size < 2) return where + "ortho grid size " + std::to_string(o.grid_size) + ", expected 2 or more";
    const std::size_t samples = std::size_t{o.grid_size} * o.grid_size;
    const std::pair<const char*, std::size_t> layers[] = {
        {"climate", o.climate.size()},       {"temp_dec", o.temp_dec.size()},     {"temp_jul", o.temp_jul.size()},
        {"precip_dec", o.precip_dec.size()}, {"precip_jul", o.precip_jul.size()}, {"lights", o.lights.size()},
        {"elevation", o.elevation.size()}};
    for (const auto& [name, size] : layers) {
        if (size != samples) {
            return where + "ortho layer " + name + " has " + std::to_string(size) + " samples, expected " +
                   std::to_string(samples) + " (" + std::to_string(o.grid_size) + "x" + std::to_string(o.grid_size) +
                   ")";
        }
    }
    return {};
}

OrthoTileSampler::OrthoTileSampler(const Tile& tile) : m_layers(tile.ortho) {
    if (std::string problem = orthoLayersProblem(tile); !problem.empty()) throw std::invalid_argument(problem);
    m_texel = tile.size_m / m_layers.cover_size;
    m_spacing = tile.size_m / (m_layers.grid_size - 1);
}

OrthoTileSampler::Bilinear OrthoTileSampler::gridWeights(double x, double y) const {
    const int last = m_layers.grid_size - 1;
    const double gx = std::clamp(x / m_spacing, 0.0, double(last));
    const double gy = std::clamp(y / m_spacing, 0.0, double(last));
    const int c = std::min(static_cast<int>(gx), last - 1), r = std::min(static_cast<int>(gy), last - 1);
    const auto tx = static_cast<float>(gx - c), ty = static_cast<float>(gy - r);
    const int n = m_layers.grid_size;
    return {r * n + c,           r * n + c + 1, (r + 1) * n + c, (r + 1) * n + c + 1,
            (1 - tx) * (1 - ty), tx * (1 - ty), (1 - tx) * ty,   tx * ty};
}

float OrthoTileSampler::grid(const std::vector<std::uint8_t>& layer, const Bilinear& b, float (*decode)(std::uint8_t)) {
    auto at = [&](int i) { return decode(layer[static_cast<std::size_t>(i)]); };
    return b.w00 * at(b.i00) + b.w10 * at(b.i10) + b.w01 * at(b.i01) + b.w11 * at(b.i11);
}

SuperLandCover OrthoTileSampler::coverAt(double x, double y) const {
    const int n = m_layers.cover_size;
    const int c = std::clamp(static_cast<int>(std::floor(x / m_texel)), 0, n - 1);
    const int r = std::clamp(static_cast<int>(std::floor(y / m_texel)), 0, n - 1);
    return static_cast<SuperLandCover>(m_layers.cover[static_cast<std::size_t>(r) * n + c]);
}

OrthoPixel OrthoTileSampler::pixel(double x, double y) const {
    OrthoPixel p;
    // Land cover: the trained classes (trainedAs) of the four nearest texels with bilinear weights,
    // so classes blend across a texel as the trainer's 4x4 sub-samples blend them (seed 6.6.1).
    {
        const int n = m_layers.cover_size;
        const double fx = x / m_texel - 0.5, fy = y / m_texel - 0.5;
        const int c0 = static_cast<int>(std::floor(fx)), r0 = static_cast<int>(std::floor(fy));
        const auto tx = static_cast<float>(fx - c0), ty = static_cast<float>(fy - r0);
        auto cls = [&](int r, int c) {
            r = std::clamp(r, 0, n - 1);
            c = std::clamp(c, 0, n - 1);
            const auto super = static_cast<SuperLandCover>(m_layers.cover[static_cast<std::size_t>(r) * n + c]);
            return static_cast<std::uint8_t>(trainedAs(super));
        };
        p.cover = topTwoShares({cls(r0, c0), cls(r0, c0 + 1), cls(r0 + 1, c0), cls(r0 + 1, c0 + 1)},
                               {(1 - tx) * (1 - ty), tx * (1 - ty), (1 - tx) * ty, tx * ty});
    }
    const Bilinear b = gridWeights(x, y);
    auto climate = [&](int i) { return m_layers.climate[static_cast<std::size_t>(i)]; };
    p.climate =
        topTwoShares({climate(b.i00), climate(b.i10), climate(b.i01), climate(b.i11)}, {b.w00, b.w10, b.w01, b.w11});
    auto elevation = [&](int i) { return static_cast<float>(m_layers.elevation[static_cast<std::size_t>(i)]); };
    p.elevation_m =
        b.w00 * elevation(b.i00) + b.w10 * elevation(b.i10) + b.w01 * elevation(b.i01) + b.w11 * elevation(b.i11);
    p.temp_dec_c = grid(m_layers.temp_dec, b, temperatureFromCode);
    p.temp_jul_c = grid(m_layers.temp_jul, b, temperatureFromCode);
    p.precip_dec_mm = grid(m_layers.precip_dec, b, precipitationFromCode);
    p.precip_jul_mm = grid(m_layers.precip_jul, b, precipitationFromCode);
    p.lights = grid(m_layers.lights, b, lightsDecode);
    return p;
}

void OrthoTileSampler::encodeRows(double x0, double y0, double extent, int size, int row0, int row1,
                                  OrthoInput* out) const {
    const double step = extent / size;
    for (int r = row0; r < row1; ++r) {
        const double y = y0 + (r + 0.5) * step;
        for (int c = 0; c < size; ++c) *out++ = encodeInput(pixel(x0 + (c + 0.5) * step, y));
    }
}

}  // namespace navmap::map::ortho
