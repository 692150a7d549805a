// SPDX-License-Identifier: Apache-2.0
#include "navmap/map/ortho/climate.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>

#include "navmap/map/ortho/rng.h"

namespace navmap::map::ortho {

namespace {

constexpr std::uint8_t kNone = 255;

int wrap(int x, int w) {
    x %= w;
    return x < 0 ? x + w : x;
}

/// Months above 10 C, with the year as a sine between the coldest and the warmest month.
double monthsAbove10(double t_cold, double t_warm) {
    const double mean = 0.5 * (t_cold + t_warm), amplitude = 0.5 * (t_warm - t_cold);
    if (amplitude < 1e-6) return mean > 10.0 ? 12.0 : 0.0;
    const double c = std::clamp((10.0 - mean) / amplitude, -1.0, 1.0);
    return 12.0 * std::acos(c) / std::numbers::pi;
}

}  // namespace

const char* climateName(ClimateClass c) {
    static constexpr const char* kNames[kClimateClassCount] = {
        "Af",  "Am",  "Aw",  "BWh", "BWk", "BSh", "BSk", "Csa", "Csb", "Csc", "Cwa", "Cwb", "Cwc", "Cfa", "Cfb",
        "Cfc", "Dsa", "Dsb", "Dsc", "Dsd", "Dwa", "Dwb", "Dwc", "Dwd", "Dfa", "Dfb", "Dfc", "Dfd", "ET",  "EF"};
    const auto i = static_cast<std::size_t>(c);
    return i < kClimateClassCount ? kNames[i] : "?";
}

ClimateClass classifyClimate(float t_dec, float t_jul, float p_dec, float p_jul, double lat) {
    using C = ClimateClass;
    const double t_warm = std::max(t_dec, t_jul), t_cold = std::min(t_dec, t_jul);
    const double mat = 0.5 * (t_dec + t_jul);
    const double p_summer = lat >= 0 ? p_jul : p_dec, p_winter = lat >= 0 ? p_dec : p_jul;
    const double map = 6.0 * (double(p_dec) + double(p_jul));
    const double p_dry = std::min(p_dec, p_jul);
    if (t_warm < 10.0) return t_warm < 0.0 ? C::EF : C::ET;
    // Peel et al.: P_threshold = 2 MAT, + 28 with 70 % of the rain in summer, + 14 without a
    // season; arid (B) where MAP < 10 P_threshold, desert (BW) below 5 P_threshold.
    const double summer_share = map > 0 ? 6.0 * p_summer / map : 0.5;
    const double arid_mm = 10.0 * (2.0 * mat + (summer_share >= 0.7 ? 28.0 : summer_share > 0.3 ? 14.0 : 0.0));
    if (map < arid_mm) {
        const bool desert = map < 0.5 * arid_mm;
        const bool hot = mat >= 18.0;
        return desert ? (hot ? C::BWh : C::BWk) : (hot ? C::BSh : C::BSk);
    }
    if (t_cold >= 18.0) {
        if (p_dry >= 60.0) return C::Af;
        if (p_dry >= 100.0 - map / 25.0) return C::Am;
        return C::Aw;
    }
    // Precipitation regime: s (dry summer), w (dry winter), f (no dry season).
    int regime = 2;
    if (p_summer < 40.0 && p_summer < p_winter / 3.0) {
        regime = 0;
    } else if (p_winter < p_summer / 10.0) {
        regime = 1;
    }
    // Summer heat: a (warmest >= 22), b (4 months >= 10), c, d (coldest < -38, D only).
    const double months = monthsAbove10(t_cold, t_warm);
    int heat = t_warm >= 22.0 ? 0 : months >= 4.0 ? 1 : 2;
    if (t_cold > 0.0) {
        static constexpr C kC[3][3] = {{C::Csa, C::Csb, C::Csc}, {C::Cwa, C::Cwb, C::Cwc}, {C::Cfa, C::Cfb, C::Cfc}};
        return kC[regime][heat];
    }
    if (heat == 2 && t_cold < -38.0) heat = 3;
    static constexpr C kD[3][4] = {
        {C::Dsa, C::Dsb, C::Dsc, C::Dsd}, {C::Dwa, C::Dwb, C::Dwc, C::Dwd}, {C::Dfa, C::Dfb, C::Dfc, C::Dfd}};
    return kD[regime][heat];
}

ClassShares topTwoShares(const std::array<std::uint8_t, 4>& classes, const std::array<float, 4>& weights) {
    std::array<std::uint8_t, 4> cls{};
    std::array<float, 4> share{};
    int n = 0;
    for (std::size_t i = 0; i < 4; ++i) {
        if (weights[i] <= 0.0f) continue;
        int k = 0;
        while (k < n && cls[static_cast<std::size_t>(k)] != classes[i]) ++k;
        if (k == n) {
            cls[static_cast<std::size_t>(n)] = classes[i];
            share[static_cast<std::size_t>(n++)] = 0.0f;
        }
        share[static_cast<std::size_t>(k)] += weights[i];
    }
    ClassShares out;
    if (n == 0) {
        out.first = classes[0];
        return out;
    }
    auto better = [&](int a, int b) {
        const auto ia = static_cast<std::size_t>(a), ib = static_cast<std::size_t>(b);
        return share[ia] > share[ib] || (share[ia] == share[ib] && cls[ia] < cls[ib]);
    };
    int best = 0;
    for (int k = 1; k < n; ++k) {
        if (better(k, best)) best = k;
    }
    int next = -1;
    for (int k = 0; k < n; ++k) {
        if (k != best && (next < 0 || better(k, next))) next = k;
    }
    out.first = cls[static_cast<std::size_t>(best)];
    out.first_share = share[static_cast<std::size_t>(best)];
    if (next >= 0) {
        out.second = cls[static_cast<std::size_t>(next)];
        out.second_share = share[static_cast<std::size_t>(next)];
    } else {
        out.second = out.first;
        out.second_share = 0.0f;
    }
    return out;
}

ClimateClass ClimateGrid::nearest(double lat, double lon) const {
    const int x = wrap(static_cast<int>(std::floor((lon + 180.0) / 360.0 * width)), width);
    const int y = std::clamp(static_cast<int>(std::floor((90.0 - lat) / 180.0 * height)), 0, height - 1);
    return static_cast<ClimateClass>(classes[static_cast<std::size_t>(y) * width + x]);
}

ClassShares ClimateGrid::shares(double lat, double lon) const {
    const double fx = (lon + 180.0) / 360.0 * width - 0.5;
    const double fy = std::clamp((90.0 - lat) / 180.0 * height - 0.5, 0.0, double(height - 1));
    const int x0 = static_cast<int>(std::floor(fx)), y0 = std::min(static_cast<int>(std::floor(fy)), height - 1);
    const int y1 = std::min(y0 + 1, height - 1);
    const auto tx = static_cast<float>(fx - x0), ty = static_cast<float>(fy - y0);
    auto at = [&](int x, int y) { return classes[static_cast<std::size_t>(y) * width + wrap(x, width)]; };
    return topTwoShares({at(x0, y0), at(x0 + 1, y0), at(x0, y1), at(x0 + 1, y1)},
                        {(1 - tx) * (1 - ty), tx * (1 - ty), (1 - tx) * ty, tx * ty});
}

ClimateGrid buildClimateGrid(const GeoGrid& t_dec, const GeoGrid& t_jul, const GeoGrid& p_dec, const GeoGrid& p_jul,
                             const NaturalEarthCover& cover, std::uint64_t seed, int iterations) {
    const int w = t_dec.width, h = t_dec.height;
    for (const GeoGrid* g : {&t_jul, &p_dec, &p_jul}) {
        if (g->width != w || g->height != h) {
            throw std::invalid_argument(g->name + ": " + std::to_string(g->width) + "x" + std::to_string(g->height) +
                                        ", expected " + std::to_string(w) + "x" + std::to_string(h) + " as " +
                                        t_dec.name);
        }
    }
    ClimateGrid grid;
    grid.width = w;
    grid.height = h;
    grid.classes.assign(static_cast<std::size_t>(w) * h, kNone);
    GeoWindow window;
    window.width = w;
    window.height = h;
    const std::vector<std::uint8_t> ne =
        cover.empty() ? std::vector<std::uint8_t>(grid.classes.size(), 1) : cover.rasterize(window);
    auto land = [&](std::size_t i) {
        const auto c = static_cast<GlobalCover>(ne[i]);
        return c != GlobalCover::Ocean && c != GlobalCover::Lake;
    };
    std::vector<std::uint32_t> land_cells;
    for (int y = 0; y < h; ++y) {
        const double lat = window.lat(y);
        for (int x = 0; x < w; ++x) {
            const auto i = static_cast<std::size_t>(y) * w + x;
            if (!land(i)) continue;
            grid.classes[i] = static_cast<std::uint8_t>(
                classifyClimate(t_dec.decode[t_dec.codes[i]], t_jul.decode[t_jul.codes[i]],
                                p_dec.decode[p_dec.codes[i]], p_jul.decode[p_jul.codes[i]], lat));
            land_cells.push_back(static_cast<std::uint32_t>(i));
        }
    }
    // Scrambling (seed 6.5): swap each land pixel with a random land 4-neighbour, sweep by sweep.
    Rng rng(seed);
    for (int it = 0; it < iterations; ++it) {
        for (std::uint32_t i : land_cells) {
            const int x = static_cast<int>(i % static_cast<std::uint32_t>(w)),
                      y = static_cast<int>(i / static_cast<std::uint32_t>(w));
            static constexpr int kDx[4] = {1, -1, 0, 0}, kDy[4] = {0, 0, 1, -1};
            const auto k = static_cast<std::size_t>(rng.below(4));
            const int ny = y + kDy[k];
            if (ny < 0 || ny >= h) continue;
            const auto j = static_cast<std::size_t>(ny) * w + wrap(x + kDx[k], w);
            if (!land(j)) continue;
            std::swap(grid.classes[i], grid.classes[j]);
        }
    }
    // Coastline correction (seed 6.5): land classes grow into the water, nearest first.
    std::vector<std::uint32_t> frontier = land_cells, next;
    while (!frontier.empty()) {
        next.clear();
        for (std::uint32_t i : frontier) {
            const int x = static_cast<int>(i % static_cast<std::uint32_t>(w)),
                      y = static_cast<int>(i / static_cast<std::uint32_t>(w));
            const std::pair<int, int> nbs[4] = {{x + 1, y}, {x - 1, y}, {x, y + 1}, {x, y - 1}};
            for (const auto& [nx, ny] : nbs) {
                if (ny < 0 || ny >= h) continue;
                const auto j = static_cast<std::size_t>(ny) * w + wrap(nx, w);
                if (grid.classes[j] != kNone) continue;
                grid.classes[j] = grid.classes[i];
                next.push_back(static_cast<std::uint32_t>(j));
            }
        }
        frontier.swap(next);
    }
    // No land at all (a test grid without cover): classify every pixel directly.
    for (int y = 0; y < h; ++y) {
        for (int x = 0; x < w; ++x) {
            const auto i = static_cast<std::size_t>(y) * w + x;
            if (grid.classes[i] != kNone) continue;
            grid.classes[i] = static_cast<std::uint8_t>(
                classifyClimate(t_dec.decode[t_dec.codes[i]], t_jul.decode[t_jul.codes[i]],
                                p_dec.decode[p_dec.codes[i]], p_jul.decode[p_jul.codes[i]], window.lat(y)));
        }
    }
    return grid;
}

}  // namespace navmap::map::ortho
