// SPDX-License-Identifier: Apache-2.0
#include "andorra_drive.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <memory>

#include "test_paths.h"

namespace navmap::test {

DriveScene& andorraDrive() {
    static DriveScene d = DriveScene::open(binaryDir() / "andorra.navmap", kAndorraLaVella, kEncamp);
    return d;
}

render::MapFrame settledAndorraFrame(render::ViewMode mode, int width, int height, double measure_m, double speed_mps) {
    DriveScene& d = andorraDrive();
    render::CameraRig rig;
    rig.setMode(mode);
    const double aspect = double(width) / height;
    const auto shot = d.settle(rig, measure_m, speed_mps, aspect, height);
    EXPECT_TRUE(shot.complete) << "tiles of the view at " << measure_m << " m did not load in time";
    return d.frameFor(shot, aspect, height);
}

bool standBuildingInFront(render::MapFrame& frame, glm::vec2 px, float cover_px, int width, int height,
                          double distance_m) {
    const render::Camera& cam = frame.camera;
    const glm::dvec3 forward = glm::normalize(cam.target - cam.eye);
    const glm::dvec3 right = glm::normalize(glm::cross(forward, cam.up));
    const glm::dvec3 up = glm::cross(right, forward);
    const double tan_half = std::tan(glm::radians(cam.fov_y_deg) / 2.0);
    const double ndc_x = 2.0 * px.x / width - 1.0, ndc_y = 1.0 - 2.0 * px.y / height;
    const glm::dvec3 ray = forward + right * (ndc_x * tan_half * width / height) + up * (ndc_y * tan_half);
    const double along = distance_m / glm::length(glm::dvec2(ray));
    const glm::dvec3 at = cam.eye + ray * along;
    // Its width: cover_px at that distance from the eye.
    const double side = cover_px * 2.0 * tan_half * glm::length(ray * along) / height;
    for (auto& tile : frame.tiles) {
        if (!tile || at.x < tile->origin_x || at.y < tile->origin_y || at.x >= tile->origin_x + tile->size_m ||
            at.y >= tile->origin_y + tile->size_m)
            continue;
        auto copy = std::make_shared<map::Tile>(*tile);
        const auto lx = static_cast<float>(at.x - tile->origin_x), ly = static_cast<float>(at.y - tile->origin_y);
        // The highest ground sample near it: the block rises 30 m above the line of sight from there.
        float ground = 0.0f;
        const map::TileDem& dem = copy->dem;
        if (dem.size >= 2) {
            const int col = std::clamp(int(lx / dem.spacing_m), 0, dem.size - 2);
            const int row = std::clamp(int(ly / dem.spacing_m), 0, dem.size - 2);
            ground = std::max({dem.at(row, col), dem.at(row, col + 1), dem.at(row + 1, col), dem.at(row + 1, col + 1)});
        }
        map::Building b;
        const auto h = static_cast<float>(side / 2.0);
        b.footprint.vertices = {{lx - h, ly - h}, {lx + h, ly - h}, {lx + h, ly + h}, {lx - h, ly + h}};
        b.footprint.ring_ends = {4};
        b.footprint.indices = {0, 1, 2, 0, 2, 3};
        b.height_m = static_cast<float>(std::max(10.0, at.z - ground + 30.0));
        b.osm_id = -1;
        copy->buildings.push_back(std::move(b));
        tile = std::move(copy);
        return true;
    }
    return false;
}

}  // namespace navmap::test
