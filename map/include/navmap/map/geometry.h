// SPDX-License-Identifier: Apache-2.0
#pragma once
// Planar geometry used by the compiler: simplification, clipping to tiles, areas, and the
// label anchors of seed 4.4.2. All coordinates are planar metres (PlanarPoint).

#include <cstddef>
#include <span>
#include <utility>
#include <vector>

#include "navmap/map/projection.h"

namespace navmap::map {

/// Axis-aligned box in planar metres.
struct Box {
    double min_x = 0, min_y = 0, max_x = 0, max_y = 0;
    [[nodiscard]] bool contains(PlanarPoint p) const {
        return p.x >= min_x && p.x <= max_x && p.y >= min_y && p.y <= max_y;
    }
    [[nodiscard]] bool intersects(const Box& o) const {
        return min_x <= o.max_x && o.min_x <= max_x && min_y <= o.max_y && o.min_y <= max_y;
    }
};

Box boundsOf(std::span<const PlanarPoint> points);
/// Distance from p to the segment a-b (to a when a == b), metres.
double segmentDistance(PlanarPoint p, PlanarPoint a, PlanarPoint b);

/// Signed area of a ring (not closed: the last point is not a copy of the first); positive
/// when counter-clockwise.
double ringSignedArea(std::span<const PlanarPoint> ring);

/// Barycenter (area centroid) of a polygon given as outer rings and inner rings (holes),
/// orientation ignored (seed 4.4.2: "for an area feature we compute and store its
/// barycenter"). Falls back to the vertex mean for degenerate (zero-area) input.
PlanarPoint polygonBarycenter(std::span<const std::vector<PlanarPoint>> outers,
                              std::span<const std::vector<PlanarPoint>> inners);

/// Point at half the arc length of a polyline (seed 4.4.2 anchor for horizontal line labels).
PlanarPoint polylineCenter(std::span<const PlanarPoint> line);

double polylineLength(std::span<const PlanarPoint> line);

/// Longest straight stretch of a polyline (seed 4.4.2 anchor for rotated line labels):
/// consecutive segments are merged while their direction stays within `max_turn_deg` of the
/// stretch's first segment; returns the end points of the longest stretch.
struct Segment {
    PlanarPoint a, b;
};
Segment longestStraightSegment(std::span<const PlanarPoint> line, double max_turn_deg = 10.0);

/// Douglas-Peucker over the points 0 .. count - 1 of a polyline: whether each is kept (both end
/// points always). `distance(k, i, j)` is how far point k lies from the chord i-j; a range is
/// split at its farthest point while that lies more than `tolerance` away. The kept sets of two
/// tolerances are nested (the larger keeps a subset).
template <typename Distance>
std::vector<char> douglasPeucker(std::size_t count, double tolerance, Distance distance) {
    std::vector<char> keep(count, count <= 2 || tolerance <= 0 ? 1 : 0);
    if (count <= 2 || tolerance <= 0) return keep;
    keep.front() = keep.back() = 1;
    std::vector<std::pair<std::size_t, std::size_t>> stack{{0, count - 1}};
    while (!stack.empty()) {
        const auto [i, j] = stack.back();
        stack.pop_back();
        double worst = -1;
        std::size_t worst_k = i;
        for (std::size_t k = i + 1; k < j; ++k) {
            const double d = distance(k, i, j);
            if (d > worst) {
                worst = d;
                worst_k = k;
            }
        }
        if (worst > tolerance) {
            keep[worst_k] = 1;
            stack.emplace_back(i, worst_k);
            stack.emplace_back(worst_k, j);
        }
    }
    return keep;
}

/// Douglas-Peucker simplification keeping both end points; tolerance in metres.
std::vector<PlanarPoint> simplifyPolyline(std::span<const PlanarPoint> line, double tolerance);
/// Simplification of a closed ring (not repeated first point); may return fewer than 3 points.
std::vector<PlanarPoint> simplifyRing(std::span<const PlanarPoint> ring, double tolerance);

/// Clips a polyline to a box (Liang-Barsky per segment); returns the pieces inside.
std::vector<std::vector<PlanarPoint>> clipPolyline(std::span<const PlanarPoint> line, const Box& box);

/// Clips a ring to a box (Sutherland-Hodgman). The result may contain zero-width bridges along
/// the box edges for concave input; they enclose no area, so odd-winding triangulation ignores them.
std::vector<PlanarPoint> clipRing(std::span<const PlanarPoint> ring, const Box& box);

}  // namespace navmap::map
