// SPDX-License-Identifier: Apache-2.0
#pragma once
// Test and benchmark fixtures (never linked by an installed program): a planned drive over a
// map scene, one MapView over its cache, and the named places of the embedded default data
// the drives run between (the golden tests, the benchmarks and navmap-label-quality).

#include <chrono>
#include <cstddef>
#include <filesystem>
#include <memory>
#include <vector>

#include "navmap/common/geo_coordinate.h"
#include "navmap/map/map_scene.h"
#include "navmap/map/routing.h"
#include "navmap/render/camera_rig.h"
#include "navmap/render/map_frame.h"
#include "navmap/render/map_view.h"

namespace navmap::test {

/// A planned drive: the route polyline with measures (map::planRoute), ready to draw.
struct PlannedDrive {
    std::vector<map::RoutePoint> line;
    render::RouteGeometry geometry;  ///< z = 0: the renderer drapes the route onto the terrain
};

/// Vehicle pose at `measure_m` along a drive.
render::VehiclePose poseAlong(const PlannedDrive& drive, double measure_m, double speed_mps,
                              const render::CameraRig::TerrainHeight& terrain = {});

/// A store, one MapView over its cache and a planned drive: what the benchmarks, the label
/// quality tool and the tests fly along.
struct DriveScene {
    map::MapScene scene;
    std::unique_ptr<render::MapView> view;
    PlannedDrive drive;  ///< empty when map::planRoute finds no route

    /// A camera settled on the vehicle with every tile it needs resident.
    struct Shot {
        render::Camera camera;
        render::VehiclePose pose;
        bool complete = false;   ///< all wanted tiles loaded within the timeout
        double measure_m = 0.0;  ///< where along the drive
    };

    /// Places the vehicle `measure_m` along the drive, snaps `rig` onto it and loads the tiles the
    /// camera needs (three rounds: the first loads tiles, the later ones see terrain heights). The
    /// route needs no heights: the renderer drapes it onto each tile it draws.
    Shot settle(render::CameraRig& rig, double measure_m, double speed_mps, double aspect, int viewport_height,
                std::chrono::milliseconds timeout = std::chrono::seconds(20));

    /// The map frame of a settled shot: its camera, the tiles it needs, the drive as the route
    /// driven up to the shot's pose, and the vehicle marker there. Layers stay at their defaults.
    [[nodiscard]] render::MapFrame frameFor(const Shot& shot, double aspect, int viewport_height) const;

    /// Throws map::StoreError naming the store when it cannot be opened or has no usable road
    /// graph (a drive needs one).
    static DriveScene open(const std::filesystem::path& store_path, GeoCoordinate from, GeoCoordinate to,
                           std::size_t budget_bytes = std::size_t{128} << 20);
};
/// Named places of the embedded default data: used for drives and fixed views.
inline constexpr GeoCoordinate kAndorraLaVella{42.5075, 1.5218};
inline constexpr GeoCoordinate kEncamp{42.5347, 1.5801};
inline constexpr GeoCoordinate kSantJulia{42.4637, 1.4913};

}  // namespace navmap::test
