// SPDX-License-Identifier: Apache-2.0
#pragma once
// Map cameras as MapLibre GL JS states them (HMI teams specify views this way): a center in
// longitude/latitude, a zoom on 512-px tiles, a pitch in degrees from straight down, a bearing
// clockwise from north, a vertical field of view of 36.87 degrees, and the camera at the distance
// that puts the center in the middle of the viewport. Converted here to navmap's Camera in the
// store frame (map::Projection metres, z up). GL-free; pure functions.

#include <functional>

#include "navmap/common/geo_coordinate.h"
#include "navmap/map/projection.h"
#include "navmap/render/camera.h"

namespace navmap::render {

/// MapLibre GL JS's default vertical field of view, degrees (its transform: 0.6435011 rad).
inline constexpr double kMapLibreFovYDeg = 36.87;
/// Circumference of the WGS84 equator, metres, as MapLibre's transform uses it.
inline constexpr double kMapLibreEarthCircumferenceM = 40075016.686;
/// MapLibre GL JS's tile size in pixels: zoom z shows the world 512 x 2^z pixels wide.
inline constexpr double kMapLibreTileSizePx = 512.0;
/// The accepted ranges (MapLibre's maxPitch is 85 degrees; zoom 24 is far below a pixel a centimetre).
inline constexpr double kMapLibreMinZoom = 0.0, kMapLibreMaxZoom = 24.0;
inline constexpr double kMapLibreMinPitchDeg = 0.0, kMapLibreMaxPitchDeg = 85.0;

/// A MapLibre GL JS camera: jumpTo({center, zoom, pitch, bearing}).
struct MapLibreCamera {
    GeoCoordinate center;  ///< WGS84 degrees
    double zoom = 16.0;
    double pitch_deg = 0.0;    ///< 0 = looking straight down; 85 at most
    double bearing_deg = 0.0;  ///< the direction at the top of the screen, clockwise from north
};

/// Ground metres per screen pixel at the center: 40075016.686 * cos(lat) / (512 * 2^zoom).
[[nodiscard]] double mapLibreMetresPerPixel(double lat_deg, double zoom);

/// Eye to center, metres: 0.5 * viewport_height_px / tan(fov_y / 2) * metres per pixel.
[[nodiscard]] double mapLibreCameraDistance(double lat_deg, double zoom, int viewport_height_px,
                                            double fov_y_deg = kMapLibreFovYDeg);

/// The camera looking at `center` (store-frame metres, z on the ground) from the MapLibre distance
/// for `lat_deg` and `zoom`, pitched and turned as given. Up is the screen's up direction, so a
/// pitch of 0 looks straight down with `bearing_deg` at the top. Near and far planes as the
/// camera rig sets them (near 2 % of the distance within 1..50 m, far at least 60 km).
[[nodiscard]] Camera mapLibreCameraAt(const glm::dvec3& center, double lat_deg, double zoom, double pitch_deg,
                                      double bearing_deg, int viewport_height_px);

/// A bearing from true north (MapLibre, compasses, GNSS) turned into the store frame, whose y axis
/// is grid north: the two differ off the projection's central meridian (meridian convergence).
[[nodiscard]] double gridBearingDeg(const map::Projection& projection, double lat_deg, double lon_deg,
                                    double bearing_deg);

/// The same for a camera given in longitude/latitude: the center is projected with `projection`
/// and stands on the ground height `terrain` gives there (empty: z = 0).
[[nodiscard]] Camera cameraFromMapLibre(const MapLibreCamera& camera, const map::Projection& projection,
                                        int viewport_height_px,
                                        const std::function<double(double x, double y)>& terrain = {});

}  // namespace navmap::render
