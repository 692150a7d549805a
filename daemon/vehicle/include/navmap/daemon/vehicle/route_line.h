// SPDX-License-Identifier: Apache-2.0
#pragma once
// RouteLine: the active route as a store-frame polyline with measures, and matching a position
// onto it (nearest segment with heading agreement, preferring the neighbourhood of the previous
// match so that a route that passes the same place twice is followed in order). Immutable.

#include <optional>
#include <string>
#include <vector>

#include "navmap/daemon/vehicle/vehicle_state_config.h"
#include "navmap/map/projection.h"

namespace navmap::daemon {

struct RouteMatch {
    map::PlanarPoint point;    ///< nearest point on the route
    double heading_deg = 0.0;  ///< direction of the route there (clockwise from north)
    double measure_m = 0.0;    ///< distance from the route start
    double distance_m = 0.0;   ///< from the query position
    double confidence = 0.0;   ///< 0..1
};

class RouteLine {
public:
    /// `id` is the control protocol's route id; `points` in store-frame metres (duplicates dropped).
    RouteLine(std::string id, const std::vector<map::PlanarPoint>& points);

    [[nodiscard]] const std::string& id() const { return m_id; }
    [[nodiscard]] double lengthM() const { return m_measures.empty() ? 0.0 : m_measures.back(); }
    [[nodiscard]] const std::vector<map::PlanarPoint>& points() const { return m_points; }
    /// Distance from the route start at each point, metres (same size as points()).
    [[nodiscard]] const std::vector<double>& measures() const { return m_measures; }

    /// Best match within cfg.match_radius_m, or nullopt. `previousMeasure` (if any) penalises
    /// jumps along the route.
    [[nodiscard]] std::optional<RouteMatch> match(map::PlanarPoint p, std::optional<double> heading_deg,
                                                  std::optional<double> previous_measure,
                                                  const VehicleStateConfig& cfg) const;

private:
    std::string m_id;
    std::vector<map::PlanarPoint> m_points;
    std::vector<double> m_measures;
};

}  // namespace navmap::daemon
