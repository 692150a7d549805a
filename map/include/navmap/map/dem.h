// SPDX-License-Identifier: Apache-2.0
#pragma once
// Digital elevation models: SRTM .hgt tiles and the void filling every consumer relies on.

#include <cstddef>
#include <filesystem>
#include <stdexcept>
#include <vector>

namespace navmap::map {

/// Raised when a DEM file cannot be used; the message names the file and the problem.
class DemError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

/// A regular lat/lon grid of heights in metres. Row 0 is the north edge, column 0 the west
/// edge; samples sit on grid points (SRTM convention). Voids are NaN until filled.
struct Dem {
    int rows = 0;
    int cols = 0;
    double north = 0.0;          ///< latitude of row 0, degrees
    double west = 0.0;           ///< longitude of column 0, degrees
    double spacing = 0.0;        ///< grid spacing in degrees (same in lat and lon for SRTM)
    std::vector<float> heights;  ///< rows * cols, row-major
    std::size_t void_count = 0;  ///< samples that were -32768 in the source

    [[nodiscard]] float at(int row, int col) const { return heights[static_cast<std::size_t>(row) * cols + col]; }
    [[nodiscard]] double south() const { return north - spacing * (rows - 1); }
    [[nodiscard]] double east() const { return west + spacing * (cols - 1); }
    /// Bilinear height at a geographic position; positions outside the grid clamp to its edge.
    [[nodiscard]] float sample(double lat, double lon) const;
};

/// An SRTM .hgt file's grid as its name and size give it, checked as loadHgt checks them (DemError
/// naming the file), without reading its samples.
struct HgtShape {
    int side = 0;  ///< samples per side: 1201 or 3601
    double north = 0.0;
    double west = 0.0;
    double spacing = 0.0;
};
HgtShape probeHgt(const std::filesystem::path& path);

/// Reads an SRTM .hgt tile (1201x1201 SRTM3 or 3601x3601 SRTM1, big-endian int16). The tile's
/// south-west corner comes from the file name (e.g. N42E001.hgt). Voids (-32768) become NaN and
/// are counted. Throws DemError naming the file on a bad size or name.
Dem loadHgt(const std::filesystem::path& path);

/// Fills NaN samples from their valid surroundings with a push-pull pyramid (valid-weighted
/// averages going down, interpolation coming back up), so voids become smooth surfaces that
/// join their rims instead of pits. Returns the number of samples filled.
std::size_t fillVoids(Dem& dem);

/// Cuts the part of the grid covering [south, north] x [west, east] (degrees), snapped
/// outwards to whole samples.
Dem crop(const Dem& dem, double south, double west, double north, double east);

}  // namespace navmap::map
