// SPDX-License-Identifier: Apache-2.0
#include "navmap/map/world_tiles.h"

#include <GeographicLib/Constants.hpp>
#include <GeographicLib/Math.hpp>
#include <algorithm>
#include <bit>
#include <charconv>
#include <cmath>
#include <numbers>

namespace navmap::map {
namespace {

using GeographicLib::Math;

// WGS84 (GeographicLib::Constants::WGS84_a and _f) as constant expressions: frames made before
// main() (a Projection held in a namespace-scope constant) must not see these uninitialised.
constexpr double kA = 6378137.0;
constexpr double kF = 1.0 / 298.257223563;
constexpr double kE = 0.081819190842621494;  // first eccentricity, sqrt(f (2 - f))
constexpr double kHalf = std::numbers::pi * kA;
static_assert(kE * kE > kF * (2.0 - kF) * (1.0 - 1e-15) && kE * kE < kF * (2.0 - kF) * (1.0 + 1e-15));

double wrapLon(double lon) { return lon - 360.0 * std::floor((lon + 180.0) / 360.0); }

}  // namespace

double worldHalfSize() { return kHalf; }

double worldLatitudeLimit() {
    static const double kLimit = [] {
        double lat = 0, lon = 0;
        fromWorldMercator({0.0, kHalf}, lat, lon);
        return lat;
    }();
    return kLimit;
}

MercatorPoint toWorldMercator(double lat_deg, double lon_deg) {
    // Y = a * asinh(tan chi), chi the conformal latitude (GeographicLib's taupf).
    const double taup = Math::taupf(Math::tand(std::clamp(lat_deg, -89.999999, 89.999999)), kE);
    return {kA * wrapLon(lon_deg) * Math::degree(), kA * std::asinh(taup)};
}

void fromWorldMercator(MercatorPoint m, double& lat_deg, double& lon_deg) {
    lat_deg = Math::atand(Math::tauf(std::sinh(m.y / kA), kE));
    lon_deg = wrapLon(m.x / kA / Math::degree());
}

double worldMercatorScale(double lat_deg) {
    const double s = Math::sind(lat_deg);
    return std::sqrt(1.0 - kE * kE * s * s) / Math::cosd(lat_deg);
}

bool WorldTileId::valid() const {
    if (z < 0 || z > kMaxWorldZoom) return false;
    const std::uint64_t n = std::uint64_t{1} << z;
    return x < n && y < n;
}

std::uint64_t WorldTileId::key() const {
    std::uint64_t k = 1;
    for (int i = z - 1; i >= 0; --i) k = (k << 2) | (((y >> i) & 1u) << 1) | ((x >> i) & 1u);
    return k;
}

std::optional<WorldTileId> WorldTileId::fromKey(std::uint64_t key) {
    if (key == 0) return std::nullopt;
    const int top = 63 - std::countl_zero(key);  // the marker bit
    if (top % 2 != 0 || top / 2 > kMaxWorldZoom) return std::nullopt;
    WorldTileId id{top / 2, 0, 0};
    for (int i = id.z - 1; i >= 0; --i) {
        const auto d = static_cast<std::uint32_t>((key >> (2 * i)) & 3u);
        id.x = (id.x << 1) | (d & 1u);
        id.y = (id.y << 1) | (d >> 1);
    }
    return id;
}

std::string WorldTileId::toString() const {
    return std::to_string(z) + "/" + std::to_string(x) + "/" + std::to_string(y);
}

std::optional<WorldTileId> WorldTileId::parse(std::string_view text) {
    WorldTileId id;
    const char* p = text.data();
    const char* end = text.data() + text.size();
    auto number = [&](auto& out, bool last) {
        const auto r = std::from_chars(p, end, out);
        if (r.ec != std::errc{} || r.ptr == p) return false;
        p = r.ptr;
        if (last) return p == end;
        if (p == end || *p != '/') return false;
        ++p;
        return true;
    };
    if (!number(id.z, false) || !number(id.x, false) || !number(id.y, true) || !id.valid()) return std::nullopt;
    return id;
}

WorldTileId WorldTileId::parent() const { return z == 0 ? *this : WorldTileId{z - 1, x / 2, y / 2}; }

WorldTileId WorldTileId::child(int which) const {
    return {z + 1, 2 * x + static_cast<std::uint32_t>(which & 1), 2 * y + static_cast<std::uint32_t>((which >> 1) & 1)};
}

bool WorldTileId::contains(const WorldTileId& d) const {
    if (d.z < z) return false;
    const int shift = d.z - z;
    return (d.x >> shift) == x && (d.y >> shift) == y;
}

std::optional<WorldTileId> WorldTileId::neighbour(int dx, int dy) const {
    const std::int64_t n = std::int64_t{1} << z;
    const std::int64_t ny = std::int64_t{y} + dy;
    if (ny < 0 || ny >= n) return std::nullopt;
    std::int64_t nx = (std::int64_t{x} + dx) % n;
    if (nx < 0) nx += n;
    return WorldTileId{z, static_cast<std::uint32_t>(nx), static_cast<std::uint32_t>(ny)};
}

double WorldTileId::size() const { return std::ldexp(2.0 * kHalf, -z); }

MercatorPoint WorldTileId::southWest() const { return {-kHalf + x * size(), -kHalf + y * size()}; }

MercatorPoint WorldTileId::centre() const {
    const MercatorPoint sw = southWest();
    return {sw.x + 0.5 * size(), sw.y + 0.5 * size()};
}

WorldTileId worldTileAt(int z, MercatorPoint m) {
    z = std::clamp(z, 0, kMaxWorldZoom);
    const double n = std::ldexp(1.0, z);
    auto index = [&](double v) {
        return static_cast<std::uint32_t>(std::clamp(std::floor((v + kHalf) / (2.0 * kHalf) * n), 0.0, n - 1.0));
    };
    return {z, index(m.x), index(m.y)};
}

WorldTileId worldTileAt(int z, double lat_deg, double lon_deg) {
    return worldTileAt(z, toWorldMercator(lat_deg, lon_deg));
}

WorldTileId worldTileCovering(double south, double west, double north, double east, int max_z) {
    const MercatorPoint sw = toWorldMercator(south, west);
    // The east edge is inside the box: a box ending at 180 E stays in the last column.
    MercatorPoint ne = toWorldMercator(north, east);
    if (east >= 180.0 || ne.x < sw.x) ne.x = kHalf * (1.0 - 1e-15);
    for (int z = std::clamp(max_z, 0, kMaxWorldZoom); z > 0; --z) {
        const WorldTileId a = worldTileAt(z, sw), b = worldTileAt(z, ne);
        if (a == b) return a;
    }
    return {};
}

int worldZoomForGroundSize(double size_m, double lat_deg) {
    const double ground_world = 2.0 * kHalf / worldMercatorScale(lat_deg);
    const double z = std::round(std::log2(ground_world / std::max(size_m, 1e-3)));
    return static_cast<int>(std::clamp(z, 0.0, static_cast<double>(kMaxWorldZoom)));
}

}  // namespace navmap::map
