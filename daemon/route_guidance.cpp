// SPDX-License-Identifier: Apache-2.0
#include "route_guidance.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "navmap/map/guidance/countdown.h"

namespace navmap::daemon {

namespace mg = map::guidance;

namespace {

mg::OffRouteConfig offRouteConfig(const GuidanceConfig& c) {
    mg::OffRouteConfig o;
    o.leave_distance_m = c.off_route_distance_m;
    o.leave_time_s = c.off_route_time_s;
    o.return_distance_m = c.on_route_distance_m;
    o.return_time_s = c.on_route_time_s;
    return o;
}

}  // namespace

std::string formatRemainingDistance(double metres) {
    char buf[32];
    const double m = std::isfinite(metres) ? std::max(0.0, metres) : 0.0;
    if (m < 995.0)
        std::snprintf(buf, sizeof buf, "%d m", static_cast<int>(std::lround(m / 10.0) * 10));
    else
        std::snprintf(buf, sizeof buf, "%.1f km", std::max(1.0, std::floor(m / 100.0) / 10.0));
    return buf;
}

std::string formatRemainingTime(double seconds) {
    char buf[32];
    const double s = std::isfinite(seconds) ? std::max(0.0, seconds) : 0.0;
    const long minutes = std::lround(s / 60.0);
    if (s < 30.0)
        std::snprintf(buf, sizeof buf, "< 1 min");
    else if (minutes < 60)
        std::snprintf(buf, sizeof buf, "%ld min", minutes);
    else
        std::snprintf(buf, sizeof buf, "%ld h %02ld min", minutes / 60, minutes % 60);
    return buf;
}

RouteGuidance::RouteGuidance(map::Projection projection, GuidanceConfig config, Publish publish, Log log)
    : m_projection(projection),
      m_config(config),
      m_publish(std::move(publish)),
      m_log(log),
      m_off_route(offRouteConfig(config)) {}

void RouteGuidance::setConfig(const GuidanceConfig& config) {
    const bool lanes_again = config.lane_distance_m != m_config.lane_distance_m;
    m_config = config;
    m_off_route = mg::OffRouteDetector(offRouteConfig(config));
    if (lanes_again) findLanes();
}

void RouteGuidance::setGraph(std::shared_ptr<const map::RoadGraph> graph, const map::Projection& graph_frame) {
    m_lane_finder.reset();
    m_graph = std::move(graph);
    m_graph_frame = graph_frame;
    if (m_graph) m_lane_finder = std::make_unique<mg::LaneFinder>(*m_graph);
}

void RouteGuidance::findLanes() {
    m_lanes.clear();
    if (!m_route || !m_control || !m_lane_finder || !m_graph_frame) return;
    // The control points in the graph's own frame (the map frame moves when re-centred; the
    // graph does not): the lanes do not change with it.
    std::vector<map::PlanarPoint> points;
    points.reserve(m_control->points.size());
    for (const auto& p : m_control->points) points.push_back(m_graph_frame->forward(p.lat_deg, p.lon_deg));
    mg::LaneSearchOptions options;
    options.distance_m = m_config.lane_distance_m;
    m_lanes = m_lane_finder->find(points, m_route->maneuvers(), options);
}

void RouteGuidance::setRoute(const std::shared_ptr<const ipc::RouteState>& route) {
    m_route.reset();
    m_tracker.reset();
    m_off_route.reset();
    m_matched = false;
    m_snapshot = {};
    m_route_id.clear();
    m_control = nullptr;
    m_lanes.clear();
    if (!route || route->points.size() < 2) return;
    m_route_id = route->id;
    m_control = route;
    build(true);
    findLanes();
}

void RouteGuidance::rebase(const map::Projection& frame) {
    m_projection = frame;
    if (m_control) build(false);
}

void RouteGuidance::build(bool log_problems) {
    const auto& route = m_control;
    // The control points as they are (RouteState's line drops repeated points, which adds no
    // length): maneuver indices stay valid and the measures are the ones the renderers drape.
    std::vector<map::PlanarPoint> points;
    points.reserve(route->points.size());
    for (const auto& p : route->points) points.push_back(m_projection.forward(p.lat_deg, p.lon_deg));
    std::vector<mg::Maneuver> maneuvers;
    maneuvers.reserve(route->maneuvers.size());
    for (const ipc::Maneuver& in : route->maneuvers) {
        mg::Maneuver m;
        m.type = in.type;  // one enum (navmap/common/maneuver_type.h)
        m.point = in.index;
        m.end_point = in.end_index.value_or(in.index);
        m.exit = static_cast<int>(in.exit_number.value_or(0));
        m.street = in.text;
        maneuvers.push_back(std::move(m));
    }
    auto guidance = std::make_shared<mg::GuidanceRoute>(std::move(points), std::move(maneuvers));
    if (log_problems) {
        for (const std::string& p : guidance->problems())
            m_log(Log::kWarning, "route %s: %s", m_route_id.c_str(), p.c_str());
    }
    m_route = guidance;
    m_tracker = std::make_unique<mg::RouteProgressTracker>(m_route);
}

void RouteGuidance::update(const EstimatedPose& pose, double time_s) {
    if (!m_tracker || !pose.valid || pose.stale) return;
    const mg::RouteProgress& p = m_tracker->update({pose.x, pose.y});
    m_matched = true;
    const bool was_off = m_off_route.offRoute();
    const bool off = m_off_route.update(time_s, p.offset_m);
    if (off != was_off) {
        ipc::ControlEvent e;
        e.kind = off ? ipc::ControlEventKind::OffRoute : ipc::ControlEventKind::BackOnRoute;
        e.route_id = m_route_id;
        e.offset_m = p.offset_m;
        // Logged before the event goes out: whoever hears it finds it in the log.
        if (off)
            m_log(Log::kNotice, "route %s: off the route (%.0f m from it)", m_route_id.c_str(), p.offset_m);
        else
            m_log(Log::kInfo, "route %s: back on the route", m_route_id.c_str());
        if (m_publish) m_publish(e);
    }
    fill();
}

void RouteGuidance::fill() {
    const mg::RouteProgress& p = m_tracker->progress();
    GuidanceSnapshot s;
    s.active = m_matched;
    s.off_route = m_off_route.offRoute();
    s.arrived = p.arrived;
    s.remaining_m = p.remaining_m;
    s.remaining_s = p.remaining_s;
    s.remaining_distance = formatRemainingDistance(p.remaining_m);
    s.remaining_time = formatRemainingTime(p.remaining_s);
    const auto& maneuvers = m_route->maneuvers();
    if (p.next && *p.next < maneuvers.size()) {
        const mg::Maneuver& next = maneuvers[*p.next];
        s.next = next;
        s.next_junction = m_route->points()[next.point];
        s.street = next.street;
        s.next_distance_m = std::max(0.0, p.to_next_m);
        s.distance_text = mg::formatCountdown(p.to_next_m);
        if (!s.off_route && *p.next < m_lanes.size() && m_lanes[*p.next] &&
            s.next_distance_m <= m_config.lane_distance_m)
            s.lanes = m_lanes[*p.next];
        if (!s.off_route) {
            // The next manoeuvre's arrow, and the one after it, fainter, when it follows closely.
            for (std::size_t k = *p.next; k < maneuvers.size() && k <= *p.next + 1; ++k) {
                const mg::Maneuver& m = maneuvers[k];
                if (m.type == mg::ManeuverType::Depart || m.type == mg::ManeuverType::Arrive) continue;
                if (k > *p.next && m.measure_m - next.end_measure_m > m_config.second_arrow_within_m) break;
                s.arrows.push_back({m.measure_m, std::max(m.end_measure_m, m.measure_m), k == *p.next ? 1.0f : 0.45f});
            }
        }
    }
    m_snapshot = std::move(s);
}

}  // namespace navmap::daemon
