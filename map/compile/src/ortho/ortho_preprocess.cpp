// SPDX-License-Identifier: Apache-2.0
#include "navmap/map/compile/ortho/ortho_preprocess.h"
#include "navmap/map/feature_classes.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <numeric>

#include "navmap/map/ortho/super_land_cover.h"

namespace navmap::map::ortho {

void rasterizeAreas(const Tile& tile, int n, std::vector<std::uint8_t>& cover) {
    cover.assign(static_cast<std::size_t>(n) * n, 0);
    std::vector<const Area*> areas;
    for (const auto& a : tile.areas) areas.push_back(&a);
    std::stable_sort(areas.begin(), areas.end(),
                     [](const Area* a, const Area* b) { return areaDrawOrder(a->cls) < areaDrawOrder(b->cls); });
    const double texel = tile.size_m / n;
    for (const Area* a : areas) {
        if (areaIsTint(a->cls)) continue;  // a tint over what lies under it, no cover of its own
        const auto value = static_cast<std::uint8_t>(static_cast<int>(fromArea(a->cls)) + 1);
        const auto& v = a->polygon.vertices;
        const auto& idx = a->polygon.indices;
        for (std::size_t t = 0; t + 2 < idx.size(); t += 3) {
            if (idx[t] >= v.size() || idx[t + 1] >= v.size() || idx[t + 2] >= v.size()) continue;
            // Texel-centre coordinates: texel (r, c) is centred at (c, r).
            const double ax = v[idx[t]].x / texel - 0.5, ay = v[idx[t]].y / texel - 0.5;
            const double bx = v[idx[t + 1]].x / texel - 0.5, by = v[idx[t + 1]].y / texel - 0.5;
            const double cx = v[idx[t + 2]].x / texel - 0.5, cy = v[idx[t + 2]].y / texel - 0.5;
            const double area2 = (bx - ax) * (cy - ay) - (by - ay) * (cx - ax);
            if (area2 == 0.0) continue;
            const double s = area2 > 0 ? 1.0 : -1.0;  // either winding
            const int c0 = std::max(static_cast<int>(std::ceil(std::min({ax, bx, cx}))), 0);
            const int c1 = std::min(static_cast<int>(std::floor(std::max({ax, bx, cx}))), n - 1);
            const int r0 = std::max(static_cast<int>(std::ceil(std::min({ay, by, cy}))), 0);
            const int r1 = std::min(static_cast<int>(std::floor(std::max({ay, by, cy}))), n - 1);
            for (int r = r0; r <= r1; ++r) {
                for (int c = c0; c <= c1; ++c) {
                    const double e0 = s * ((bx - ax) * (r - ay) - (by - ay) * (c - ax));
                    const double e1 = s * ((cx - bx) * (r - by) - (cy - by) * (c - bx));
                    const double e2 = s * ((ax - cx) * (r - cy) - (ay - cy) * (c - cx));
                    if (e0 >= 0 && e1 >= 0 && e2 >= 0) cover[static_cast<std::size_t>(r) * n + c] = value;
                }
            }
        }
    }
}

OrthoLayers sampleOrthoLayers(const Tile& tile, const GlobalInputs& in, const Projection& proj, int nc, int ng) {
    OrthoLayers o;
    o.cover_size = static_cast<std::uint16_t>(nc);
    o.grid_size = static_cast<std::uint16_t>(ng);
    // Texel positions are interpolated from the corners' latitude and longitude, as the DEM
    // grid's are (docs/tile-store.md), so neighbouring tiles sample their shared border alike.
    double lat[4], lon[4];  // SW, SE, NW, NE
    const double x0 = tile.origin_x, y0 = tile.origin_y, x1 = x0 + tile.size_m, y1 = y0 + tile.size_m;
    proj.reverse({x0, y0}, lat[0], lon[0]);
    proj.reverse({x1, y0}, lat[1], lon[1]);
    proj.reverse({x0, y1}, lat[2], lon[2]);
    proj.reverse({x1, y1}, lat[3], lon[3]);
    auto latlon = [&](double u, double v, double& la, double& lo) {
        la = (1 - u) * (1 - v) * lat[0] + u * (1 - v) * lat[1] + (1 - u) * v * lat[2] + u * v * lat[3];
        lo = (1 - u) * (1 - v) * lon[0] + u * (1 - v) * lon[1] + (1 - u) * v * lon[2] + u * v * lon[3];
    };

    // Super land cover: the OSM areas where they lie, else Natural Earth on a window over the
    // tile at 1.5 times the texel density.
    std::vector<std::uint8_t> osm;
    rasterizeAreas(tile, nc, osm);
    GeoWindow w;
    w.south = *std::min_element(lat, lat + 4);
    w.north = *std::max_element(lat, lat + 4);
    w.west = *std::min_element(lon, lon + 4);
    w.east = *std::max_element(lon, lon + 4);
    w.width = w.height = nc * 3 / 2;
    const std::vector<std::uint8_t> ne =
        in.cover.empty() ? std::vector<std::uint8_t>(std::size_t(w.width) * w.height, 1) : in.cover.rasterize(w);
    o.cover.resize(static_cast<std::size_t>(nc) * nc);
    for (int r = 0; r < nc; ++r) {
        for (int c = 0; c < nc; ++c) {
            const auto i = static_cast<std::size_t>(r) * nc + c;
            if (osm[i] != 0) {
                o.cover[i] = static_cast<std::uint8_t>(osm[i] - 1);
                continue;
            }
            double la = 0, lo = 0;
            latlon((c + 0.5) / nc, (r + 0.5) / nc, la, lo);
            const int wc = std::clamp(static_cast<int>((lo - w.west) / (w.east - w.west) * w.width), 0, w.width - 1);
            const int wr =
                std::clamp(static_cast<int>((w.north - la) / (w.north - w.south) * w.height), 0, w.height - 1);
            o.cover[i] = static_cast<std::uint8_t>(
                fromGlobal(static_cast<GlobalCover>(ne[static_cast<std::size_t>(wr) * w.width + wc])));
        }
    }

    // Grid layers.
    const std::size_t n2 = static_cast<std::size_t>(ng) * ng;
    for (auto* layer :
         {&o.climate, &o.temp_dec, &o.temp_jul, &o.precip_dec, &o.precip_jul, &o.lights, &o.slope, &o.aspect}) {
        layer->resize(n2);
    }
    o.elevation.resize(n2);
    const TileDem& dem = tile.dem;
    const double spacing = tile.size_m / (ng - 1);
    auto dem_at = [&](double x, double y, float& h) {
        if (dem.size < 2) return false;
        const double ds = tile.size_m / (dem.size - 1);
        const int last = dem.size - 1;
        const double gx = std::clamp(x / ds, 0.0, double(last)), gy = std::clamp(y / ds, 0.0, double(last));
        const int c = std::min(static_cast<int>(gx), last - 1), r = std::min(static_cast<int>(gy), last - 1);
        const double tx = gx - c, ty = gy - r;
        const float a = dem.at(r, c), b = dem.at(r, c + 1), d = dem.at(r + 1, c), e = dem.at(r + 1, c + 1);
        // A missing DEM sample is 0 m in the store: only a fully covered tile, or a cell whose
        // samples are all set, is taken from the region's DEM.
        if (dem.coverage < 1.0f && (a == 0.0f || b == 0.0f || d == 0.0f || e == 0.0f)) return false;
        h = static_cast<float>((1 - tx) * (1 - ty) * a + tx * (1 - ty) * b + (1 - tx) * ty * d + tx * ty * e);
        return true;
    };
    for (int r = 0; r < ng; ++r) {
        for (int c = 0; c < ng; ++c) {
            const auto i = static_cast<std::size_t>(r) * ng + c;
            double la = 0, lo = 0;
            latlon(static_cast<double>(c) / (ng - 1), static_cast<double>(r) / (ng - 1), la, lo);
            o.climate[i] = in.climate.empty() ? 0 : static_cast<std::uint8_t>(in.climate.nearest(la, lo));
            o.temp_dec[i] = temperatureCode(in.temp_dec.bilinear(la, lo));
            o.temp_jul[i] = temperatureCode(in.temp_jul.bilinear(la, lo));
            o.precip_dec[i] = precipitationCode(in.precip_dec.bilinear(la, lo));
            o.precip_jul[i] = precipitationCode(in.precip_jul.bilinear(la, lo));
            o.lights[i] =
                static_cast<std::uint8_t>(std::clamp(std::lround(in.lights.bilinear(la, lo) * 255.0f), 0L, 255L));
            float h = 0;
            if (!dem_at(c * spacing, r * spacing, h)) h = in.elevation.empty() ? 0.0f : in.elevation.bilinear(la, lo);
            o.elevation[i] = static_cast<std::int16_t>(std::clamp(std::lround(h), -32768L, 32767L));
        }
    }
    // Slope and aspect of the elevation grid (central differences, one-sided at the border).
    for (int r = 0; r < ng; ++r) {
        for (int c = 0; c < ng; ++c) {
            const int c0 = std::max(c - 1, 0), c1 = std::min(c + 1, ng - 1), r0 = std::max(r - 1, 0),
                      r1 = std::min(r + 1, ng - 1);
            auto e = [&](int rr, int cc) {
                return static_cast<double>(o.elevation[static_cast<std::size_t>(rr) * ng + cc]);
            };
            const double dzdx = (e(r, c1) - e(r, c0)) / ((c1 - c0) * spacing);
            const double dzdy = (e(r1, c) - e(r0, c)) / ((r1 - r0) * spacing);
            const auto i = static_cast<std::size_t>(r) * ng + c;
            const double g = std::hypot(dzdx, dzdy);
            o.slope[i] = static_cast<std::uint8_t>(std::lround(std::atan(g) * 180.0 / std::numbers::pi));
            double az =
                g > 0 ? std::atan2(-dzdx, -dzdy) * 180.0 / std::numbers::pi : 0.0;  // downhill, clockwise from north
            if (az < 0) az += 360.0;
            o.aspect[i] = static_cast<std::uint8_t>(std::lround(az * 256.0 / 360.0) % 256);
        }
    }
    return o;
}

}  // namespace navmap::map::ortho
