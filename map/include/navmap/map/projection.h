// SPDX-License-Identifier: Apache-2.0
#pragma once
// Map projection shared by the compiler, the tile store and the renderer.

#include <GeographicLib/TransverseMercator.hpp>

namespace navmap::map {

/// Planar metres east/north of an origin.
struct PlanarPoint {
    double x = 0.0;  ///< metres east of the origin
    double y = 0.0;  ///< metres north of the origin
};

/// Transverse Mercator (WGS84, scale 1 on the central meridian) centred on an origin, so that
/// a region of a few hundred kilometres maps to metres with sub-0.1% scale error and the
/// origin itself is (0, 0). Doubles throughout; renderers subtract a camera-relative origin
/// before going to float. Thread-safe (immutable).
class Projection {
public:
    Projection(double origin_lat, double origin_lon);

    [[nodiscard]] PlanarPoint forward(double lat, double lon) const;
    /// Inverse of forward(): returns {lat, lon} in degrees.
    void reverse(PlanarPoint p, double& lat, double& lon) const;

    [[nodiscard]] double originLat() const { return m_origin_lat; }
    [[nodiscard]] double originLon() const { return m_origin_lon; }

private:
    GeographicLib::TransverseMercator m_tm;
    double m_origin_lat;
    double m_origin_lon;
    double m_origin_northing = 0.0;
};

}  // namespace navmap::map
