// SPDX-License-Identifier: Apache-2.0
#include "navmap/map/ortho/color_difference.h"

#include <algorithm>
#include <cmath>

namespace navmap::map::ortho {

namespace {

double linear(double c) { return c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4); }
double labF(double t) { return t > 216.0 / 24389.0 ? std::cbrt(t) : (24389.0 / 27.0 * t + 16.0) / 116.0; }

}  // namespace

std::array<double, 3> srgbToLab(const std::array<float, 3>& rgb) {
    const double r = linear(std::clamp<double>(rgb[0], 0, 1)), g = linear(std::clamp<double>(rgb[1], 0, 1)),
                 b = linear(std::clamp<double>(rgb[2], 0, 1));
    // sRGB -> XYZ (D65), normalized by the white point.
    const double x = (0.4124564 * r + 0.3575761 * g + 0.1804375 * b) / 0.95047;
    const double y = 0.2126729 * r + 0.7151522 * g + 0.0721750 * b;
    const double z = (0.0193339 * r + 0.1191920 * g + 0.9503041 * b) / 1.08883;
    const double fx = labF(x), fy = labF(y), fz = labF(z);
    return {116.0 * fy - 16.0, 500.0 * (fx - fy), 200.0 * (fy - fz)};
}

double deltaE76(const std::array<float, 3>& a, const std::array<float, 3>& b) {
    const auto la = srgbToLab(a), lb = srgbToLab(b);
    return std::sqrt((la[0] - lb[0]) * (la[0] - lb[0]) + (la[1] - lb[1]) * (la[1] - lb[1]) +
                     (la[2] - lb[2]) * (la[2] - lb[2]));
}

}  // namespace navmap::map::ortho
