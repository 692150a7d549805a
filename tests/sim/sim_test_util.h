// SPDX-License-Identifier: Apache-2.0
#pragma once
// Helpers for the simulator tests: synthetic routes and the navmap DBC/decoder.

#include <cmath>
#include <memory>
#include <numbers>
#include <vector>

#include "navmap/ipc/can/dbc_database.h"
#include "navmap/ipc/can/vehicle_decoder.h"
#include "navmap/map/projection.h"
#include "navmap/sim/drive_route.h"

namespace navmap::sim::test {

/// Projection at the Andorra store origin (close enough for synthetic routes).
inline map::Projection andorraProjection() { return map::Projection(42.55, 1.57); }

inline std::shared_ptr<const ipc::DbcDatabase> navmapDbc() {
    return std::make_shared<const ipc::DbcDatabase>(
        ipc::DbcDatabase::loadOrThrow(NAVMAP_IPC_DEFAULT_DBC, ipc::DbcDatabase::Mode::Strict));
}

inline ipc::VehicleDecoder navmapDecoder() {
    auto d = ipc::VehicleDecoder::create({navmapDbc()}, ipc::SignalMap::navmapDefaults());
    return std::move(d).value();
}

/// Straight line east from the origin.
inline std::vector<map::PlanarPoint> straight(double length_m, double step_m = 50.0) {
    std::vector<map::PlanarPoint> pts;
    for (double x = 0; x < length_m; x += step_m) pts.push_back({x, 0.0});
    pts.push_back({length_m, 0.0});
    return pts;
}

/// East `leg` metres, then a sharp 90 degree left turn, north `leg` metres.
inline std::vector<map::PlanarPoint> corner(double leg) {
    return {{0, 0}, {leg / 2, 0}, {leg, 0}, {leg, leg / 2}, {leg, leg}};
}

/// Counter-clockwise circle of radius r (starting east of the centre going north), `turns` turns.
inline std::vector<map::PlanarPoint> circle(double r, double turns = 1.0, int per_turn = 360) {
    std::vector<map::PlanarPoint> pts;
    const int n = static_cast<int>(turns * per_turn);
    for (int i = 0; i <= n; ++i) {
        const double a = 2.0 * std::numbers::pi * i / per_turn;
        pts.push_back({r * std::cos(a), r * std::sin(a)});
    }
    return pts;
}

/// Distance from p to a polyline.
inline double distanceToLine(const std::vector<map::RoutePoint>& line, map::PlanarPoint p) {
    double best = 1e300;
    for (std::size_t i = 0; i + 1 < line.size(); ++i) {
        const auto a = line[i].position;
        const auto b = line[i + 1].position;
        const double dx = b.x - a.x, dy = b.y - a.y;
        const double len2 = dx * dx + dy * dy;
        double t = len2 > 0 ? ((p.x - a.x) * dx + (p.y - a.y) * dy) / len2 : 0.0;
        t = std::fmax(0.0, std::fmin(1.0, t));
        best = std::fmin(best, std::hypot(a.x + t * dx - p.x, a.y + t * dy - p.y));
    }
    return best;
}

}  // namespace navmap::sim::test
