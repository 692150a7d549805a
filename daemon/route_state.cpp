// SPDX-License-Identifier: Apache-2.0
#include "route_state.h"

#include <algorithm>
#include <vector>

namespace navmap::daemon {

bool RouteState::update(const std::shared_ptr<const ipc::RouteState>& route) {
    if (!route) {
        // clear_route: nothing to draw or match from now on.
        if (m_id.empty() && !m_line) return false;
        m_version = ~std::uint64_t{0};
        ++m_conversions;
        m_id.clear();
        m_control_points = 0;
        m_driven_m = 0.0;
        m_line = nullptr;
        m_control = nullptr;
        const std::uint64_t geometry_version = m_geometry.version + 1;
        m_geometry = {};
        m_geometry.version = geometry_version;
        return true;
    }
    if (route->version == m_version) return false;
    m_version = route->version;
    ++m_conversions;
    m_id = route->id;
    m_control_points = route->points.size();
    m_driven_m = 0.0;
    m_control = route;
    convert();
    return true;
}

void RouteState::rebase(const map::Projection& frame) {
    m_projection = frame;
    if (m_line) convert();
}

void RouteState::convert() {
    std::vector<map::PlanarPoint> points;
    points.reserve(m_control->points.size());
    for (const auto& p : m_control->points) points.push_back(m_projection.forward(p.lat_deg, p.lon_deg));
    m_line = points.size() >= 2 ? std::make_shared<const RouteLine>(m_id, points) : nullptr;
    // The renderers re-drape the route when the geometry's version changes.
    const std::uint64_t geometry_version = m_geometry.version + 1;
    m_geometry = {};
    m_geometry.version = geometry_version;
    if (m_line) {
        for (const auto& p : m_line->points()) m_geometry.points.emplace_back(p.x, p.y, 0.0);
        m_geometry.measure_m = m_line->measures();
    }
}

void RouteState::track(const EstimatedPose& pose) {
    if (pose.on_route) m_driven_m = std::max(m_driven_m, pose.route_driven_m);
}

double RouteState::remainingM() const { return std::max(0.0, lengthM() - m_driven_m); }

}  // namespace navmap::daemon
