// SPDX-License-Identifier: Apache-2.0
#include "navmap/map/ortho/geo_grid.h"

#include <algorithm>
#include <cmath>

namespace navmap::map::ortho {

namespace {

int wrapX(int x, int width) {
    x %= width;
    return x < 0 ? x + width : x;
}

}  // namespace

float GeoGrid::bilinear(double lat, double lon) const {
    const double fx = px(lon), fy = std::clamp(py(lat), 0.0, double(height - 1));
    const int x0 = static_cast<int>(std::floor(fx)), y0 = std::min(static_cast<int>(std::floor(fy)), height - 1);
    const int y1 = std::min(y0 + 1, height - 1);
    const double tx = fx - x0, ty = fy - y0;
    const int xa = wrapX(x0, width), xb = wrapX(x0 + 1, width);
    const double top = (1 - tx) * decode[code(xa, y0)] + tx * decode[code(xb, y0)];
    const double bottom = (1 - tx) * decode[code(xa, y1)] + tx * decode[code(xb, y1)];
    return static_cast<float>((1 - ty) * top + ty * bottom);
}

std::uint8_t GeoGrid::nearest(double lat, double lon) const {
    const int x = wrapX(static_cast<int>(std::floor(px(lon) + 0.5)), width);
    const int y = std::clamp(static_cast<int>(std::floor(py(lat) + 0.5)), 0, height - 1);
    return code(x, y);
}

float GeoGrid::boxMean(double south, double west, double north, double east) const {
    const int xa = static_cast<int>(std::ceil(px(west))), xb = static_cast<int>(std::floor(px(east)));
    const int ya = std::max(static_cast<int>(std::ceil(py(north))), 0);
    const int yb = std::min(static_cast<int>(std::floor(py(south))), height - 1);
    double sum = 0;
    int n = 0;
    for (int y = ya; y <= yb; ++y) {
        for (int x = xa; x <= xb; ++x) {
            sum += decode[code(wrapX(x, width), y)];
            ++n;
        }
    }
    if (n == 0) return decode[nearest(0.5 * (south + north), 0.5 * (west + east))];
    return static_cast<float>(sum / n);
}

std::array<float, 256> piecewiseDecode(const std::vector<std::pair<float, float>>& anchors) {
    std::array<float, 256> t{};
    for (int c = 0; c < 256; ++c) {
        const float p = static_cast<float>(c) / 255.0f;
        if (p <= anchors.front().first) {
            t[static_cast<std::size_t>(c)] = anchors.front().second;
            continue;
        }
        t[static_cast<std::size_t>(c)] = anchors.back().second;
        for (std::size_t i = 1; i < anchors.size(); ++i) {
            if (p <= anchors[i].first) {
                const auto [p0, v0] = anchors[i - 1];
                const auto [p1, v1] = anchors[i];
                t[static_cast<std::size_t>(c)] = v0 + (v1 - v0) * (p - p0) / (p1 - p0);
                break;
            }
        }
    }
    return t;
}

std::array<float, 256> temperatureDecode() { return piecewiseDecode({{0.0f, -69.0f}, {1.0f, 42.0f}}); }

std::array<float, 256> precipitationDecode() {
    // precipcolors.leg stops with the precip-*.dgml legend labels; above 0.93 ("1024 mm or more")
    // the scale is continued to 2048 mm at 1.
    return piecewiseDecode({{0.00f, 0.0f},
                            {0.04f, 10.0f},
                            {0.16f, 40.0f},
                            {0.25f, 63.0f},
                            {0.35f, 89.0f},
                            {0.50f, 127.0f},
                            {0.75f, 256.0f},
                            {0.87f, 512.0f},
                            {0.93f, 1024.0f},
                            {1.00f, 2048.0f}});
}

std::array<float, 256> elevationDecode() {
    // seacolors.leg (below 0.38) and landcolors.leg (from 0.38) stops with the srtm.dgml legend.
    return piecewiseDecode({{0.00f, -11000.0f},
                            {0.07f, -6500.0f},
                            {0.14f, -4000.0f},
                            {0.21f, -2000.0f},
                            {0.28f, -200.0f},
                            {0.31f, -50.0f},
                            {0.38f, 0.0f},
                            {0.45f, 50.0f},
                            {0.52f, 200.0f},
                            {0.59f, 500.0f},
                            {0.70f, 1000.0f},
                            {0.77f, 2000.0f},
                            {0.83f, 3500.0f},
                            {0.90f, 5000.0f},
                            {0.95f, 7000.0f},
                            {1.00f, 9000.0f}});
}

}  // namespace navmap::map::ortho
