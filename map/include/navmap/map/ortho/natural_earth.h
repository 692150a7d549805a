// SPDX-License-Identifier: Apache-2.0
#pragma once
// The global land cover of the synthetic orthoimages: the Natural Earth 1:50m polygon layers of
// marble-qt-data (land, lakes, glaciated areas, Antarctic ice shelves, urban areas, playas; read
// with readPn2), rasterized on any window of the globe by scanlines (seed 6.4, 6.5).

#include <cstdint>
#include <filesystem>
#include <vector>

#include "navmap/map/ortho/pn2.h"

namespace navmap::map::ortho {

/// Natural Earth classes, the land cover known worldwide and thus trained against Blue Marble.
enum class GlobalCover : std::uint8_t { Ocean = 0, Land, Lake, Glacier, IceShelf, Urban, Playa };
inline constexpr int kGlobalCoverCount = 7;
const char* globalCoverName(GlobalCover c);

/// A grid over a latitude/longitude box: pixel (c, r) is centred on
/// lat = north - (r + 0.5) * (north - south) / height, lon = west + (c + 0.5) * (east - west) / width.
struct GeoWindow {
    double south = -90, west = -180, north = 90, east = 180;
    int width = 0, height = 0;
    [[nodiscard]] double lat(int r) const { return north - (r + 0.5) * (north - south) / height; }
    [[nodiscard]] double lon(int c) const { return west + (c + 0.5) * (east - west) / width; }
};

/// The rings of one layer's polygons, bucketed by latitude for scanline fills.
class PolygonLayer {
public:
    PolygonLayer() = default;
    explicit PolygonLayer(const std::vector<Pn2Polygon>& polygons);
    /// Sets out[r * width + c] = value at every pixel centre of the window inside the layer
    /// (even-odd rule over all rings, so holes stay open).
    void paint(const GeoWindow& window, std::uint8_t value, std::vector<std::uint8_t>& out) const;
    [[nodiscard]] std::size_t edgeCount() const { return m_edges.size(); }

private:
    struct Edge {
        double lat0, lon0, lat1, lon1;
    };
    static constexpr double kBandDeg = 0.5;
    std::vector<Edge> m_edges;
    std::vector<std::vector<std::uint32_t>> m_bands;  // edges overlapping each latitude band
};

class NaturalEarthCover {
public:
    /// Reads <marble data>/naturalearth/ne_50m_{land,antarctic_ice_shelves_polys,lakes,playas,
    /// glaciated_areas,urban_areas}.pn2; throws Pn2Error naming the file.
    static NaturalEarthCover load(const std::filesystem::path& marble_data_dir);
    /// Builds from layers in painting order (tests).
    explicit NaturalEarthCover(std::vector<std::pair<GlobalCover, PolygonLayer>> layers)
        : m_layers(std::move(layers)) {}
    NaturalEarthCover() = default;

    /// GlobalCover per pixel of the window: ocean, then land, ice shelves, lakes, playas,
    /// glaciers and urban areas painted over each other in that order.
    [[nodiscard]] std::vector<std::uint8_t> rasterize(const GeoWindow& window) const;
    [[nodiscard]] bool empty() const { return m_layers.empty(); }

private:
    std::vector<std::pair<GlobalCover, PolygonLayer>> m_layers;
};

}  // namespace navmap::map::ortho
