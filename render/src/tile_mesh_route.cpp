// SPDX-License-Identifier: Apache-2.0
// The route draped onto a tile's terrain grid, its geomorphing, and the roads' level of detail
// (tile_mesh.h).
#include "tile_mesh.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <utility>

#include "navmap/map/geometry.h"
#include "navmap/render/terrain_lod.h"

namespace navmap::render {

namespace {

// A point of the route in tile-local metres with its distance along the route.
struct RoutePoint {
    glm::dvec2 p;
    double measure_m = 0.0;
};

// The route's runs over the square [0, e]^2 (tile-local): each a polyline of two points or more,
// split where the route leaves the square. `clipped` counts the segments overlapping it.
std::vector<std::vector<RoutePoint>> routeRunsInSquare(const RouteGeometry& route, const glm::dvec3& origin, double e,
                                                       std::size_t& clipped) {
    std::vector<std::vector<RoutePoint>> runs;
    bool open_end = false;  // the last run ends where its segment ends (not cut by the square)
    std::size_t last_segment = 0;
    for (std::size_t i = 0; i + 1 < route.points.size(); ++i) {
        const glm::dvec2 a(route.points[i].x - origin.x, route.points[i].y - origin.y);
        const glm::dvec2 b(route.points[i + 1].x - origin.x, route.points[i + 1].y - origin.y);
        if (std::max(a.x, b.x) < 0.0 || std::min(a.x, b.x) > e || std::max(a.y, b.y) < 0.0 || std::min(a.y, b.y) > e)
            continue;
        // Liang-Barsky clip of a -> b to the tile square.
        const glm::dvec2 d = b - a;
        double t0 = 0.0, t1 = 1.0;
        bool inside = true;
        const double p[4] = {-d.x, d.x, -d.y, d.y};
        const double q[4] = {a.x, e - a.x, a.y, e - a.y};
        for (int k = 0; k < 4 && inside; ++k) {
            if (p[k] == 0.0) {
                inside = q[k] >= 0.0;
            } else {
                const double t = q[k] / p[k];
                if (p[k] < 0.0)
                    t0 = std::max(t0, t);
                else
                    t1 = std::min(t1, t);
            }
        }
        if (!inside || t1 - t0 <= 1e-12) continue;
        if (glm::length(d) * (t1 - t0) < 1e-6) continue;
        ++clipped;
        const double m0 = route.measure_m[i], m1 = route.measure_m[i + 1];
        const RoutePoint q0{a + t0 * d, m0 + (m1 - m0) * t0};
        const RoutePoint q1{a + t1 * d, m0 + (m1 - m0) * t1};
        if (runs.empty() || !open_end || last_segment + 1 != i || t0 > 0.0) runs.push_back({q0});
        runs.back().push_back(q1);
        open_end = t1 >= 1.0;
        last_segment = i;
    }
    return runs;
}

double chordDistance(const glm::dvec2& p, const glm::dvec2& a, const glm::dvec2& b) {
    const glm::dvec2 ab = b - a;
    const double len2 = glm::dot(ab, ab);
    const double t = len2 > 0.0 ? std::clamp(glm::dot(p - a, ab) / len2, 0.0, 1.0) : 0.0;
    return glm::length(p - (a + t * ab));
}

// Which cells of an n x n raster over [0, e]^2 a segment's centreline passes (sampled every half
// cell), into `cells` (cleared first).
void coverageCells(const RoutePoint& a, const RoutePoint& b, double e, int n, std::vector<std::uint32_t>& cells) {
    cells.clear();
    const double cell = e / n;
    const double len = glm::length(b.p - a.p);
    const auto steps = static_cast<std::size_t>(std::ceil(len / (0.5 * cell))) + 1;
    for (std::size_t k = 0; k <= steps; ++k) {
        const glm::dvec2 p = glm::mix(a.p, b.p, double(k) / double(steps));
        const int c = std::clamp(static_cast<int>(p.x / cell), 0, n - 1);
        const int r = std::clamp(static_cast<int>(p.y / cell), 0, n - 1);
        const auto at = static_cast<std::uint32_t>(r * n + c);
        if (cells.empty() || cells.back() != at) cells.push_back(at);
    }
}

// Whether distance `m` along the route lies in one of its tunnels, and where that changes next
// (infinity: nowhere further on).
std::pair<bool, double> tunnelAt(const RouteGeometry& route, double m) {
    const auto& t = route.tunnels_m;
    // The first tunnel that ends after m.
    const auto it = std::upper_bound(t.begin(), t.end(), m, [](double v, const auto& r) { return v < r.second; });
    if (it == t.end()) return {false, std::numeric_limits<double>::infinity()};
    if (m >= it->first) return {true, it->second};
    return {false, it->first};
}

}  // namespace

std::vector<RoutePiece> drapeRoute(const RouteGeometry& route, const glm::dvec3& origin, const HeightGrid& grid,
                                   const std::array<HeightGrid, kMorphLevels>& ancestors,
                                   const RouteDrapeOptions& options, RouteDrapeCounts* counts) {
    RouteDrapeCounts local;
    RouteDrapeCounts& n = counts ? *counts : local;
    n = {};
    std::vector<RoutePiece> out;
    if (grid.size < 2 || route.points.size() < 2 || route.measure_m.size() != route.points.size()) return out;
    const double e = grid.extent();
    // Clipped to the tile, then each run inside it simplified to the view's tolerance: what is
    // draped depends on the tile and the tolerance, not on how densely the route is given.
    std::vector<std::pair<RoutePoint, RoutePoint>> segments;
    for (const std::vector<RoutePoint>& run : routeRunsInSquare(route, origin, e, n.segments_clipped)) {
        const std::vector<char> keep = map::douglasPeucker(
            run.size(), options.tolerance_m,
            [&](std::size_t k, std::size_t i, std::size_t j) { return chordDistance(run[k].p, run[i].p, run[j].p); });
        std::size_t from = 0;
        for (std::size_t j = 1; j < run.size(); ++j) {
            if (!keep[j]) continue;
            segments.emplace_back(run[from], run[j]);
            from = j;
        }
    }
    // seed 3.6.1: a vertex wherever a segment crosses a triangle edge of this tile's grid. False
    // when the segment would take the pieces over `limit` (nothing of it is added then).
    std::vector<glm::dvec2> seg(2);
    std::vector<RoutePiece> pieces;  // of one segment
    auto drape = [&](const RoutePoint& a, const RoutePoint& b, std::size_t limit) {
        seg[0] = a.p;
        seg[1] = b.p;
        const std::vector<glm::dvec3> draped = drapePolyline(grid, seg);
        if (draped.size() < 2) return true;
        const double len = glm::length(b.p - a.p);
        auto measure_at = [&](const glm::dvec3& v) {
            return a.measure_m +
                   (b.measure_m - a.measure_m) * std::clamp(glm::length(glm::dvec2(v) - a.p) / len, 0.0, 1.0);
        };
        pieces.clear();
        for (std::size_t k = 0; k + 1 < draped.size(); ++k) {
            const glm::dvec3& q0 = draped[k];
            const glm::dvec3& q1 = draped[k + 1];
            const double m0 = measure_at(q0), m1 = measure_at(q1);
            // Split where a tunnel begins or ends: the piece lies on one triangle, so the split
            // point lies on the surface at every level.
            double from = 0.0, m = m0;
            for (;;) {
                const auto [in_tunnel, next_m] = tunnelAt(route, m);
                const double to = next_m < m1 && m1 > m0 ? (next_m - m0) / (m1 - m0) : 1.0;
                const glm::dvec3 s0 = glm::mix(q0, q1, from), s1 = glm::mix(q0, q1, to);
                RoutePiece piece{glm::vec3(s0),
                                 glm::vec3(s1),
                                 {},
                                 {},
                                 static_cast<float>(m),
                                 static_cast<float>(m0 + (m1 - m0) * to),
                                 in_tunnel};
                for (std::size_t j = 0; j < ancestors.size(); ++j) {
                    if (!ancestors[j].heights) continue;
                    piece.ancestor_z0[j] = static_cast<float>(ancestors[j].heightAt(s0.x, s0.y));
                    piece.ancestor_z1[j] = static_cast<float>(ancestors[j].heightAt(s1.x, s1.y));
                }
                pieces.push_back(piece);
                if (to >= 1.0) break;
                from = to;
                m = next_m;
            }
        }
        if (out.size() + pieces.size() > limit) return false;
        out.insert(out.end(), pieces.begin(), pieces.end());
        return true;
    };
    bool fits = true;
    for (const auto& [a, b] : segments) {
        if (!(fits = drape(a, b, options.max_pieces))) break;
    }
    if (fits) {
        n.segments_draped = segments.size();
        return out;
    }
    // Over the bound (a route that crosses the tile again and again): only the segments that
    // draw somewhere the route is not drawn yet, at the coverage raster's resolution, coarser
    // until they fit; at the coarsest, none beyond the bound.
    n.coverage_used = true;
    std::vector<char> covered;
    std::vector<std::uint32_t> cells;
    for (int cells_per_side = kRouteCoverageCells;; cells_per_side /= 2) {
        const bool last_try = cells_per_side <= kRouteCoverageCellsCoarsest;
        out.clear();
        n.segments_draped = n.segments_covered = n.segments_over_limit = 0;
        covered.assign(static_cast<std::size_t>(cells_per_side) * static_cast<std::size_t>(cells_per_side), 0);
        std::size_t covered_count = 0;
        bool full = false;
        for (const auto& [a, b] : segments) {
            if (full) {
                ++n.segments_over_limit;
                continue;
            }
            if (covered_count == covered.size()) {
                ++n.segments_covered;
                continue;
            }
            coverageCells(a, b, e, cells_per_side, cells);
            if (std::all_of(cells.begin(), cells.end(), [&](std::uint32_t c) { return covered[c] != 0; })) {
                ++n.segments_covered;
                continue;
            }
            if (!drape(a, b, options.max_pieces)) {
                full = true;
                ++n.segments_over_limit;
                if (!last_try) break;  // coarser cells
                continue;
            }
            ++n.segments_draped;
            for (const std::uint32_t c : cells) {
                covered_count += covered[c] == 0 ? 1 : 0;
                covered[c] = 1;
            }
        }
        if (!full || last_try) break;
    }
    return out;
}

void morphRoute(std::span<const RoutePiece> pieces, const TileMorph& morph, const glm::vec2& eye_local,
                std::vector<RoadInstance>& out) {
    out.clear();
    out.reserve(pieces.size());
    auto at = [&](glm::vec3 p, const std::array<float, kMorphLevels>& ancestor_z) {
        const glm::vec2 d = glm::vec2(p) - eye_local;
        p.z = morphedHeight(morphDistance(d.x, d.y, morph), morph, p.z, ancestor_z);
        return p;
    };
    for (const RoutePiece& r : pieces) {
        // The route's pieces carry no road class: theirs says whether the piece is in a tunnel
        // (roads_geo.vert draws it dashed).
        out.push_back(
            {at(r.p0, r.ancestor_z0), at(r.p1, r.ancestor_z1), r.tunnel ? 1.0f : 0.0f, 0.0f, r.measure0, r.measure1});
    }
}

int roadLodLevel(float distance_m, float focal_px, float max_error_px) {
    int level = 0;
    for (int k = 1; k < kRoadLods; ++k) {
        if (kRoadLodTolerance[static_cast<std::size_t>(k)] * focal_px <= max_error_px * distance_m) level = k;
    }
    return level;
}

}  // namespace navmap::render
