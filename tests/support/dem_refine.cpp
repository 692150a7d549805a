// SPDX-License-Identifier: Apache-2.0
#include "dem_refine.h"

#include <algorithm>
#include <cmath>

namespace navmap::render {

namespace {

// Catmull-Rom weights for a sample at fractional position t between p1 and p2.
double catmullRom(double p0, double p1, double p2, double p3, double t) {
    return p1 + 0.5 * t * (p2 - p0 + t * (2.0 * p0 - 5.0 * p1 + 4.0 * p2 - p3 + t * (3.0 * (p1 - p2) + p3 - p0)));
}

// Deterministic lattice value in [-1, 1] (integer hash, no global state).
double latticeValue(std::int64_t ix, std::int64_t iy, std::uint32_t octave, std::uint32_t seed) {
    std::uint64_t h = static_cast<std::uint64_t>(ix) * 0x9E3779B97F4A7C15ull ^
                      static_cast<std::uint64_t>(iy) * 0xC2B2AE3D27D4EB4Full ^ (std::uint64_t{octave} << 32) ^ seed;
    h ^= h >> 33;
    h *= 0xFF51AFD7ED558CCDull;
    h ^= h >> 33;
    h *= 0xC4CEB9FE1A85EC53ull;
    h ^= h >> 33;
    return static_cast<double>(h >> 11) / static_cast<double>(1ull << 53) * 2.0 - 1.0;
}

// Value noise with a smooth (quintic) blend between lattice values.
double valueNoise(double x, double y, std::uint32_t octave, std::uint32_t seed) {
    const double fx = std::floor(x), fy = std::floor(y);
    const auto ix = static_cast<std::int64_t>(fx), iy = static_cast<std::int64_t>(fy);
    auto fade = [](double t) { return t * t * t * (t * (t * 6.0 - 15.0) + 10.0); };
    const double u = fade(x - fx), v = fade(y - fy);
    const double a = latticeValue(ix, iy, octave, seed), b = latticeValue(ix + 1, iy, octave, seed);
    const double c = latticeValue(ix, iy + 1, octave, seed), d = latticeValue(ix + 1, iy + 1, octave, seed);
    return (a + (b - a) * u) + ((c + (d - c) * u) - (a + (b - a) * u)) * v;
}

}  // namespace

double demDetail(double x, double y, const DemRefineOptions& options) {
    double sum = 0.0, amplitude = options.detail_amplitude_m, wavelength = options.detail_wavelength_m;
    for (int o = 0; o < options.detail_octaves; ++o) {
        sum += amplitude * valueNoise(x / wavelength, y / wavelength, static_cast<std::uint32_t>(o), options.seed);
        amplitude *= 0.5;
        wavelength *= 0.5;
    }
    return sum;
}

map::TileDem refineDem(const map::TileDem& coarse, double tile_size_m, double origin_x, double origin_y,
                       const DemRefineOptions& options) {
    if (coarse.size < 2 || coarse.heights.size() != std::size_t{coarse.size} * coarse.size) return coarse;
    const int n = coarse.size;
    const int intervals =
        std::clamp(static_cast<int>(std::lround(tile_size_m / std::max(options.spacing_m, 0.1))), 1, 65534);
    map::TileDem out;
    out.size = static_cast<std::uint16_t>(intervals + 1);
    out.spacing_m = static_cast<float>(tile_size_m / intervals);
    out.coverage = coarse.coverage;
    out.heights.resize(std::size_t{out.size} * out.size);
    const double coarse_spacing = tile_size_m / (n - 1);
    // Samples one step outside the grid are extrapolated linearly, so the border cells keep the
    // Catmull-Rom properties (a plane stays a plane).
    auto col = [&](int r, int c) {
        const int cc = std::clamp(c, 0, n - 1);
        const double v = coarse.at(r, cc);
        if (c == cc) return v;
        return v + (v - coarse.at(r, c < 0 ? 1 : n - 2));
    };
    auto at = [&](int r, int c) {
        const int rc = std::clamp(r, 0, n - 1);
        const double v = col(rc, c);
        if (r == rc) return v;
        return v + (v - col(r < 0 ? 1 : n - 2, c));
    };
    for (int r = 0; r < out.size; ++r) {
        const double y = r * static_cast<double>(out.spacing_m);
        const double gy = std::min(y / coarse_spacing, n - 1.0);
        const int r1 = std::min(static_cast<int>(gy), n - 2);
        const double ty = gy - r1;
        for (int c = 0; c < out.size; ++c) {
            const double x = c * static_cast<double>(out.spacing_m);
            const double gx = std::min(x / coarse_spacing, n - 1.0);
            const int c1 = std::min(static_cast<int>(gx), n - 2);
            const double tx = gx - c1;
            double rows[4];
            for (int k = 0; k < 4; ++k) {
                const int rr = r1 - 1 + k;
                rows[k] = catmullRom(at(rr, c1 - 1), at(rr, c1), at(rr, c1 + 1), at(rr, c1 + 2), tx);
            }
            const double h =
                catmullRom(rows[0], rows[1], rows[2], rows[3], ty) + demDetail(origin_x + x, origin_y + y, options);
            out.heights[static_cast<std::size_t>(r) * out.size + c] = static_cast<float>(h);
        }
    }
    return out;
}

std::shared_ptr<map::Tile> refineTile(const map::Tile& tile, const DemRefineOptions& options) {
    auto out = std::make_shared<map::Tile>(tile);
    out->dem = refineDem(tile.dem, tile.size_m, tile.origin_x, tile.origin_y, options);
    return out;
}

}  // namespace navmap::render
