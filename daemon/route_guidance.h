// SPDX-License-Identifier: Apache-2.0
#pragma once
// RouteGuidance: the active route's manoeuvres followed along the map-matched pose (map/guidance:
// progress, countdown, off-route hysteresis), turned into what the displays show (the arrows of
// the next manoeuvres, the HUD's next-turn panel) and what the control socket's subscribers hear
// (off_route, back_on_route). Render thread only. docs/guidance.md.

#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "config.h"
#include "log.h"
#include "navmap/daemon/vehicle/vehicle_state.h"
#include "navmap/ipc/control/control_command.h"
#include "navmap/ipc/control/control_state.h"
#include "navmap/map/guidance/guidance_route.h"
#include "navmap/map/guidance/lane_guidance.h"
#include "navmap/map/guidance/off_route_detector.h"
#include "navmap/map/guidance/route_progress_tracker.h"
#include "navmap/map/projection.h"

namespace navmap::daemon {

/// One manoeuvre arrow, as distances along the route (RouteState's measures).
struct GuidanceArrow {
    double junction_m = 0.0;  ///< where the manoeuvre happens (a roundabout's entry)
    double end_m = 0.0;       ///< where it is done (a roundabout's exit; else junction_m)
    float emphasis = 1.0f;    ///< 1: the next manoeuvre; lower: the one after, drawn fainter
};

/// What the displays show of the guidance at one moment.
struct GuidanceSnapshot {
    bool active = false;     ///< a route is set and the pose has been matched onto it
    bool off_route = false;  ///< the vehicle left the route (hysteresis: docs/guidance.md)
    bool arrived = false;
    std::vector<GuidanceArrow> arrows;            ///< none while off the route
    std::optional<map::guidance::Maneuver> next;  ///< the next manoeuvre (never depart)
    map::PlanarPoint next_junction;               ///< where it happens, store frame
    double next_distance_m = 0.0;                 ///< along the route to its junction (0 inside it)
    std::string distance_text;                    ///< countdown to it: "300 m", "now"
    std::string street;                           ///< the street it turns into; may be empty
    /// The lanes before it, within [guidance] lane_distance_m of its junction (docs/guidance.md
    /// "Lanes"); none: no lane data there, or off the route.
    std::optional<map::guidance::LaneGuidance> lanes;
    double remaining_m = 0.0;
    double remaining_s = 0.0;
    std::string remaining_distance;  ///< "4.2 km"
    std::string remaining_time;      ///< "7 min"
};

class RouteGuidance {
public:
    using Publish = std::function<void(const ipc::ControlEvent&)>;
    RouteGuidance(map::Projection projection, GuidanceConfig config, Publish publish, Log log);

    /// A new control route (or none: cleared): progress and off-route state start over.
    void setRoute(const std::shared_ptr<const ipc::RouteState>& route);
    /// Converts the route again into `frame` (the daemon re-centred its map frame); progress is
    /// found again at the next update(), the off-route state is kept.
    void rebase(const map::Projection& frame);
    /// Follows the pose (store frame, map-matched) at `time_s` (any monotonic clock, seconds).
    void update(const EstimatedPose& pose, double time_s);
    void setConfig(const GuidanceConfig& config);
    /// The road graph (in `graph_frame`) the lanes come from; null: no lane guidance. Takes
    /// effect with the next route.
    void setGraph(std::shared_ptr<const map::RoadGraph> graph, const map::Projection& graph_frame);

    [[nodiscard]] const GuidanceSnapshot& snapshot() const { return m_snapshot; }
    /// The route being followed; null without one.
    [[nodiscard]] const std::shared_ptr<const map::guidance::GuidanceRoute>& route() const { return m_route; }

private:
    void fill();
    // m_control in m_projection: the route and a tracker starting over.
    void build(bool log_problems);
    // The lanes before each of m_route's manoeuvres, from the graph (m_lanes).
    void findLanes();

    map::Projection m_projection;
    GuidanceConfig m_config;
    Publish m_publish;
    Log m_log;
    std::string m_route_id;
    std::shared_ptr<const ipc::RouteState> m_control;  // the route given to setRoute()
    std::shared_ptr<const map::guidance::GuidanceRoute> m_route;
    std::unique_ptr<map::guidance::RouteProgressTracker> m_tracker;
    map::guidance::OffRouteDetector m_off_route;
    bool m_matched = false;
    GuidanceSnapshot m_snapshot;
    std::shared_ptr<const map::RoadGraph> m_graph;
    std::optional<map::Projection> m_graph_frame;                     // set with m_graph
    std::unique_ptr<map::guidance::LaneFinder> m_lane_finder;         // over m_graph
    std::vector<std::optional<map::guidance::LaneGuidance>> m_lanes;  // per m_route manoeuvre
};

/// The remaining distance as drivers read it: "850 m" (tens of metres) under 1 km, "4.2 km" above.
std::string formatRemainingDistance(double metres);
/// The remaining time: "< 1 min", "7 min", "1 h 15 min".
std::string formatRemainingTime(double seconds);

}  // namespace navmap::daemon
