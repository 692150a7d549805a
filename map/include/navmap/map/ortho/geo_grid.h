// SPDX-License-Identifier: Apache-2.0
#pragma once
// Global equirectangular rasters of 8-bit codes with a table that decodes them to physical units
// (degrees Celsius, millimetres, metres): the form in which marble-qt-data ships its global
// layers (seed 6.4). Pixel (x, y) is centred on lon = -180 + (x + 0.5) * 360 / width,
// lat = 90 - (y + 0.5) * 180 / height; row 0 is the north.

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace navmap::map::ortho {

struct GeoGrid {
    std::string name;  ///< the source, for messages
    int width = 0;
    int height = 0;
    std::vector<std::uint8_t> codes;  ///< width * height, row-major
    std::array<float, 256> decode{};  ///< code -> physical value

    [[nodiscard]] bool empty() const { return codes.empty(); }
    [[nodiscard]] std::uint8_t code(int x, int y) const { return codes[static_cast<std::size_t>(y) * width + x]; }
    /// Continuous pixel coordinates of a position (x wraps around the globe; y clamps at the poles).
    [[nodiscard]] double px(double lon) const { return (lon + 180.0) / 360.0 * width - 0.5; }
    [[nodiscard]] double py(double lat) const { return (90.0 - lat) / 180.0 * height - 0.5; }
    /// Bilinear interpolation of the decoded values.
    [[nodiscard]] float bilinear(double lat, double lon) const;
    /// Code of the pixel holding the position.
    [[nodiscard]] std::uint8_t nearest(double lat, double lon) const;
    /// Mean decoded value over the box [south, north] x [west, east] (pixels whose centre lies
    /// inside; the nearest pixel when none does).
    [[nodiscard]] float boxMean(double south, double west, double north, double east) const;
};

/// Piecewise-linear decode table through (code position in [0, 1], value) anchors, sorted by
/// position; codes outside the anchors clamp.
std::array<float, 256> piecewiseDecode(const std::vector<std::pair<float, float>>& anchors);

/// The decode tables of the marble-qt-data layers, derived from their legends (the .dgml legend
/// items and the .leg colour stops; docs/orthoimage.md "Inputs"):
/// temperature: linear from -69 C (code 0) to 42 C (code 255), the legend's end points;
std::array<float, 256> temperatureDecode();
/// precipitation: mm per month at the stops of precipcolors.leg (0 at 0, 10 at 0.04, ... 1024 at 0.93);
std::array<float, 256> precipitationDecode();
/// elevation: metres at the stops of seacolors.leg and landcolors.leg (-11000 at 0, 0 at 0.38,
/// 7000 at 0.95, 9000 at 1).
std::array<float, 256> elevationDecode();

}  // namespace navmap::map::ortho
