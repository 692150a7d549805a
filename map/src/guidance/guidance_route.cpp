// SPDX-License-Identifier: Apache-2.0
#include "navmap/map/guidance/guidance_route.h"

#include <algorithm>
#include <cmath>

namespace navmap::map::guidance {

GuidanceRoute::GuidanceRoute(std::vector<PlanarPoint> points, std::vector<Maneuver> maneuvers,
                             std::vector<float> segment_speed_kmh, double default_speed_kmh)
    : m_points(std::move(points)) {
    if (!(std::isfinite(default_speed_kmh) && default_speed_kmh > 0.0)) default_speed_kmh = kDefaultRouteSpeedKmh;
    if (!segment_speed_kmh.empty() && segment_speed_kmh.size() + 1 != m_points.size()) {
        m_problems.push_back("segment speeds: " + std::to_string(segment_speed_kmh.size()) + " for " +
                             std::to_string(m_points.empty() ? 0 : m_points.size() - 1) +
                             " segments; all segments at the default speed");
        segment_speed_kmh.clear();
    }
    m_measures.reserve(m_points.size());
    m_seconds.reserve(m_points.size());
    for (std::size_t i = 0; i < m_points.size(); ++i) {
        if (i == 0) {
            m_measures.push_back(0.0);
            m_seconds.push_back(0.0);
            continue;
        }
        const double d = std::hypot(m_points[i].x - m_points[i - 1].x, m_points[i].y - m_points[i - 1].y);
        double v = segment_speed_kmh.empty() ? default_speed_kmh : static_cast<double>(segment_speed_kmh[i - 1]);
        if (!(std::isfinite(v) && v > 0.0)) v = default_speed_kmh;
        m_measures.push_back(m_measures.back() + d);
        m_seconds.push_back(m_seconds.back() + d / (v / 3.6));
    }
    for (std::size_t k = 0; k < maneuvers.size(); ++k) {
        Maneuver& m = maneuvers[k];
        const std::string where = "maneuver " + std::to_string(k) + ": ";
        if (m.point >= m_points.size()) {
            m_problems.push_back(where + "point " + std::to_string(m.point) + " beyond the last route point " +
                                 std::to_string(m_points.empty() ? 0 : m_points.size() - 1));
            continue;
        }
        if (!m_maneuvers.empty() && m.point < m_maneuvers.back().point) {
            m_problems.push_back(where + "point " + std::to_string(m.point) + " before the previous maneuver's point " +
                                 std::to_string(m_maneuvers.back().point));
            continue;
        }
        m.end_point = std::clamp(m.end_point, m.point, m_points.size() - 1);
        m.measure_m = m_measures[m.point];
        m.end_measure_m = m_measures[m.end_point];
        m_maneuvers.push_back(std::move(m));
    }
}

GuidanceRoute GuidanceRoute::fromGraph(const RoadGraph& graph, const std::vector<RoutePoint>& line,
                                       const WayNames* names, const DeriveOptions& options) {
    std::vector<PlanarPoint> points;
    std::vector<float> speeds;
    points.reserve(line.size());
    for (std::size_t i = 0; i < line.size(); ++i) {
        points.push_back(line[i].position);
        // routePolyline drops the duplicate first point of every edge: segment i belongs to the
        // edge of its end point.
        if (i > 0) speeds.push_back(line[i].edge < graph.edges.size() ? graph.edges[line[i].edge].speed_kmh : 0.0F);
    }
    return GuidanceRoute(std::move(points), deriveManeuvers(graph, line, names, options), std::move(speeds));
}

double GuidanceRoute::secondsAt(double measure_m) const {
    if (m_points.size() < 2) return 0.0;
    const double m = std::clamp(measure_m, 0.0, m_measures.back());
    const auto it = std::upper_bound(m_measures.begin(), m_measures.end(), m);
    const std::size_t i = std::min<std::size_t>(
        static_cast<std::size_t>(std::max<std::ptrdiff_t>(1, it - m_measures.begin())) - 1, m_points.size() - 2);
    const double len = m_measures[i + 1] - m_measures[i];
    const double t = len > 0.0 ? (m - m_measures[i]) / len : 0.0;
    return m_seconds[i] + (m_seconds[i + 1] - m_seconds[i]) * t;
}

}  // namespace navmap::map::guidance
