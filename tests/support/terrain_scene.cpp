// SPDX-License-Identifier: Apache-2.0
#include "terrain_scene.h"

#include <cmath>
#include <numbers>

namespace navmap::render {

TerrainScene loadTerrainScene(const std::filesystem::path& hgt, const GeoBox& box) {
    map::Dem tile = map::loadHgt(hgt);
    map::Dem dem = map::crop(tile, box.south, box.west, box.north, box.east);
    TerrainScene scene{map::Projection((box.south + box.north) / 2, (box.west + box.east) / 2), {}, 0};
    scene.voids_filled = map::fillVoids(dem);
    scene.mesh = buildHeightfield(dem, scene.projection);
    return scene;
}

Camera andorraOverviewCamera(const map::Projection& projection) {
    // Eye over Sant Julià de Lòria, looking north-east past Andorra la Vella (1024 m).
    const map::PlanarPoint eye = projection.forward(42.445, 1.470);
    const map::PlanarPoint target = projection.forward(42.545, 1.575);
    Camera camera;
    camera.eye = {eye.x, eye.y, 3600.0};
    camera.target = {target.x, target.y, 1400.0};
    camera.fov_y_deg = 40.0;
    camera.near_m = 50.0;
    camera.far_m = 60000.0;
    return camera;
}

Camera andorraFlyoverCamera(const map::Projection& projection, double t) {
    const map::PlanarPoint centre = projection.forward(42.545, 1.575);
    const double a = 2.0 * std::numbers::pi * t - 0.75 * std::numbers::pi;  // start in the south-west
    const double radius = 15000.0;
    Camera camera;
    camera.eye = {centre.x + radius * std::cos(a), centre.y + radius * std::sin(a), 4200.0};
    camera.target = {centre.x, centre.y, 1500.0};
    camera.fov_y_deg = 40.0;
    camera.near_m = 50.0;
    camera.far_m = 60000.0;
    return camera;
}

}  // namespace navmap::render
