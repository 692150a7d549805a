// SPDX-License-Identifier: Apache-2.0
#pragma once
// RouteState: the control socket's active route (set_route, latitude/longitude) converted once per
// route version into the store frame, as the one RouteLine that both of its users share: the
// estimator matches the pose onto it (input thread, via VehicleInput::setRoute) and the renderers
// drape its RouteGeometry, made from the same points and measures. So the route's length, the
// distance driven along it and the distance remaining all come from one computation. The parts
// of the route that run in a tunnel are found on the road graph (routeTunnels) for the
// renderers to draw dashed. Render thread only; line() is immutable and may be handed to other
// threads.

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "navmap/daemon/vehicle/map_matcher.h"
#include "navmap/daemon/vehicle/route_line.h"
#include "navmap/daemon/vehicle/vehicle_state.h"
#include "navmap/ipc/control/control_state.h"
#include "navmap/map/projection.h"
#include "navmap/render/map_frame.h"

namespace navmap::daemon {

/// Where a route (`points` in the matcher's frame, `measures` its distances along the route,
/// one per point) runs in a tunnel, as [from, to] distances along it (render::RouteGeometry::
/// tunnels_m): the route is sampled every 5 m or less, each sample matched onto the road graph in
/// the route's direction (MapMatcher, 10 m around, with the hysteresis towards the previous
/// sample's edge); a sample whose edge has road_flags::kTunnel at a confidence of 0.5 or more is
/// in a tunnel, and the runs of them, gaps of up to two samples closed, are the tunnels.
std::vector<std::pair<double, double>> routeTunnels(const MapMatcher& matcher,
                                                    const std::vector<map::PlanarPoint>& points,
                                                    const std::vector<double>& measures);

class RouteState {
public:
    /// The road graph that says where a route runs in a tunnel, with the frame it is in (the
    /// daemon's first map frame: it is not re-expressed when the frame is re-centred).
    struct TunnelGraph {
        std::shared_ptr<const map::RoadGraph> graph;
        map::Projection frame;
    };
    /// `tunnels`: none, no tunnels are marked on the route.
    explicit RouteState(map::Projection projection, std::optional<TunnelGraph> tunnels = std::nullopt)
        : m_projection(projection), m_tunnels(std::move(tunnels)) {}

    /// Takes the control socket's newest route snapshot; converts it when its version is new and
    /// returns true then (the caller hands line() to the estimator). A null snapshot (cleared)
    /// drops the current route and returns true once.
    bool update(const std::shared_ptr<const ipc::RouteState>& route);
    /// Converts the route again into `frame` (the daemon re-centred its map frame) under the same
    /// id and progress; hand line() to the estimator with the rebase.
    void rebase(const map::Projection& frame);
    /// Progress: the furthest distance driven along the route of a pose matched onto it.
    void track(const EstimatedPose& pose);

    /// The route's id; empty before the first set_route.
    [[nodiscard]] const std::string& id() const { return m_id; }
    /// The store-frame route for map matching; null when the route has fewer than two points.
    [[nodiscard]] const std::shared_ptr<const RouteLine>& line() const { return m_line; }
    /// What the renderers drape; null when there is no line of two points or more.
    [[nodiscard]] const render::RouteGeometry* geometry() const {
        return m_geometry.points.size() >= 2 ? &m_geometry : nullptr;
    }
    /// Route length, metres (0 without a line).
    [[nodiscard]] double lengthM() const { return m_line ? m_line->lengthM() : 0.0; }
    /// The furthest distance driven along the route so far, metres.
    [[nodiscard]] double drivenM() const { return m_driven_m; }
    [[nodiscard]] double remainingM() const;
    /// Points the control socket gave for the route (the line drops repeated points).
    [[nodiscard]] std::size_t controlPoints() const { return m_control_points; }
    /// How many control routes were converted (one per route version).
    [[nodiscard]] std::uint64_t conversions() const { return m_conversions; }

private:
    void convert();  // m_control into m_line and m_geometry, in m_projection

    map::Projection m_projection;
    std::optional<TunnelGraph> m_tunnels;
    std::shared_ptr<const MapMatcher> m_tunnel_matcher;  // over m_tunnels' graph, made with the first route
    std::shared_ptr<const ipc::RouteState> m_control;    // the control route converted last
    std::uint64_t m_version = ~std::uint64_t{0};         // control snapshot version converted last
    std::string m_id;
    std::size_t m_control_points = 0;
    std::shared_ptr<const RouteLine> m_line;
    render::RouteGeometry m_geometry;
    double m_driven_m = 0.0;
    std::uint64_t m_conversions = 0;
};

}  // namespace navmap::daemon
