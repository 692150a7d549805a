// SPDX-License-Identifier: Apache-2.0
#include "drive_scene.h"

namespace navmap::test {

namespace {

PlannedDrive planDrive(const map::MapScene& scene, GeoCoordinate from, GeoCoordinate to) {
    PlannedDrive drive;
    const map::RoutePlan plan =
        map::planRoute(scene.graph, scene.toPlanar(from.lat_deg, from.lon_deg), scene.toPlanar(to.lat_deg, to.lon_deg));
    if (!plan.ok()) return drive;
    drive.line = map::routePolyline(scene.graph, *plan.route);
    for (const auto& p : drive.line) {
        drive.geometry.points.emplace_back(p.position.x, p.position.y, 0.0);
        drive.geometry.measure_m.push_back(p.measure_m);
    }
    return drive;
}

}  // namespace

render::VehiclePose poseAlong(const PlannedDrive& drive, double measure_m, double speed_mps,
                              const render::CameraRig::TerrainHeight& terrain) {
    const map::RouteSample s = map::sampleRoute(drive.line, measure_m);
    render::VehiclePose pose;
    pose.position = {s.position.x, s.position.y, terrain ? terrain(s.position.x, s.position.y) : 0.0};
    pose.heading_deg = s.heading_deg;
    pose.speed_mps = speed_mps;
    return pose;
}

DriveScene DriveScene::open(const std::filesystem::path& store_path, GeoCoordinate from, GeoCoordinate to,
                            std::size_t budget_bytes) {
    DriveScene d{map::MapScene::open(store_path, budget_bytes), nullptr, {}};
    if (!d.scene.graph_problem.empty()) throw map::StoreError(d.scene.graph_error);
    d.view = std::make_unique<render::MapView>(d.scene.cache);
    d.drive = planDrive(d.scene, from, to);
    return d;
}

DriveScene::Shot DriveScene::settle(render::CameraRig& rig, double measure_m, double speed_mps, double aspect,
                                    int viewport_height, std::chrono::milliseconds timeout) {
    const auto terrain = [&](double x, double y) { return view->terrainHeight(x, y); };
    Shot shot;
    shot.measure_m = measure_m;
    shot.pose = poseAlong(drive, measure_m, speed_mps);
    shot.camera = rig.update(shot.pose, 0.0);
    for (int i = 0; i < 3; ++i) {
        shot.complete = view->warmUp(shot.camera, aspect, viewport_height, timeout);
        shot.pose = poseAlong(drive, measure_m, speed_mps, terrain);
        shot.camera = rig.update(shot.pose, 0.0, terrain);
    }
    return shot;
}

render::MapFrame DriveScene::frameFor(const Shot& shot, double aspect, int viewport_height) const {
    render::MapFrame frame;
    frame.camera = shot.camera;
    frame.route = &drive.geometry;
    frame.route_progress_m = shot.measure_m;
    frame.marker = render::MarkerState{shot.pose.position, shot.pose.heading_deg, false};
    view->select(frame, aspect, viewport_height);  // tiles and their geomorph, as navmapd draws them
    return frame;
}

}  // namespace navmap::test
