// SPDX-License-Identifier: Apache-2.0
#pragma once
// Reads the global inputs of the synthetic orthoimages from Debian's marble-qt-data
// (/usr/share/marble/data; licences in its .dgml files and /usr/share/doc/marble-qt-data/
// copyright) through OpenImageIO. Part of the separate library navmap_ortho_io, so that only
// the programs that read these images (navmap-compile, navmap-ortho-train, their tests) link
// OpenImageIO.
//
//   maps/earth/temp-dec, temp-july/*.jpg      mean air temperature, 2160x1080 grey (Legates, Willmott)
//   maps/earth/precip-dec, precip-july/*.jpg  precipitation, 2160x1080 grey (Legates, Willmott)
//   maps/earth/srtm/3/RRRRRR/RRRRRR_CCCCCC.jpg elevation and bathymetry, 16 x 8 tiles of 675^2 grey
//   maps/earth/citylights/citylights.jpg      Earth at night, 2700x1350 RGB
//   maps/earth/bluemarble/bluemarble.jpg      NASA Blue Marble Next Generation, 2700x1350 RGB (target)
//   naturalearth/ne_50m_*.pn2                 Natural Earth 1:50m polygons (natural_earth.h)

#include <array>
#include <filesystem>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "navmap/map/compile/ortho/global_inputs.h"

namespace navmap::map::ortho {

/// Raised when an input cannot be used; the message names the file and the problem
/// ("temp-dec.jpg: 2160x1000 is not a global raster (the width must be twice the height)").
class OrthoInputError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

/// Where Debian installs marble-qt-data.
inline const std::filesystem::path kDebianMarbleData = "/usr/share/marble/data";

struct MarbleInputOptions {
    /// Decode only the SRTM tiles over this box (south, west, north, east, degrees); the rest
    /// of the elevation grid reads 0 m. Empty: the whole globe.
    std::optional<std::array<double, 4>> bounds;
};

/// Reads every input but Blue Marble and builds the climate grid; throws OrthoInputError (or
/// Pn2Error for the polygons).
GlobalInputs loadGlobalInputs(const std::filesystem::path& marble_data, const MarbleInputOptions& options = {});

/// An RGB raster on the same pixel grid convention as GeoGrid.
struct RgbGrid {
    int width = 0, height = 0;
    std::vector<std::uint8_t> rgb;
    [[nodiscard]] std::array<float, 3> at(int x, int y) const {
        const std::size_t i = (static_cast<std::size_t>(y) * width + x) * 3;
        return {rgb[i] / 255.0f, rgb[i + 1] / 255.0f, rgb[i + 2] / 255.0f};
    }
};
/// The training target, maps/earth/bluemarble/bluemarble.jpg.
RgbGrid loadBlueMarble(const std::filesystem::path& marble_data);

/// Reads one global raster (width = 2 x height) channel 0, or all three with `rgb`; throws
/// OrthoInputError naming the file.
std::vector<std::uint8_t> readGlobalRaster(const std::filesystem::path& file, int channels, int& width, int& height);

}  // namespace navmap::map::ortho
