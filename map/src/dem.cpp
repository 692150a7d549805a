// SPDX-License-Identifier: Apache-2.0
#include "navmap/map/dem.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <fstream>
#include <limits>
#include <regex>
#include <string>
#include <system_error>

#include "navmap/common/untrusted_file.h"

namespace navmap::map {

namespace {

constexpr std::int16_t kSrtmVoid = -32768;

struct TileCorner {
    int lat;
    int lon;
};

TileCorner parseHgtName(const std::filesystem::path& path) {
    static const std::regex kName(R"(([NS])(\d{2})([EW])(\d{3}))", std::regex::icase);
    std::smatch m;
    const std::string stem = path.stem().string();
    if (!std::regex_search(stem, m, kName)) {
        throw DemError(path.string() + ": not an SRTM tile name (expected e.g. N42E001.hgt)");
    }
    int lat = std::stoi(m[2].str());
    int lon = std::stoi(m[4].str());
    if (std::toupper(m[1].str()[0]) == 'S') lat = -lat;
    if (std::toupper(m[3].str()[0]) == 'W') lon = -lon;
    return {lat, lon};
}

// An SRTM3 or SRTM1 tile: at most 3601 x 3601 big-endian int16 samples (25.9 MB).
constexpr FileKind kHgtFile{"DEM file", std::uint64_t{3601} * 3601 * 2};

// Regular files only, opened without blocking (a FIFO or a device is refused, named), no longer
// than an SRTM1 tile, read no further than that (docs/architecture.md "Untrusted files").
UntrustedFile openHgt(const std::filesystem::path& path) {
    (void)parseHgtName(path);  // the name first: a wrong one says so, whatever the file is
    UntrustedFile file = UntrustedFile::open(path, kHgtFile);
    if (!file.ok()) throw DemError(file.error());
    return file;
}

// The grid the name and the size give; any other size than SRTM3's or SRTM1's is an error.
HgtShape hgtShape(const std::filesystem::path& path, std::uint64_t bytes) {
    const TileCorner corner = parseHgtName(path);
    int side = 0;
    if (bytes == 1201u * 1201u * 2u)
        side = 1201;
    else if (bytes == kHgtFile.max_bytes)
        side = 3601;
    else {
        throw DemError(path.string() + ": " + std::to_string(bytes) +
                       " bytes is not an SRTM tile (expected 1201x1201 or 3601x3601 int16 samples)");
    }
    return {side, corner.lat + 1.0, static_cast<double>(corner.lon), 1.0 / (side - 1)};
}

}  // namespace

float Dem::sample(double lat, double lon) const {
    const double fr = std::clamp((north - lat) / spacing, 0.0, static_cast<double>(rows - 1));
    const double fc = std::clamp((lon - west) / spacing, 0.0, static_cast<double>(cols - 1));
    const int r0 = std::min(static_cast<int>(fr), rows - 2);
    const int c0 = std::min(static_cast<int>(fc), cols - 2);
    const double tr = fr - r0;
    const double tc = fc - c0;
    const double top = at(r0, c0) * (1 - tc) + at(r0, c0 + 1) * tc;
    const double bottom = at(r0 + 1, c0) * (1 - tc) + at(r0 + 1, c0 + 1) * tc;
    return static_cast<float>(top * (1 - tr) + bottom * tr);
}

HgtShape probeHgt(const std::filesystem::path& path) {
    const UntrustedFile file = openHgt(path);
    return hgtShape(path, file.size());
}

Dem loadHgt(const std::filesystem::path& path) {
    UntrustedFile file = openHgt(path);
    const HgtShape shape = hgtShape(path, file.size());
    const int side = shape.side;
    const std::size_t bytes = static_cast<std::size_t>(side) * side * 2u;
    std::vector<unsigned char> raw;
    if (!file.readAll(raw)) throw DemError(file.error());
    if (raw.size() != bytes) {
        throw DemError(path.string() + ": " + std::to_string(raw.size()) + " bytes read of " + std::to_string(bytes) +
                       " (the file changed while being read)");
    }
    Dem dem;
    dem.rows = dem.cols = side;
    dem.spacing = shape.spacing;
    dem.north = shape.north;
    dem.west = shape.west;
    dem.heights.resize(static_cast<std::size_t>(side) * side);
    for (std::size_t i = 0; i < dem.heights.size(); ++i) {
        const auto v = static_cast<std::int16_t>((raw[2 * i] << 8) | raw[2 * i + 1]);
        if (v == kSrtmVoid) {
            dem.heights[i] = std::numeric_limits<float>::quiet_NaN();
            ++dem.void_count;
        } else {
            dem.heights[i] = v;
        }
    }
    return dem;
}

std::size_t fillVoids(Dem& dem) {
    struct Level {
        int rows, cols;
        std::vector<float> value;   // valid-weighted mean
        std::vector<float> weight;  // 0 where nothing valid below
    };
    std::size_t missing = 0;
    Level base{dem.rows, dem.cols, dem.heights, std::vector<float>(dem.heights.size(), 1.0f)};
    for (std::size_t i = 0; i < base.value.size(); ++i) {
        if (std::isnan(base.value[i])) {
            base.value[i] = 0.0f;
            base.weight[i] = 0.0f;
            ++missing;
        }
    }
    if (missing == 0 || missing == base.value.size()) return 0;

    // Push: halve until a level has no empty cell (or is 1x1).
    std::vector<Level> pyramid{std::move(base)};
    auto has_holes = [](const Level& l) {
        return std::any_of(l.weight.begin(), l.weight.end(), [](float w) { return w == 0.0f; });
    };
    while (has_holes(pyramid.back()) && (pyramid.back().rows > 1 || pyramid.back().cols > 1)) {
        const Level& fine = pyramid.back();
        Level coarse{(fine.rows + 1) / 2, (fine.cols + 1) / 2, {}, {}};
        coarse.value.assign(static_cast<std::size_t>(coarse.rows) * coarse.cols, 0.0f);
        coarse.weight.assign(coarse.value.size(), 0.0f);
        for (int r = 0; r < fine.rows; ++r) {
            for (int c = 0; c < fine.cols; ++c) {
                const std::size_t fi = static_cast<std::size_t>(r) * fine.cols + c;
                const std::size_t ci = static_cast<std::size_t>(r / 2) * coarse.cols + c / 2;
                coarse.value[ci] += fine.value[fi] * fine.weight[fi];
                coarse.weight[ci] += fine.weight[fi];
            }
        }
        for (std::size_t i = 0; i < coarse.value.size(); ++i) {
            if (coarse.weight[i] > 0) {
                coarse.value[i] /= coarse.weight[i];
                coarse.weight[i] = 1.0f;
            }
        }
        pyramid.push_back(std::move(coarse));
    }
    // Pull: fill each hole of a finer level from the bilinear interpolation of the coarser one.
    for (std::size_t li = pyramid.size() - 1; li-- > 0;) {
        Level& fine = pyramid[li];
        const Level& coarse = pyramid[li + 1];
        for (int r = 0; r < fine.rows; ++r) {
            for (int c = 0; c < fine.cols; ++c) {
                const std::size_t fi = static_cast<std::size_t>(r) * fine.cols + c;
                if (fine.weight[fi] > 0) continue;
                const double cr = std::clamp((r - 0.5) / 2.0, 0.0, coarse.rows - 1.0);
                const double cc = std::clamp((c - 0.5) / 2.0, 0.0, coarse.cols - 1.0);
                const int r0 = static_cast<int>(cr), c0 = static_cast<int>(cc);
                const int r1 = std::min(r0 + 1, coarse.rows - 1), c1 = std::min(c0 + 1, coarse.cols - 1);
                const double tr = cr - r0, tc = cc - c0;
                auto cv = [&](int rr, int ccol) {
                    return coarse.value[static_cast<std::size_t>(rr) * coarse.cols + ccol];
                };
                fine.value[fi] = static_cast<float>((cv(r0, c0) * (1 - tc) + cv(r0, c1) * tc) * (1 - tr) +
                                                    (cv(r1, c0) * (1 - tc) + cv(r1, c1) * tc) * tr);
                fine.weight[fi] = 1.0f;
            }
        }
    }
    dem.heights = std::move(pyramid.front().value);
    return missing;
}

Dem crop(const Dem& dem, double south, double west, double north, double east) {
    const int r0 = std::clamp(static_cast<int>(std::floor((dem.north - north) / dem.spacing)), 0, dem.rows - 1);
    const int r1 = std::clamp(static_cast<int>(std::ceil((dem.north - south) / dem.spacing)), 0, dem.rows - 1);
    const int c0 = std::clamp(static_cast<int>(std::floor((west - dem.west) / dem.spacing)), 0, dem.cols - 1);
    const int c1 = std::clamp(static_cast<int>(std::ceil((east - dem.west) / dem.spacing)), 0, dem.cols - 1);
    Dem out;
    out.rows = r1 - r0 + 1;
    out.cols = c1 - c0 + 1;
    out.spacing = dem.spacing;
    out.north = dem.north - r0 * dem.spacing;
    out.west = dem.west + c0 * dem.spacing;
    out.heights.reserve(static_cast<std::size_t>(out.rows) * out.cols);
    for (int r = r0; r <= r1; ++r) {
        for (int c = c0; c <= c1; ++c) {
            const float h = dem.at(r, c);
            out.heights.push_back(h);
            if (std::isnan(h)) ++out.void_count;
        }
    }
    return out;
}

}  // namespace navmap::map
