// SPDX-License-Identifier: Apache-2.0
#include "ortho_training_set.h"

#include <algorithm>
#include <cmath>
#include <numeric>

#include "navmap/map/ortho/rng.h"

namespace navmap::map::ortho {

namespace {

constexpr int kSuper = 4;  // Natural Earth subsamples per Blue Marble pixel and axis

bool inside(const HeldOutRegion& r, double lat, double lon, double margin) {
    return lat >= r.south - margin && lat <= r.north + margin && lon >= r.west - margin && lon <= r.east + margin;
}

void add(std::array<double, 3>& sum, const std::array<float, 3>& c) {
    for (std::size_t k = 0; k < 3; ++k) sum[k] += c[k];
}

}  // namespace

std::vector<HeldOutRegion> heldOutRegions() {
    // One per continent and climate family; the first holds the project's Andorra data.
    return {{"Pyrenees and Ebro (Andorra)", 40.5, -2.0, 44.5, 4.0},
            {"Sahel to Congo rim", 2.0, 15.0, 14.0, 27.0},
            {"Amazon and Cerrado", -16.0, -58.0, -4.0, -46.0},
            {"Great Plains", 34.0, -104.0, 46.0, -94.0},
            {"Ganges plain and Deccan", 18.0, 74.0, 28.0, 86.0},
            {"South-east Australia", -38.0, 140.0, -30.0, 150.0},
            {"Central Siberia", 54.0, 88.0, 64.0, 104.0}};
}

std::array<float, 3> Baselines::byClass(std::uint8_t cover) const {
    const auto& m = class_mean[std::min<std::size_t>(cover, kGlobalCoverCount - 1)];
    return {static_cast<float>(m[0]), static_cast<float>(m[1]), static_cast<float>(m[2])};
}

std::array<float, 3> Baselines::byLatitude(double lat) const {
    const auto band = static_cast<std::size_t>(std::clamp(static_cast<int>(std::floor(90.0 - lat)), 0, 179));
    const auto& m = latitude_mean[band];
    return {static_cast<float>(m[0]), static_cast<float>(m[1]), static_cast<float>(m[2])};
}

TrainingSet buildTrainingSet(const GlobalInputs& in, const RgbGrid& bm, const TrainingSetOptions& options,
                             const std::function<void(const std::string&)>& log) {
    const int cols = bm.width, rows = bm.height;
    const std::vector<HeldOutRegion> regions = heldOutRegions();
    GeoWindow fine;
    fine.width = cols * kSuper;
    fine.height = rows * kSuper;
    log("rasterizing Natural Earth at " + std::to_string(fine.width) + "x" + std::to_string(fine.height));
    const std::vector<std::uint8_t> ne = in.cover.rasterize(fine);

    // Pass 1: class shares per pixel, baselines, probability map.
    const std::size_t count = static_cast<std::size_t>(cols) * rows;
    std::vector<ClassShares> shares(count);
    std::vector<int> region(count, -1);  // held-out region, -2: buffer
    std::array<std::size_t, kGlobalCoverCount> frequency{};
    struct Sums {
        std::array<std::array<double, 3>, kGlobalCoverCount> cls{};
        std::array<std::size_t, kGlobalCoverCount> cls_n{};
        std::array<std::array<double, 3>, 180> lat{};
        std::array<std::size_t, 180> lat_n{};
    } land_sums, all_sums;
    TrainingSet set;
    for (int y = 0; y < rows; ++y) {
        const double lat = 90.0 - (y + 0.5) * 180.0 / rows;
        const auto band = static_cast<std::size_t>(std::clamp(static_cast<int>(std::floor(90.0 - lat)), 0, 179));
        for (int x = 0; x < cols; ++x) {
            const double lon = -180.0 + (x + 0.5) * 360.0 / cols;
            const std::size_t i = static_cast<std::size_t>(y) * cols + x;
            std::array<int, kGlobalCoverCount> n{};
            for (int sy = 0; sy < kSuper; ++sy) {
                const std::uint8_t* row =
                    &ne[static_cast<std::size_t>(y * kSuper + sy) * fine.width + static_cast<std::size_t>(x) * kSuper];
                for (int sx = 0; sx < kSuper; ++sx) ++n[row[sx]];
            }
            std::array<std::uint8_t, 4> cls{};
            std::array<float, 4> w{};
            // The four largest counts feed topTwoShares (it needs at most two).
            std::array<int, kGlobalCoverCount> order{};
            std::iota(order.begin(), order.end(), 0);
            std::stable_sort(order.begin(), order.end(), [&](int a, int b) {
                return n[static_cast<std::size_t>(a)] > n[static_cast<std::size_t>(b)];
            });
            for (std::size_t k = 0; k < 4; ++k) {
                cls[k] = static_cast<std::uint8_t>(order[k]);
                w[k] = static_cast<float>(n[static_cast<std::size_t>(order[k])]) / float(kSuper * kSuper);
            }
            shares[i] = topTwoShares(cls, w);
            for (std::size_t r = 0; r < regions.size(); ++r) {
                if (inside(regions[r], lat, lon, 0.0)) {
                    region[i] = static_cast<int>(r);
                    break;
                }
                if (inside(regions[r], lat, lon, kHeldOutBufferDeg)) region[i] = -2;
            }
            if (region[i] != -1) continue;
            ++set.training_pixels;
            const auto c = shares[i].first;
            ++frequency[c];
            const auto colour = bm.at(x, y);
            for (Sums* s : {&all_sums, c == std::uint8_t(GlobalCover::Ocean) || c == std::uint8_t(GlobalCover::Lake)
                                           ? nullptr
                                           : &land_sums}) {
                if (!s) continue;
                add(s->cls[c], colour);
                ++s->cls_n[c];
                add(s->lat[band], colour);
                ++s->lat_n[band];
            }
        }
    }
    auto finish = [](const Sums& s, Baselines& b) {
        std::array<double, 3> total{};
        std::size_t total_n = 0;
        for (std::size_t c = 0; c < kGlobalCoverCount; ++c) {
            for (std::size_t k = 0; k < 3; ++k) total[k] += s.cls[c][k];
            total_n += s.cls_n[c];
        }
        for (std::size_t k = 0; k < 3; ++k) total[k] /= double(std::max<std::size_t>(total_n, 1));
        for (std::size_t c = 0; c < kGlobalCoverCount; ++c) {
            for (std::size_t k = 0; k < 3; ++k)
                b.class_mean[c][k] = s.cls_n[c] ? s.cls[c][k] / double(s.cls_n[c]) : total[k];
        }
        for (std::size_t r = 0; r < 180; ++r) {
            for (std::size_t k = 0; k < 3; ++k)
                b.latitude_mean[r][k] = s.lat_n[r] ? s.lat[r][k] / double(s.lat_n[r]) : total[k];
        }
    };
    finish(land_sums, set.land);
    finish(all_sums, set.all);

    // Probability map (seed 6.6.1): rare land-cover classes more often, homogeneous open water,
    // poles and deserts less often. Weighted sampling without replacement (Efraimidis-Spirakis).
    Rng rng(options.seed);
    std::vector<std::pair<double, std::uint32_t>> keys;
    keys.reserve(set.training_pixels);
    for (std::size_t i = 0; i < count; ++i) {
        if (region[i] != -1) continue;
        const int y = static_cast<int>(i / static_cast<std::size_t>(cols));
        const double lat = 90.0 - (y + 0.5) * 180.0 / rows;
        const auto c = shares[i].first;
        double w = 1.0 / std::sqrt(double(std::max<std::size_t>(frequency[c], 1)));
        if (c == std::uint8_t(GlobalCover::Ocean) && shares[i].first_share >= 1.0f) w *= 0.1;
        if (std::abs(lat) > 75.0) w *= 0.3;
        keys.emplace_back(std::log(std::max(rng.uniform(), 1e-300)) / w, static_cast<std::uint32_t>(i));
    }
    const std::size_t take = std::min(options.samples, keys.size());
    std::partial_sort(keys.begin(), keys.begin() + static_cast<std::ptrdiff_t>(take), keys.end(),
                      [](const auto& a, const auto& b) { return a.first > b.first; });
    keys.resize(take);
    std::sort(keys.begin(), keys.end(), [](const auto& a, const auto& b) { return a.second < b.second; });

    // Pass 2: inputs of the chosen and the held-out pixels.
    auto pixel_at = [&](std::size_t i) {
        const int y = static_cast<int>(i / static_cast<std::size_t>(cols)),
                  x = static_cast<int>(i % static_cast<std::size_t>(cols));
        const double lat = 90.0 - (y + 0.5) * 180.0 / rows, lon = -180.0 + (x + 0.5) * 360.0 / cols;
        OrthoPixel p;
        p.cover = shares[i];
        p.climate = in.climate.shares(lat, lon);
        const double dlat = 90.0 / rows, dlon = 180.0 / cols;
        p.elevation_m = in.elevation.boxMean(lat - dlat, lon - dlon, lat + dlat, lon + dlon);
        p.temp_dec_c = in.temp_dec.bilinear(lat, lon);
        p.temp_jul_c = in.temp_jul.bilinear(lat, lon);
        p.precip_dec_mm = in.precip_dec.bilinear(lat, lon);
        p.precip_jul_mm = in.precip_jul.bilinear(lat, lon);
        p.lights = in.lights.bilinear(lat, lon);
        GlobePixel g;
        g.sample.input = encodeInput(p);
        g.sample.target = bm.at(x, y);
        g.lat = lat;
        g.lon = lon;
        g.cover = shares[i].first;
        g.region = region[i];
        return g;
    };
    const auto validation_every =
        options.validation_share > 0 ? static_cast<std::size_t>(std::lround(1.0 / options.validation_share)) : 0;
    for (std::size_t k = 0; k < keys.size(); ++k) {
        const GlobePixel g = pixel_at(keys[k].second);
        (validation_every && k % validation_every == 0 ? set.validation : set.train).push_back(g.sample);
    }
    for (std::size_t i = 0; i < count; ++i) {
        if (region[i] >= 0) set.held_out.push_back(pixel_at(i));
    }
    log("training set: " + std::to_string(set.train.size()) + " samples, validation " +
        std::to_string(set.validation.size()) + ", held out " + std::to_string(set.held_out.size()) + " pixels in " +
        std::to_string(regions.size()) + " regions");
    return set;
}

}  // namespace navmap::map::ortho
