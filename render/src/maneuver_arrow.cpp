// SPDX-License-Identifier: Apache-2.0
#include "navmap/render/maneuver_arrow.h"

#include <algorithm>
#include <cmath>

#include "navmap/map/road_class.h"
#include "navmap/render/road_style.h"

namespace navmap::render {

namespace {

// The longest head, as a share of the arrow's length.
constexpr double kHeadShare = 1.0 / 3.0;

// The point `measure` along a polyline with cumulative measures (clamped to its ends).
glm::dvec3 pointAt(std::span<const glm::dvec3> points, std::span<const double> measures, double measure) {
    if (measure <= measures.front()) return points.front();
    if (measure >= measures.back()) return points.back();
    const auto it = std::upper_bound(measures.begin(), measures.end(), measure);
    const auto i = static_cast<std::size_t>(it - measures.begin());
    const double span = measures[i] - measures[i - 1];
    const double t = span > 0.0 ? (measure - measures[i - 1]) / span : 0.0;
    return points[i - 1] + t * (points[i] - points[i - 1]);
}

// Parameters t0 < t1 in [0, 1] of the part of a -> b inside the disc; false when none.
bool clipToDisc(glm::dvec2 a, glm::dvec2 b, glm::dvec2 centre, double radius, double& t0, double& t1) {
    const glm::dvec2 d = b - a, f = a - centre;
    const double qa = glm::dot(d, d), qb = 2.0 * glm::dot(f, d), qc = glm::dot(f, f) - radius * radius;
    if (qa < 1e-12) return false;
    const double disc = qb * qb - 4.0 * qa * qc;
    if (disc <= 0.0) return false;
    const double root = std::sqrt(disc);
    t0 = std::max(0.0, (-qb - root) / (2.0 * qa));
    t1 = std::min(1.0, (-qb + root) / (2.0 * qa));
    return t1 > t0;
}

}  // namespace

ManeuverArrow cutManeuverArrow(const RouteGeometry& route, double junction_measure_m, double before_m, double after_m) {
    ManeuverArrow arrow;
    const auto& pts = route.points;
    const auto& ms = route.measure_m;
    if (pts.size() < 2 || ms.size() != pts.size()) return arrow;
    const double from = std::max(ms.front(), junction_measure_m - std::max(before_m, 0.0));
    const double to = std::min(ms.back(), junction_measure_m + std::max(after_m, 0.0));
    if (to - from < 1.0) return arrow;
    arrow.points.push_back(pointAt(pts, ms, from));
    // The measures grow along the route: only the points between from and to are visited.
    for (auto m = std::upper_bound(ms.begin(), ms.end(), from); m != ms.end() && *m < to; ++m)
        arrow.points.push_back(pts[static_cast<std::size_t>(m - ms.begin())]);
    arrow.points.push_back(pointAt(pts, ms, to));
    return arrow;
}

std::vector<std::vector<glm::dvec3>> junctionRoads(std::span<const std::shared_ptr<const map::Tile>> tiles,
                                                   glm::dvec2 junction, double radius_m) {
    std::vector<std::vector<glm::dvec3>> out;
    for (const auto& tile : tiles) {
        if (!tile) continue;
        const glm::dvec2 origin(tile->origin_x, tile->origin_y);
        // Tiles wholly outside the disc hold nothing of it.
        const glm::dvec2 nearest = glm::clamp(junction, origin, origin + tile->size_m);
        if (glm::length(nearest - junction) > radius_m) continue;
        for (const map::Road& road : tile->roads) {
            if (road.flags & map::road_flags::kTunnel) continue;
            std::vector<glm::dvec3> piece;
            for (std::size_t i = 0; i + 1 < road.points.size(); ++i) {
                const glm::dvec2 a = origin + glm::dvec2(road.points[i].x, road.points[i].y);
                const glm::dvec2 b = origin + glm::dvec2(road.points[i + 1].x, road.points[i + 1].y);
                double t0 = 0.0, t1 = 0.0;
                if (!clipToDisc(a, b, junction, radius_m, t0, t1)) {
                    if (piece.size() >= 2) out.push_back(std::move(piece));
                    piece.clear();
                    continue;
                }
                const glm::dvec2 p0 = a + t0 * (b - a), p1 = a + t1 * (b - a);
                if (piece.empty() || t0 > 0.0) {
                    if (piece.size() >= 2) out.push_back(std::move(piece));
                    piece.clear();
                    piece.emplace_back(p0, 0.0);
                }
                piece.emplace_back(p1, 0.0);
                if (t1 < 1.0) {  // leaves the disc
                    if (piece.size() >= 2) out.push_back(std::move(piece));
                    piece.clear();
                }
            }
            if (piece.size() >= 2) out.push_back(std::move(piece));
        }
    }
    return out;
}

float arrowScale(const ManeuverArrow& arrow, const MapStyle& style, const glm::dvec3& eye, double ground_z,
                 float focal_px) {
    glm::dvec3 mid(0.0);
    for (const glm::dvec3& p : arrow.points) mid += p;
    mid /= double(std::max<std::size_t>(arrow.points.size(), 1));
    mid.z = ground_z;
    const float eye_dist = std::max(static_cast<float>(glm::length(mid - eye)), 1.0f);
    const float px_per_m = focal_px / eye_dist;
    return std::max(distanceWidthScale(eye_dist, style.roads.scale_threshold_m, style.roads.max_scale),
                    style.arrow_min_width_px / std::max(style.arrow_width_m * px_per_m, 1e-6f));
}

ArrowShape arrowShape(const ManeuverArrow& arrow, const MapStyle& style, float scale) {
    ArrowShape s;
    scale = std::max(scale, 0.0f);
    s.half_width_m = 0.5f * std::max(style.arrow_width_m, 0.0f) * scale;
    s.head_half_width_m = std::max(0.5f * style.arrow_head_width_m * scale, s.half_width_m);
    s.casing_m = std::max(style.arrow_casing_m, 0.0f) * scale;
    // Distinct points (2D) with cumulative measures.
    std::vector<glm::dvec3> pts;
    std::vector<double> ms;
    for (const glm::dvec3& p : arrow.points) {
        if (!pts.empty()) {
            const double step = glm::length(glm::dvec2(p) - glm::dvec2(pts.back()));
            if (step < 1e-3) continue;
            ms.push_back(ms.back() + step);
        } else {
            ms.push_back(0.0);
        }
        pts.push_back(p);
    }
    if (pts.size() < 2 || ms.back() < 0.5) return s;
    const double length = ms.back();
    // At most a third of the arrow (the part past the junction of a usual cut), keeping the
    // head's proportions when it is shortened.
    const double wanted = std::max(double(style.arrow_head_length_m) * scale, 0.1);
    const double head_length = std::min(wanted, kHeadShare * length);
    s.head_half_width_m = std::max(static_cast<float>(s.head_half_width_m * head_length / wanted), s.half_width_m);
    s.tip_m = length;
    s.head_m = length - head_length;
    // The casing's tip lies casing_m off the fill's two slanted sides: casing / sin(half angle).
    const double tan_half = double(s.head_half_width_m) / head_length;
    const double sin_half = tan_half / std::sqrt(1.0 + tan_half * tan_half);
    s.casing_tip_m = length + double(s.casing_m) / std::max(sin_half, 1e-3);
    // Extend straight along the last piece, then insert the breakpoints.
    const glm::dvec2 dir = glm::normalize(glm::dvec2(pts.back()) - glm::dvec2(pts[pts.size() - 2]));
    if (s.casing_tip_m > length + 1e-6) {
        pts.push_back(pts.back() + glm::dvec3(dir * (s.casing_tip_m - length), 0.0));
        ms.push_back(s.casing_tip_m);
    }
    std::vector<double> breaks = {s.head_m - s.casing_m, s.head_m};
    RouteGeometry& line = s.line;
    for (std::size_t i = 0; i < pts.size(); ++i) {
        if (i > 0) {
            for (double b : breaks) {
                if (b > ms[i - 1] + 1e-4 && b < ms[i] - 1e-4) {
                    line.points.push_back(
                        pointAt(std::span(pts).subspan(i - 1, 2), std::span(ms).subspan(i - 1, 2), b));
                    line.measure_m.push_back(b);
                }
            }
        }
        line.points.push_back(pts[i]);
        line.measure_m.push_back(ms[i]);
    }
    line.version = 1;
    return s;
}

float arrowHalfWidth(const ArrowShape& s, double m, bool casing, bool after) {
    // Just beyond or just before `m`, so a width that jumps there is read on the side asked for.
    const double x = after ? m + 1e-3 : m - 1e-3;
    const double head_length = s.tip_m - s.head_m;
    if (head_length <= 0.0) return 0.0f;
    const double slope = double(s.head_half_width_m) / head_length;  // half width lost per metre
    if (!casing) {
        if (x < s.head_m) return s.half_width_m;
        return static_cast<float>(std::max(0.0, (s.tip_m - x) * slope));
    }
    double w = 0.0;
    if (x < s.head_m) w = double(s.half_width_m) + s.casing_m;
    if (x >= s.head_m - s.casing_m) w = std::max(w, (s.casing_tip_m - x) * slope);
    return static_cast<float>(std::max(w, 0.0));
}

}  // namespace navmap::render
