// SPDX-License-Identifier: Apache-2.0
#pragma once
// Which tiles a camera needs: the tiles under its ground footprint (visible set, highest
// priority, nearest first) plus prefetch ahead along the heading or the route.

#include <span>
#include <vector>

#include "navmap/map/tile_cache.h"
#include "navmap/map/tile_scheme.h"

namespace navmap::map {

/// Tiles of `level` overlapping a ground polygon (store-frame metres, any orientation);
/// priority = base - distance(tile center, focus) / tile size, so nearer tiles come first.
std::vector<TileRequest> tilesInPolygon(const TileScheme& scheme, int level, std::span<const PlanarPoint> polygon,
                                        PlanarPoint focus, float base_priority);

/// Tiles of `level` overlapping a circle.
std::vector<TileRequest> tilesInCircle(const TileScheme& scheme, int level, PlanarPoint center, double radius_m,
                                       float base_priority);

/// Tiles within radius_m of a polyline (e.g. the planned route ahead), nearer to its start
/// first, up to `length_m` along it.
std::vector<TileRequest> tilesAlongPolyline(const TileScheme& scheme, int level, std::span<const PlanarPoint> line,
                                            double radius_m, double length_m, float base_priority);

struct CameraFootprint {
    std::vector<PlanarPoint> ground;     ///< visible ground polygon (store frame)
    PlanarPoint position;                ///< vehicle/camera ground position
    double heading_deg = 0;              ///< clockwise from north
    double prefetch_m = 0;               ///< look-ahead distance along the heading
    std::span<const PlanarPoint> route;  ///< optional route ahead (store frame); used instead of the heading
};

/// Visible tiles (priority >= 1000) plus prefetch tiles (priority < 1000), deduplicated with the
/// highest priority kept.
std::vector<TileRequest> selectTiles(const TileScheme& scheme, int level, const CameraFootprint& camera);

/// Merges request lists, keeping the highest priority per tile.
std::vector<TileRequest> mergeRequests(std::vector<TileRequest> a, std::span<const TileRequest> b);

}  // namespace navmap::map
