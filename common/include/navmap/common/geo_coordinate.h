// SPDX-License-Identifier: Apache-2.0
#pragma once
// GeoCoordinate: the one geographic point of every module (control protocol route points, the
// simulator's places, the map compiler's OSM features, Natural Earth polygons, MapLibre cameras,
// recorded drives), so a position goes from one module to the next as a value and its units are
// in its field names.
// Plain values, no I/O; no checks of the ranges (the parsers that build one check them).

namespace navmap {

/// A point on the WGS84 ellipsoid, in degrees: latitude north positive [-90, 90], longitude east
/// positive [-180, 180].
struct GeoCoordinate {
    double lat_deg = 0.0;
    double lon_deg = 0.0;
    bool operator==(const GeoCoordinate&) const = default;
};

}  // namespace navmap
