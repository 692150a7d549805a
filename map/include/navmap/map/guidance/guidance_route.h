// SPDX-License-Identifier: Apache-2.0
#pragma once
// GuidanceRoute: a route as guidance needs it (docs/guidance.md): the polyline in the store
// frame with measures, the travel time to every point, and the manoeuvres. Built from a graph
// route (manoeuvres derived, speeds from the edges) or from plain points and given manoeuvres
// (a set_route from the control protocol). Immutable after construction; thread-safe to read.

#include <string>
#include <vector>

#include "navmap/map/guidance/maneuver.h"
#include "navmap/map/guidance/maneuver_derivation.h"
#include "navmap/map/guidance/way_names.h"
#include "navmap/map/projection.h"
#include "navmap/map/road_graph.h"
#include "navmap/map/routing.h"

namespace navmap::map::guidance {

/// Speed assumed where a route segment has none (a set_route carries no speeds), km/h: an
/// average over Andorra's valley roads and towns, between the 50 km/h of town streets and the
/// 90 km/h of the CG main roads, lowered for junctions and bends.
inline constexpr double kDefaultRouteSpeedKmh = 40.0;

class GuidanceRoute {
public:
    GuidanceRoute() = default;

    /// `points` in the store frame (zero-length segments allowed); `maneuvers` by point index
    /// (their measures are recomputed from the points); `segment_speed_kmh` per segment
    /// (points.size() - 1 entries, or empty: every segment at `default_speed_kmh`; a speed that
    /// is not finite or not positive also takes the default). A manoeuvre whose point lies
    /// beyond the last point or before the previous manoeuvre's is dropped and named in
    /// problems(); an end_point before its point is set to the point.
    GuidanceRoute(std::vector<PlanarPoint> points, std::vector<Maneuver> maneuvers,
                  std::vector<float> segment_speed_kmh = {}, double default_speed_kmh = kDefaultRouteSpeedKmh);

    /// A graph route's polyline (map::routePolyline) with manoeuvres from deriveManeuvers() and
    /// each segment at its edge's speed (RoadGraph maxspeed or class default).
    static GuidanceRoute fromGraph(const RoadGraph& graph, const std::vector<RoutePoint>& line,
                                   const WayNames* names = nullptr, const DeriveOptions& options = {});

    [[nodiscard]] const std::vector<PlanarPoint>& points() const { return m_points; }
    [[nodiscard]] const std::vector<double>& measures() const { return m_measures; }
    [[nodiscard]] const std::vector<Maneuver>& maneuvers() const { return m_maneuvers; }
    [[nodiscard]] double lengthM() const { return m_measures.empty() ? 0.0 : m_measures.back(); }
    /// Travel time from the start to the end at the segment speeds, seconds.
    [[nodiscard]] double durationS() const { return m_seconds.empty() ? 0.0 : m_seconds.back(); }
    /// Travel time from the start to `measure_m` (clamped to the route), seconds.
    [[nodiscard]] double secondsAt(double measure_m) const;
    /// What was wrong with the input ("maneuver 3: point 900 beyond the last route point 120");
    /// empty when nothing.
    [[nodiscard]] const std::vector<std::string>& problems() const { return m_problems; }

private:
    std::vector<PlanarPoint> m_points;
    std::vector<double> m_measures;
    std::vector<double> m_seconds;  // travel time from the start to each point
    std::vector<Maneuver> m_maneuvers;
    std::vector<std::string> m_problems;
};

}  // namespace navmap::map::guidance
