// SPDX-License-Identifier: Apache-2.0
#pragma once
// The local frame shared by the compiler, the tile store and the renderer: World Mercator (the
// world tile scheme's projection, world_tiles.h) around an origin, in ground metres at the origin.

#include "navmap/map/world_tiles.h"

namespace navmap::map {

/// Planar metres east/north of an origin.
struct PlanarPoint {
    double x = 0.0;  ///< metres east of the origin
    double y = 0.0;  ///< metres north of the origin
};

/// A local frame: World Mercator (ellipsoidal, WGS84; conformal, grid north = true north) around
/// an origin, divided by the projection's scale at the origin, so that the origin is (0, 0) and
/// lengths are true metres there. The scale drifts away from the origin's latitude by about
/// tan(lat) * 0.016 % per km north or south (0.014 % per km at 42 N, 0.04 % at 70 N); it does not
/// drift east or west. Two frames differ by a uniform scale and a translation (transformFrom), so
/// a store's tiles can be drawn in a frame around the camera anywhere on Earth. Doubles
/// throughout; renderers subtract a camera-relative origin before going to float. Thread-safe
/// (immutable).
class Projection {
public:
    Projection(double origin_lat, double origin_lon);

    [[nodiscard]] PlanarPoint forward(double lat, double lon) const;
    /// Inverse of forward(): returns {lat, lon} in degrees (longitude in [-180, 180)).
    void reverse(PlanarPoint p, double& lat, double& lon) const;

    [[nodiscard]] double originLat() const { return m_origin_lat; }
    [[nodiscard]] double originLon() const { return m_origin_lon; }

    /// World Mercator metres per frame metre.
    [[nodiscard]] double scale() const { return m_scale; }
    /// A World Mercator point in this frame. x is taken on the side of the antimeridian nearer to
    /// the origin.
    [[nodiscard]] PlanarPoint fromMercator(MercatorPoint m) const;
    [[nodiscard]] MercatorPoint toMercator(PlanarPoint p) const;
    /// Points of `from` in this frame: p_this = scale * p_from + offset.
    [[nodiscard]] FrameTransform transformFrom(const Projection& from) const;

private:
    double m_origin_lat;
    double m_origin_lon;
    double m_scale;
    MercatorPoint m_origin;
};

}  // namespace navmap::map
