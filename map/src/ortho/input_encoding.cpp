// SPDX-License-Identifier: Apache-2.0
#include "navmap/map/ortho/input_encoding.h"

#include <algorithm>
#include <cmath>

namespace navmap::map::ortho {

std::uint8_t quantizeInput(float v) {
    if (!(v > 0.0f)) return 0;  // NaN too
    return static_cast<std::uint8_t>(std::lround(std::min(v, 1.0f) * 255.0f));
}

OrthoInput encodeInput(const OrthoPixel& p) {
    OrthoInput in;
    int k = 0;
    auto put = [&](int node, float v) {
        in.pairs[static_cast<std::size_t>(2 * k)] = static_cast<std::uint8_t>(node);
        in.pairs[static_cast<std::size_t>(2 * k + 1)] = quantizeInput(v);
        ++k;
    };
    put(kCoverNode + std::min<int>(p.cover.first, kGlobalCoverCount - 1), p.cover.first_share);
    put(kCoverNode + std::min<int>(p.cover.second, kGlobalCoverCount - 1), p.cover.second_share);
    put(kClimateNode + std::min<int>(p.climate.first, kClimateClassCount - 1), p.climate.first_share);
    put(kClimateNode + std::min<int>(p.climate.second, kClimateClassCount - 1), p.climate.second_share);
    put(kElevationNode, std::max(p.elevation_m, 0.0f) / 6000.0f);
    put(kTempDecNode, (p.temp_dec_c + 70.0f) / 115.0f);
    put(kTempJulNode, (p.temp_jul_c + 70.0f) / 115.0f);
    put(kPrecipDecNode, std::sqrt(std::max(p.precip_dec_mm, 0.0f) / 2048.0f));
    put(kPrecipJulNode, std::sqrt(std::max(p.precip_jul_mm, 0.0f) / 2048.0f));
    put(kLightsNode, p.lights);
    return in;
}

std::array<float, kOrthoInputs> expandInput(const OrthoInput& in) {
    std::array<float, kOrthoInputs> v{};
    for (int k = 0; k < kOrthoActive; ++k) {
        if (in.node(k) < kOrthoInputs) v[static_cast<std::size_t>(in.node(k))] += in.value(k);
    }
    return v;
}

}  // namespace navmap::map::ortho
