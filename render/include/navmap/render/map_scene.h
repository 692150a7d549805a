// SPDX-License-Identifier: Apache-2.0
#pragma once
// A map scene over a compiled tile store: the store, its tile cache, the projection, the road
// graph, and helpers to place a vehicle on a road and to plan a drive (used by navmapd's
// simulated drive, the golden tests and the benchmarks).

#include <chrono>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "navmap/map/routing.h"
#include "navmap/map/tile_cache.h"
#include "navmap/map/tile_store.h"
#include "navmap/render/camera_rig.h"
#include "navmap/render/map_frame.h"
#include "navmap/render/map_view.h"

namespace navmap::render {

struct MapScene {
    std::shared_ptr<map::TileStore> store;
    std::shared_ptr<map::TileCache> cache;
    map::RoadGraph graph;       ///< empty when the store's graph is unavailable
    /// Why the road graph is unavailable ("checksum mismatch", "the store has none"); empty when
    /// it loaded. The map still renders; routing and map matching go without.
    std::string graph_problem;
    std::string graph_error;    ///< the same naming the file: "<store>: road graph: checksum mismatch"

    /// Opens a store (throws map::StoreError naming the file when its header or index is
    /// unusable) with a cache of `budget_bytes`. A damaged road graph is not fatal: graph_problem.
    static MapScene open(const std::filesystem::path& store_path, std::size_t budget_bytes = std::size_t{128} << 20);

    [[nodiscard]] map::Projection projection() const { return store->projection(); }
    [[nodiscard]] map::PlanarPoint toPlanar(double lat, double lon) const { return projection().forward(lat, lon); }
};

/// A planned drive: the route polyline on the terrain, with measures, ready to draw.
struct PlannedDrive {
    std::vector<map::RoutePoint> line;
    RouteGeometry geometry;  ///< z from the terrain when available
};

/// Fastest car route between two geographic points (nearest drivable graph nodes), or an
/// empty drive when none exists. `terrain` (may be empty) gives heights for the geometry.
PlannedDrive planDrive(const MapScene& scene, double from_lat, double from_lon, double to_lat, double to_lon,
                       const CameraRig::TerrainHeight& terrain = {});

/// Vehicle pose at `measure_m` along a drive.
VehiclePose poseAlong(const PlannedDrive& drive, double measure_m, double speed_mps,
                      const CameraRig::TerrainHeight& terrain = {});

/// Named places of the embedded default data (degrees): used for drives and fixed views.
struct GeoPoint {
    double lat, lon;
};

/// A store, one MapView over its cache and a planned drive: what the benchmarks, the label
/// quality tool and the tests fly along.
struct DriveScene {
    MapScene scene;
    std::unique_ptr<MapView> view;
    PlannedDrive drive;

    /// A camera settled on the vehicle with every tile it needs resident.
    struct Shot {
        Camera camera;
        VehiclePose pose;
        bool complete = false;  ///< all wanted tiles loaded within the timeout
        double measure_m = 0.0;  ///< where along the drive
    };

    /// Places the vehicle `measure_m` along the drive, snaps `rig` onto it and loads the tiles the
    /// camera needs (three rounds: the first loads tiles, the later ones see terrain heights). The
    /// route needs no heights: the renderer drapes it onto each tile it draws.
    Shot settle(CameraRig& rig, double measure_m, double speed_mps, double aspect, int viewport_height,
                std::chrono::milliseconds timeout = std::chrono::seconds(20));

    /// The map frame of a settled shot: its camera, the tiles it needs, the drive as the route
    /// driven up to the shot's pose, and the vehicle marker there. Layers stay at their defaults.
    [[nodiscard]] MapFrame frameFor(const Shot& shot, double aspect, int viewport_height) const;

    /// Throws map::StoreError naming the store when it cannot be opened or has no usable road
    /// graph (a drive needs one).
    static DriveScene open(const std::filesystem::path& store_path, GeoPoint from, GeoPoint to,
                           std::size_t budget_bytes = std::size_t{128} << 20);
};
inline constexpr GeoPoint kAndorraLaVella{42.5075, 1.5218};
inline constexpr GeoPoint kEncamp{42.5347, 1.5801};
inline constexpr GeoPoint kSantJulia{42.4637, 1.4913};

}  // namespace navmap::render
