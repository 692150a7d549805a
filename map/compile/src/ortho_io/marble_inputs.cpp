// SPDX-License-Identifier: Apache-2.0
#include "navmap/map/compile/ortho/marble_inputs.h"

#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace navmap::map::ortho {

namespace {

namespace fs = std::filesystem;

std::string dims(int w, int h) { return std::to_string(w) + "x" + std::to_string(h); }

std::vector<std::uint8_t> readImage(const fs::path& file, int channels, int& width, int& height) {
    auto in = OIIO::ImageInput::open(file.string());
    if (!in) {
        std::string e = OIIO::geterror();
        if (!fs::exists(file)) e = "no such file (is marble-qt-data installed?)";
        throw OrthoInputError(file.string() + ": " + e);
    }
    const OIIO::ImageSpec& spec = in->spec();
    width = spec.width;
    height = spec.height;
    if (spec.nchannels < channels) {
        throw OrthoInputError(file.string() + ": " + std::to_string(spec.nchannels) + " channels, expected " +
                              std::to_string(channels));
    }
    std::vector<std::uint8_t> px(static_cast<std::size_t>(width) * height * channels);
    if (!in->read_image(0, 0, 0, channels, OIIO::TypeDesc::UINT8, px.data())) {
        throw OrthoInputError(file.string() + ": " + in->geterror());
    }
    return px;
}

GeoGrid globalGrey(const fs::path& file, const std::array<float, 256>& decode) {
    GeoGrid g;
    g.name = file.filename().string();
    g.codes = readGlobalRaster(file, 1, g.width, g.height);
    g.decode = decode;
    return g;
}

}  // namespace

std::vector<std::uint8_t> readGlobalRaster(const fs::path& file, int channels, int& width, int& height) {
    std::vector<std::uint8_t> px = readImage(file, channels, width, height);
    if (width != 2 * height || height < 2) {
        throw OrthoInputError(file.string() + ": " + dims(width, height) +
                              " is not a global raster (the width must be twice the height)");
    }
    return px;
}

GlobalInputs loadGlobalInputs(const fs::path& dir, const MarbleInputOptions& options) {
    const fs::path earth = dir / "maps" / "earth";
    GlobalInputs in;
    in.temp_dec = globalGrey(earth / "temp-dec" / "temp-dec.jpg", temperatureDecode());
    in.temp_jul = globalGrey(earth / "temp-july" / "temp-july.jpg", temperatureDecode());
    in.precip_dec = globalGrey(earth / "precip-dec" / "precip-dec.jpg", precipitationDecode());
    in.precip_jul = globalGrey(earth / "precip-july" / "precip-july.jpg", precipitationDecode());
    for (const GeoGrid* g : {&in.temp_jul, &in.precip_dec, &in.precip_jul}) {
        if (g->width != in.temp_dec.width || g->height != in.temp_dec.height) {
            throw OrthoInputError(g->name + " is " + dims(g->width, g->height) + ", temp-dec.jpg " +
                                  dims(in.temp_dec.width, in.temp_dec.height) +
                                  ": the climate rasters must share one grid");
        }
    }

    // City lights: the night image's terrain is dark blue (R and G below about 48); lights are
    // what rises above that, 0..1.
    {
        int w = 0, h = 0;
        const fs::path file = earth / "citylights" / "citylights.jpg";
        const std::vector<std::uint8_t> rgb = readGlobalRaster(file, 3, w, h);
        in.lights.name = file.filename().string();
        in.lights.width = w;
        in.lights.height = h;
        in.lights.codes.resize(static_cast<std::size_t>(w) * h);
        for (std::size_t i = 0; i < in.lights.codes.size(); ++i) {
            const double v = (0.5 * (rgb[3 * i] + rgb[3 * i + 1]) - 48.0) / 207.0;
            in.lights.codes[i] = static_cast<std::uint8_t>(std::lround(std::clamp(v, 0.0, 1.0) * 255.0));
        }
        for (int c = 0; c < 256; ++c) in.lights.decode[static_cast<std::size_t>(c)] = static_cast<float>(c) / 255.0f;
    }

    // SRTM: level 3 of marble's tile pyramid, 16 x 8 tiles of 675 x 675 (2 arc minutes).
    {
        constexpr int kTile = 675, kCols = 16, kRows = 8;
        GeoGrid& g = in.elevation;
        g.name = "srtm/3";
        g.width = kTile * kCols;
        g.height = kTile * kRows;
        g.decode = elevationDecode();
        const auto sea_level = static_cast<std::uint8_t>(std::lround(0.38 * 255.0));  // 0 m
        g.codes.assign(static_cast<std::size_t>(g.width) * g.height, sea_level);
        for (int r = 0; r < kRows; ++r) {
            for (int c = 0; c < kCols; ++c) {
                if (options.bounds) {
                    const auto& [s, w, n, e] = *options.bounds;
                    const double tn = 90.0 - 180.0 * r / kRows, ts = 90.0 - 180.0 * (r + 1) / kRows;
                    const double tw = -180.0 + 360.0 * c / kCols, te = -180.0 + 360.0 * (c + 1) / kCols;
                    if (ts > n + 1 || tn < s - 1 || tw > e + 1 || te < w - 1) continue;  // a degree of margin
                }
                char name[64];
                std::snprintf(name, sizeof name, "%06d/%06d_%06d.jpg", r, r, c);
                const fs::path file = earth / "srtm" / "3" / name;
                int w = 0, h = 0;
                const std::vector<std::uint8_t> tile = readImage(file, 1, w, h);
                if (w != kTile || h != kTile) {
                    throw OrthoInputError(file.string() + ": " + dims(w, h) + ", expected " + dims(kTile, kTile) +
                                          " like every tile of marble's SRTM level 3");
                }
                for (int y = 0; y < kTile; ++y) {
                    std::copy_n(tile.data() + static_cast<std::size_t>(y) * kTile, kTile,
                                g.codes.data() + static_cast<std::size_t>(r * kTile + y) * g.width +
                                    static_cast<std::size_t>(c) * kTile);
                }
            }
        }
    }

    in.cover = NaturalEarthCover::load(dir);
    in.climate = buildClimateGrid(in.temp_dec, in.temp_jul, in.precip_dec, in.precip_jul, in.cover);
    return in;
}

RgbGrid loadBlueMarble(const fs::path& dir) {
    RgbGrid g;
    g.rgb = readGlobalRaster(dir / "maps" / "earth" / "bluemarble" / "bluemarble.jpg", 3, g.width, g.height);
    return g;
}

}  // namespace navmap::map::ortho
