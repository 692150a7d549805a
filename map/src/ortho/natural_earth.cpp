// SPDX-License-Identifier: Apache-2.0
#include "navmap/map/ortho/natural_earth.h"

#include <algorithm>
#include <cmath>

namespace navmap::map::ortho {

const char* globalCoverName(GlobalCover c) {
    switch (c) {
        case GlobalCover::Ocean: return "ocean";
        case GlobalCover::Land: return "land";
        case GlobalCover::Lake: return "lake";
        case GlobalCover::Glacier: return "glacier";
        case GlobalCover::IceShelf: return "ice shelf";
        case GlobalCover::Urban: return "urban";
        case GlobalCover::Playa: return "playa";
    }
    return "?";
}

PolygonLayer::PolygonLayer(const std::vector<Pn2Polygon>& polygons) {
    const auto bands = static_cast<std::size_t>(std::lround(180.0 / kBandDeg));
    m_bands.resize(bands);
    auto ring = [&](const std::vector<GeoCoordinate>& pts) {
        for (std::size_t i = 0; i < pts.size(); ++i) {
            const GeoCoordinate a = pts[i], b = pts[(i + 1) % pts.size()];
            if (a.lat_deg == b.lat_deg) continue;  // never crosses a scanline under the half-open rule
            const auto index = static_cast<std::uint32_t>(m_edges.size());
            m_edges.push_back({a.lat_deg, a.lon_deg, b.lat_deg, b.lon_deg});
            const double lo = std::min(a.lat_deg, b.lat_deg), hi = std::max(a.lat_deg, b.lat_deg);
            const auto b0 = static_cast<std::size_t>(std::clamp((lo + 90.0) / kBandDeg, 0.0, double(bands - 1)));
            const auto b1 = static_cast<std::size_t>(std::clamp((hi + 90.0) / kBandDeg, 0.0, double(bands - 1)));
            for (std::size_t k = b0; k <= b1; ++k) m_bands[k].push_back(index);
        }
    };
    for (const auto& p : polygons) {
        if (p.outer.size() >= 3) ring(p.outer);
        for (const auto& h : p.holes) {
            if (h.size() >= 3) ring(h);
        }
    }
}

void PolygonLayer::paint(const GeoWindow& w, std::uint8_t value, std::vector<std::uint8_t>& out) const {
    if (m_bands.empty()) return;
    std::vector<double> crossings;
    const double dlon = (w.east - w.west) / w.width;
    for (int r = 0; r < w.height; ++r) {
        const double lat = w.lat(r);
        const auto band =
            static_cast<std::size_t>(std::clamp((lat + 90.0) / kBandDeg, 0.0, double(m_bands.size() - 1)));
        crossings.clear();
        for (std::uint32_t i : m_bands[band]) {
            const Edge& e = m_edges[i];
            // Half-open in latitude, so a vertex on the scanline counts once.
            if ((e.lat0 <= lat) == (e.lat1 <= lat)) continue;
            crossings.push_back(e.lon0 + (lat - e.lat0) * (e.lon1 - e.lon0) / (e.lat1 - e.lat0));
        }
        std::sort(crossings.begin(), crossings.end());
        std::uint8_t* row = out.data() + static_cast<std::size_t>(r) * w.width;
        for (std::size_t k = 0; k + 1 < crossings.size(); k += 2) {
            // Pixel centres within [crossings[k], crossings[k + 1]).
            const int c0 = std::max(static_cast<int>(std::ceil((crossings[k] - w.west) / dlon - 0.5)), 0);
            const int c1 = std::min(static_cast<int>(std::ceil((crossings[k + 1] - w.west) / dlon - 0.5)), w.width);
            for (int c = c0; c < c1; ++c) row[c] = value;
        }
    }
}

NaturalEarthCover NaturalEarthCover::load(const std::filesystem::path& dir) {
    const std::filesystem::path ne = dir / "naturalearth";
    const std::pair<GlobalCover, const char*> files[] = {
        {GlobalCover::Land, "ne_50m_land.pn2"},
        {GlobalCover::IceShelf, "ne_50m_antarctic_ice_shelves_polys.pn2"},
        {GlobalCover::Lake, "ne_50m_lakes.pn2"},
        {GlobalCover::Playa, "ne_50m_playas.pn2"},
        {GlobalCover::Glacier, "ne_50m_glaciated_areas.pn2"},
        {GlobalCover::Urban, "ne_50m_urban_areas.pn2"}};
    std::vector<std::pair<GlobalCover, PolygonLayer>> layers;
    for (const auto& [cls, file] : files) layers.emplace_back(cls, PolygonLayer(readPn2(ne / file).polygons));
    return NaturalEarthCover(std::move(layers));
}

std::vector<std::uint8_t> NaturalEarthCover::rasterize(const GeoWindow& window) const {
    std::vector<std::uint8_t> out(static_cast<std::size_t>(window.width) * window.height,
                                  static_cast<std::uint8_t>(GlobalCover::Ocean));
    for (const auto& [cls, layer] : m_layers) layer.paint(window, static_cast<std::uint8_t>(cls), out);
    return out;
}

}  // namespace navmap::map::ortho
