// SPDX-License-Identifier: Apache-2.0
// The label pass's keep-out areas: the vehicle marker, the speed limit sign, the current street's
// bar, the lane row, the route just ahead of the car and the manoeuvre arrows, as screen boxes no
// label may cover.
#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include "guidance_overlay_pass.h"
#include "label_pass.h"
#include "label_pass_screen.h"
#include "navmap/render/maneuver_arrow.h"
#include "street_bar_layout.h"

namespace navmap::render::gl {

void LabelPass::keepOut(const MapFrame& frame, std::span<const TileLabels> tiles, glm::vec2 viewport,
                        std::span<const glm::vec2> marker, const MapStyle& style) {
    m_keep_out.clear();
    const float margin = m_params.keep_out_margin_px;
    if (marker.size() >= 2) {
        glm::vec2 lo(std::numeric_limits<float>::max()), hi(std::numeric_limits<float>::lowest());
        for (const glm::vec2 p : marker) {
            lo = glm::min(lo, p);
            hi = glm::max(hi, p);
        }
        m_keep_out.push_back({0.5f * (lo + hi), 0.5f * (hi - lo) + margin, {1.0f, 0.0f}});
    }
    // The speed limit sign, drawn over everything in its corner.
    if (frame.speed_limit && frame.speed_limit->kmh > 0) {
        const int digits = static_cast<int>(std::to_string(frame.speed_limit->kmh).size());
        const SpeedLimitSignLayout sign = speedLimitSignLayout(
            static_cast<int>(viewport.x), static_cast<int>(viewport.y), frame.speed_limit->corner, digits);
        m_keep_out.push_back({sign.centre, glm::vec2(sign.radius + margin), {1.0f, 0.0f}});
    }
    // The current street's bar, laid out with this pass's engine as the overlay lays it out.
    if (frame.street_bar) {
        const StreetBarLayout bar =
            streetBarLayout(m_engine, *frame.street_bar, static_cast<int>(viewport.x), static_cast<int>(viewport.y));
        if (!bar.text.empty())
            m_keep_out.push_back({0.5f * (bar.lo + bar.hi), 0.5f * (bar.hi - bar.lo) + margin, {1.0f, 0.0f}});
    }
    // The lane row's panel at the top centre, drawn over everything there.
    if (frame.lanes && !frame.lanes->lanes.empty()) {
        const LaneRowLayout row =
            laneRowAtTop(static_cast<int>(viewport.x), static_cast<int>(viewport.y), frame.lanes->lanes.size());
        const auto [lo, hi] = laneRowPanel(row, frame.lanes->lanes.size());
        m_keep_out.push_back({0.5f * (lo + hi), 0.5f * (hi - lo) + glm::vec2(margin), {1.0f, 0.0f}});
    }
    auto ground_at = [&](double x, double y) {
        const double z = groundHeight(tiles, x, y);
        return std::isnan(z) ? frame.camera.target.z : z;
    };
    const float focal_px = m_projection[1][1] * 0.5f * viewport.y;
    const auto near = static_cast<float>(frame.camera.near_m);
    // A draped polyline on screen: one box per piece, as wide as the piece (`half_width_m(i)`,
    // piece i from point i - 1 to i) at its nearer end, plus the margin.
    auto strip = [&](const std::vector<glm::dvec3>& points, auto&& half_width_m) {
        for (std::size_t i = 1; i < points.size(); ++i) {
            const glm::vec4 ca = m_view_projection * glm::vec4(glm::vec3(points[i - 1] - m_eye), 1.0f);
            const glm::vec4 cb = m_view_projection * glm::vec4(glm::vec3(points[i] - m_eye), 1.0f);
            if (ca.w < near || cb.w < near) continue;
            const glm::vec2 a = toScreen(ca, viewport), b = toScreen(cb, viewport);
            const float len = glm::length(b - a);
            const glm::vec2 axis = len > 1e-3f ? (b - a) / len : glm::vec2(1.0f, 0.0f);
            const float half_width = half_width_m(i) * focal_px / std::min(ca.w, cb.w) + margin;
            m_keep_out.push_back({0.5f * (a + b), {0.5f * len + half_width, half_width}, axis});
        }
    };
    // Points every `step_m` along a polyline with measures, from `from` to `to`, draped on the
    // finest drawn tile under each.
    auto sample = [&](const std::vector<glm::dvec3>& points, const std::vector<double>& measure_m, double from,
                      double to, double step_m) {
        std::vector<glm::dvec3> out;
        std::vector<double> at;
        // From the first point at or beyond `from` (the measures grow along the line).
        std::size_t k = std::max<std::size_t>(
            1,
            static_cast<std::size_t>(std::lower_bound(measure_m.begin(), measure_m.end(), from) - measure_m.begin()));
        for (double m = from;; m = std::min(m + step_m, to)) {
            while (k + 1 < measure_m.size() && measure_m[k] < m) ++k;
            const double m0 = measure_m[k - 1], m1 = measure_m[k];
            const double u = m1 > m0 ? std::clamp((m - m0) / (m1 - m0), 0.0, 1.0) : 0.0;
            const glm::dvec3 p = glm::mix(points[k - 1], points[k], u);
            out.emplace_back(p.x, p.y, ground_at(p.x, p.y));
            at.push_back(m);
            if (m >= to) break;
        }
        return std::pair(std::move(out), std::move(at));
    };
    // The route just ahead of the car.
    if (frame.route && frame.layers.route && frame.route->points.size() >= 2 &&
        frame.route->measure_m.size() == frame.route->points.size()) {
        const RouteGeometry& r = *frame.route;
        const double from = std::clamp(frame.route_progress_m, r.measure_m.front(), r.measure_m.back());
        const double to = std::min(from + m_params.route_keep_out_m, r.measure_m.back());
        const auto [points, at] = sample(r.points, r.measure_m, from, to, 10.0);
        strip(points, [&](std::size_t) { return 0.5f * style.route_width_m; });
    }
    // The manoeuvre arrows, as wide as they are drawn (casing included; the head at its base).
    for (const ManeuverArrow& arrow : frame.arrows) {
        if (arrow.emphasis <= 0.0f) continue;
        const float grow = arrowScale(arrow, style, frame.camera.eye, frame.camera.target.z, focal_px);
        const ArrowShape shape = arrowShape(arrow, style, grow);
        const RouteGeometry& line = shape.line;
        if (line.points.size() < 2 || line.measure_m.size() != line.points.size()) continue;
        const auto sampled = sample(line.points, line.measure_m, line.measure_m.front(), line.measure_m.back(), 5.0);
        const auto& points = sampled.first;
        const auto& at = sampled.second;
        strip(points, [&](std::size_t i) {
            return std::max(arrowHalfWidth(shape, at[i - 1], true, true), arrowHalfWidth(shape, at[i], true, false));
        });
    }
}

}  // namespace navmap::render::gl
