// SPDX-License-Identifier: Apache-2.0
#include "navmap/render/maplibre_camera.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace navmap::render {

namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

}  // namespace

double mapLibreMetresPerPixel(double lat_deg, double zoom) {
    return kMapLibreEarthCircumferenceM * std::cos(lat_deg * kDeg) / (kMapLibreTileSizePx * std::exp2(zoom));
}

double mapLibreCameraDistance(double lat_deg, double zoom, int viewport_height_px, double fov_y_deg) {
    return 0.5 * static_cast<double>(viewport_height_px) / std::tan(0.5 * fov_y_deg * kDeg) *
           mapLibreMetresPerPixel(lat_deg, zoom);
}

Camera mapLibreCameraAt(const glm::dvec3& center, double lat_deg, double zoom, double pitch_deg, double bearing_deg,
                        int viewport_height_px) {
    const double d = mapLibreCameraDistance(lat_deg, zoom, viewport_height_px);
    const double p = pitch_deg * kDeg;
    const double b = bearing_deg * kDeg;
    const glm::dvec3 ahead(std::sin(b), std::cos(b), 0.0);  // the bearing on the ground
    const glm::dvec3 z(0.0, 0.0, 1.0);
    Camera c;
    c.target = center;
    c.eye = center - ahead * (d * std::sin(p)) + z * (d * std::cos(p));
    // The screen's up direction, perpendicular to the line of sight: the bearing when looking
    // straight down, turning to the vertical as the pitch grows (a fixed z-up would be undefined
    // at pitch 0).
    c.up = ahead * std::cos(p) + z * std::sin(p);
    c.fov_y_deg = kMapLibreFovYDeg;
    c.near_m = std::clamp(d * 0.02, 1.0, 50.0);
    c.far_m = std::max(60000.0, d * 20.0);
    return c;
}

double gridBearingDeg(const map::Projection& projection, double lat_deg, double lon_deg, double bearing_deg) {
    // True north measured on the plane: a step north in latitude.
    const map::PlanarPoint c = projection.forward(lat_deg, lon_deg);
    const map::PlanarPoint north = projection.forward(lat_deg + 1e-4, lon_deg);
    return bearing_deg + std::atan2(north.x - c.x, north.y - c.y) / kDeg;
}

Camera cameraFromMapLibre(const MapLibreCamera& camera, const map::Projection& projection, int viewport_height_px,
                          const std::function<double(double x, double y)>& terrain) {
    const map::PlanarPoint c = projection.forward(camera.center.lat_deg, camera.center.lon_deg);
    const double z = terrain ? terrain(c.x, c.y) : 0.0;
    return mapLibreCameraAt(
        {c.x, c.y, z}, camera.center.lat_deg, camera.zoom, camera.pitch_deg,
        gridBearingDeg(projection, camera.center.lat_deg, camera.center.lon_deg, camera.bearing_deg),
        viewport_height_px);
}

}  // namespace navmap::render
