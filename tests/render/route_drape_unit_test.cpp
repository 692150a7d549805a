// SPDX-License-Identifier: Apache-2.0
// The route draped per tile (seed 3.6.1; tile_mesh.h drapeRoute/morphRoute): every piece lies on
// one triangle of the tile's grid, the route is clipped to the tile square, measures follow the
// draped vertices, and the pieces follow the terrain's geomorph. The work per tile is bounded by
// the tile and the view's tolerance, not by the route's points (RouteDrapeOptions).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "navmap/render/terrain_lod.h"
#include "tile_mesh.h"

namespace {

using namespace navmap;
using namespace navmap::render;

// A 1000 m tile at (20000, -15000) with a hill in the middle and 33 samples per side.
std::shared_ptr<map::Tile> hillTile() {
    auto t = std::make_shared<map::Tile>();
    t->id = {6, 3, 4};
    t->origin_x = 20000.0;
    t->origin_y = -15000.0;
    t->size_m = 1000.0;
    const int n = 33;
    t->dem.size = n;
    t->dem.spacing_m = 1000.0f / (n - 1);
    t->dem.coverage = 1.0f;
    for (int r = 0; r < n; ++r) {
        for (int c = 0; c < n; ++c) {
            const double x = c * 1000.0 / (n - 1) - 500.0, y = r * 1000.0 / (n - 1) - 450.0;
            t->dem.heights.push_back(static_cast<float>(
                900.0 + 250.0 * std::exp(-(x * x + y * y) / (2.0 * 180.0 * 180.0)) + 7.0 * std::sin(x / 23.0)));
        }
    }
    return t;
}

// A route with sparse points: from south-west outside the tile, over the hill, out to the east.
RouteGeometry sparseRoute() {
    RouteGeometry r;
    const glm::dvec2 pts[] = {{19800.0, -14900.0}, {20500.0, -14550.0}, {21300.0, -14420.0}};
    double m = 0.0;
    for (std::size_t i = 0; i < std::size(pts); ++i) {
        if (i > 0) m += glm::length(pts[i] - pts[i - 1]);
        r.points.emplace_back(pts[i].x, pts[i].y, 0.0);  // z is not used for drawing
        r.measure_m.push_back(m);
    }
    r.version = 1;
    return r;
}

// Which triangle of the grid holds p (HeightGrid's split), with a tolerance for points on edges.
bool inTriangle(const HeightGrid& g, glm::dvec2 a, glm::dvec2 b) {
    // Both ends inside one triangle <=> the midpoint's triangle contains both (up to 1e-4 m).
    const glm::dvec2 m = 0.5 * (a + b);
    const int col = std::clamp(static_cast<int>(std::floor(m.x / g.spacing)), 0, g.size - 2);
    const int row = std::clamp(static_cast<int>(std::floor(m.y / g.spacing)), 0, g.size - 2);
    const double fx = m.x / g.spacing - col, fy = m.y / g.spacing - row;
    const bool upper = fy > fx;
    auto inside = [&](glm::dvec2 p) {
        const double u = p.x / g.spacing - col, v = p.y / g.spacing - row;
        const double e = 1e-4 / g.spacing;
        if (u < -e || v < -e || u > 1 + e || v > 1 + e) return false;
        return upper ? v >= u - e : v <= u + e;
    };
    return inside(a) && inside(b);
}

TEST(RouteDrape, PiecesLieOnTheTilesTrianglesAtTheirBarycentricHeight) {
    const auto tile = hillTile();
    const TileMesh mesh = buildTileMesh(*tile);
    const HeightGrid grid = mesh.grid();
    const RouteGeometry route = sparseRoute();
    const auto pieces = drapeRoute(route, mesh.origin, grid, mesh.ancestorGrids());
    ASSERT_GT(pieces.size(), 40u) << "a vertex at every crossed triangle edge";
    for (const RoutePiece& p : pieces) {
        for (const glm::vec3 q : {p.p0, p.p1}) {
            ASSERT_GE(q.x, -1e-3f);
            ASSERT_LE(q.x, 1000.0f + 1e-3f);
            ASSERT_GE(q.y, -1e-3f);
            ASSERT_LE(q.y, 1000.0f + 1e-3f);
            // z is the grid's barycentric height (HeightGrid::heightAt is the triangulated surface).
            ASSERT_NEAR(q.z, grid.heightAt(q.x, q.y), 2e-3) << q.x << ", " << q.y;
        }
        // Both ends on one triangle: the straight piece lies in that triangle's plane.
        ASSERT_TRUE(inTriangle(grid, glm::dvec2(p.p0), glm::dvec2(p.p1))) << p.p0.x << "," << p.p0.y;
        const glm::dvec3 mid = 0.5 * (glm::dvec3(p.p0) + glm::dvec3(p.p1));
        ASSERT_NEAR(mid.z, grid.heightAt(mid.x, mid.y), 2e-3);
        // Geomorph target: the parent surface at the same place.
        for (int j = 0; j < kMorphLevels; ++j) {
            ASSERT_NEAR(p.ancestor_z0[j], mesh.ancestorGrid(j).heightAt(p.p0.x, p.p0.y), 2e-3);
            ASSERT_NEAR(p.ancestor_z1[j], mesh.ancestorGrid(j).heightAt(p.p1.x, p.p1.y), 2e-3);
        }
    }
    // The hill top is on the route: the draped route climbs it (a straight line between the sparse
    // points would run 200 m below).
    float top = 0.0f;
    for (const RoutePiece& p : pieces) top = std::max(top, p.p0.z);
    EXPECT_GT(top, 1100.0f);
}

TEST(RouteDrape, ClippedToTheTileWithMeasuresAlongTheRoute) {
    const auto tile = hillTile();
    const TileMesh mesh = buildTileMesh(*tile);
    const RouteGeometry route = sparseRoute();
    const auto pieces = drapeRoute(route, mesh.origin, mesh.grid(), mesh.ancestorGrids());
    ASSERT_FALSE(pieces.empty());
    // Measure = distance along the route from its first point, at every draped vertex.
    auto expected = [&](glm::vec3 local) {
        const glm::dvec2 p(local.x + mesh.origin.x, local.y + mesh.origin.y);
        for (std::size_t i = 0; i + 1 < route.points.size(); ++i) {
            const glm::dvec2 a(route.points[i]), b(route.points[i + 1]);
            const glm::dvec2 d = b - a;
            const double t = glm::dot(p - a, d) / glm::dot(d, d);
            const glm::dvec2 q = a + t * d;
            if (t >= -1e-6 && t <= 1 + 1e-6 && glm::length(p - q) < 1e-2)
                return route.measure_m[i] + t * glm::length(d);
        }
        return -1.0;
    };
    double length = 0.0;
    for (const RoutePiece& p : pieces) {
        ASSERT_NEAR(p.measure0, expected(p.p0), 0.05);
        ASSERT_NEAR(p.measure1, expected(p.p1), 0.05);
        EXPECT_GE(p.measure1, p.measure0);
        length += glm::length(glm::dvec2(p.p1) - glm::dvec2(p.p0));
    }
    // The pieces cover exactly the part of the route inside the tile: it enters on the west edge
    // (x = 0) and leaves on the east edge (x = 1000).
    EXPECT_NEAR(pieces.front().p0.x, 0.0f, 1e-3f);
    EXPECT_NEAR(pieces.back().p1.x, 1000.0f, 1e-3f);
    EXPECT_NEAR(length, pieces.back().measure1 - pieces.front().measure0, 0.05);
    // A tile the route does not touch gets nothing.
    EXPECT_TRUE(
        drapeRoute(route, mesh.origin + glm::dvec3(0.0, 5000.0, 0.0), mesh.grid(), mesh.ancestorGrids()).empty());
}

TEST(RouteDrape, PiecesFollowTheTerrainMorph) {
    const auto tile = hillTile();
    const TileMesh mesh = buildTileMesh(*tile);
    const auto pieces = drapeRoute(sparseRoute(), mesh.origin, mesh.grid(), mesh.ancestorGrids());
    std::vector<RoadInstance> out;
    TileMorph m;
    for (int j = 0; j < kMorphLevels; ++j) {
        m.end_m[j] = 3000.0f * float(1 << j);
        m.start_m[j] = 0.7f * m.end_m[j];
    }
    // Camera right above the tile: before the morph, own surface.
    morphRoute(pieces, m, glm::vec2(500.0f, 500.0f), out);
    ASSERT_EQ(out.size(), pieces.size());
    for (std::size_t i = 0; i < out.size(); ++i) EXPECT_EQ(out[i].p0.z, pieces[i].p0.z);
    // Just beyond the first range: the parent surface, exactly what the morphed terrain shows.
    morphRoute(pieces, m, glm::vec2(-3050.0f, 500.0f), out);
    for (std::size_t i = 0; i < out.size(); ++i) {
        EXPECT_EQ(out[i].p0.z, pieces[i].ancestor_z0[0]);
        EXPECT_EQ(out[i].p1.z, pieces[i].ancestor_z1[0]);
        EXPECT_EQ(out[i].measure0, pieces[i].measure0);
    }
    // Far away: the coarsest carried level.
    morphRoute(pieces, m, glm::vec2(-40000.0f, 500.0f), out);
    for (std::size_t i = 0; i < out.size(); ++i) EXPECT_EQ(out[i].p0.z, pieces[i].ancestor_z0[kMorphLevels - 1]);
    // In between: the vertex's own factor (the terrain shader's rule).
    const glm::vec2 eye(-1800.0f, 500.0f);
    morphRoute(pieces, m, eye, out);
    int between = 0;
    for (std::size_t i = 0; i < out.size(); ++i) {
        const glm::vec2 d = glm::vec2(pieces[i].p0) - eye;
        const float f = morphFactor(morphDistance(d.x, d.y, m), m.start_m[0], m.end_m[0]);
        ASSERT_LT(morphDistance(d.x, d.y, m), m.start_m[1]) << "only the first slot is active here";
        EXPECT_NEAR(out[i].p0.z, pieces[i].p0.z + f * (pieces[i].ancestor_z0[0] - pieces[i].p0.z), 1e-3f);
        if (f > 0.0f && f < 1.0f) ++between;
    }
    EXPECT_GT(between, 10);
}

// `points` points zig-zagging east-west across the hill tile, from 200 m beyond its west edge to
// 200 m beyond its east one, from its south edge to its north one: every segment crosses it.
RouteGeometry zigZagRoute(int points) {
    RouteGeometry r;
    double m = 0.0;
    for (int i = 0; i < points; ++i) {
        const glm::dvec2 p(20000.0 + (i % 2 == 0 ? -200.0 : 1200.0), -15000.0 + 1000.0 * i / (points - 1));
        if (i > 0) m += glm::length(p - glm::dvec2(r.points.back()));
        r.points.emplace_back(p.x, p.y, 0.0);
        r.measure_m.push_back(m);
    }
    r.version = 1;
    return r;
}

// The widest north-south gap (metres) between the pieces over the tile's 1000 m, its edges included.
double widestGap(const std::vector<RoutePiece>& pieces) {
    std::vector<double> y{0.0, 1000.0};
    for (const RoutePiece& p : pieces) y.insert(y.end(), {p.p0.y, p.p1.y});
    std::sort(y.begin(), y.end());
    double gap = 0.0;
    for (std::size_t i = 1; i < y.size(); ++i) gap = std::max(gap, y[i] - y[i - 1]);
    return gap;
}

TEST(RouteDrape, AZigZagRouteCostsTheTileNotItsPointCount) {
    const auto tile = hillTile();
    const TileMesh mesh = buildTileMesh(*tile);
    RouteDrapeCounts c2k, c20k;
    const auto p2k = drapeRoute(zigZagRoute(2000), mesh.origin, mesh.grid(), mesh.ancestorGrids(), {}, &c2k);
    const auto p20k = drapeRoute(zigZagRoute(20000), mesh.origin, mesh.grid(), mesh.ancestorGrids(), {}, &c20k);
    EXPECT_EQ(c2k.segments_clipped, 1999u) << "every segment crosses the tile";
    EXPECT_EQ(c20k.segments_clipped, 19999u);
    // Drawn unbounded, each segment would be draped at every triangle edge it crosses (about 100
    // pieces over 1000 m of 32 cells): 200,000 and 2,000,000 pieces. Bounded by the tile instead.
    EXPECT_TRUE(c2k.coverage_used);
    EXPECT_TRUE(c20k.coverage_used);
    EXPECT_LE(p2k.size(), kRoutePiecesPerTile);
    EXPECT_LE(p20k.size(), kRoutePiecesPerTile);
    EXPECT_LT(p20k.size(), p2k.size() * 3 / 2) << "ten times the points, about the same work";
    EXPECT_LT(c20k.segments_draped, c2k.segments_draped * 3 / 2) << c2k.segments_draped << " " << c20k.segments_draped;
    EXPECT_EQ(c20k.segments_draped + c20k.segments_covered + c20k.segments_over_limit, c20k.segments_clipped);
    EXPECT_GT(c20k.segments_covered, 19000u) << "most segments lie where the route is drawn already";
    // What is drawn still fills the tile as the zig-zag does, from its south edge to its north
    // one, in stripes no further apart than the coarsest coverage cells.
    EXPECT_EQ(c20k.segments_over_limit, 0u);
    EXPECT_LE(widestGap(p2k), 1000.0 / kRouteCoverageCellsCoarsest + 1.0);
    EXPECT_LE(widestGap(p20k), 1000.0 / kRouteCoverageCellsCoarsest + 1.0);
    // Still pieces of the route: on the tile's triangles, measures from the route.
    for (const RoutePiece& p : p20k) {
        ASSERT_NEAR(p.p0.z, mesh.grid().heightAt(p.p0.x, p.p0.y), 2e-3);
        ASSERT_GE(p.measure1, p.measure0);
    }
}

TEST(RouteDrape, ADenseRouteIsSimplifiedToTheTolerance) {
    const auto tile = hillTile();
    const TileMesh mesh = buildTileMesh(*tile);
    // The sparse route given again with a point every 5 cm on it (about 33,000 points): within
    // any tolerance of the sparse one.
    const RouteGeometry sparse = sparseRoute();
    RouteGeometry dense;
    for (std::size_t i = 0; i + 1 < sparse.points.size(); ++i) {
        const glm::dvec3 a = sparse.points[i], b = sparse.points[i + 1];
        const auto steps = static_cast<int>(glm::length(b - a) / 0.05);
        for (int k = 0; k < steps; ++k) {
            const double t = double(k) / steps;
            dense.points.push_back(glm::mix(a, b, t));
            dense.measure_m.push_back(sparse.measure_m[i] + t * (sparse.measure_m[i + 1] - sparse.measure_m[i]));
        }
    }
    dense.points.push_back(sparse.points.back());
    dense.measure_m.push_back(sparse.measure_m.back());
    dense.version = 1;
    ASSERT_GT(dense.points.size(), 30000u);
    const auto expected = drapeRoute(sparse, mesh.origin, mesh.grid(), mesh.ancestorGrids());
    RouteDrapeOptions options;
    options.tolerance_m = 1.0 / 32.0;
    RouteDrapeCounts counts;
    const auto pieces = drapeRoute(dense, mesh.origin, mesh.grid(), mesh.ancestorGrids(), options, &counts);
    EXPECT_GT(counts.segments_clipped, 20000u);
    EXPECT_EQ(counts.segments_draped, 2u) << "the two segments of the sparse route inside the tile";
    EXPECT_FALSE(counts.coverage_used);
    ASSERT_EQ(pieces.size(), expected.size());
    for (std::size_t i = 0; i < pieces.size(); ++i) {
        EXPECT_NEAR(glm::length(pieces[i].p0 - expected[i].p0), 0.0f, 2e-3f) << i;
        EXPECT_NEAR(glm::length(pieces[i].p1 - expected[i].p1), 0.0f, 2e-3f) << i;
        EXPECT_NEAR(pieces[i].measure0, expected[i].measure0, 0.05f) << i;
    }
    // Without simplifying, every 5 cm segment is a piece: the bound keeps it to the tile's.
    RouteDrapeCounts unsimplified;
    const auto bounded = drapeRoute(dense, mesh.origin, mesh.grid(), mesh.ancestorGrids(), {}, &unsimplified);
    EXPECT_TRUE(unsimplified.coverage_used);
    EXPECT_LE(bounded.size(), kRoutePiecesPerTile);
}

TEST(RouteDrape, ANormalRouteIsDrapedWhole) {
    // A route far under the bound is draped as it is, however it is simplified: no segment left out.
    const auto tile = hillTile();
    const TileMesh mesh = buildTileMesh(*tile);
    RouteDrapeCounts counts;
    RouteDrapeOptions options;
    options.tolerance_m = 1.0 / 32.0;
    const auto pieces = drapeRoute(sparseRoute(), mesh.origin, mesh.grid(), mesh.ancestorGrids(), options, &counts);
    EXPECT_EQ(pieces.size(), drapeRoute(sparseRoute(), mesh.origin, mesh.grid(), mesh.ancestorGrids()).size());
    EXPECT_EQ(counts.segments_clipped, 2u);
    EXPECT_EQ(counts.segments_draped, 2u);
    EXPECT_EQ(counts.segments_covered + counts.segments_over_limit, 0u);
    EXPECT_FALSE(counts.coverage_used);
}

}  // namespace

// A tunnel from 300 m to 700 m along the route: the pieces are split where it begins and ends,
// those between are marked, the rest not, and none is lost (the measures still join up).
TEST(RouteDrape, PiecesAreSplitAndMarkedWhereTheRouteRunsInATunnel) {
    const auto tile = hillTile();
    const TileMesh mesh = buildTileMesh(*tile);
    RouteGeometry route = sparseRoute();
    const auto plain = drapeRoute(route, mesh.origin, mesh.grid(), mesh.ancestorGrids());
    route.tunnels_m = {{300.0, 700.0}, {2000.0, 2100.0}};  // the second one lies beyond the tile
    const auto pieces = drapeRoute(route, mesh.origin, mesh.grid(), mesh.ancestorGrids());
    ASSERT_FALSE(pieces.empty());
    EXPECT_EQ(pieces.size(), plain.size() + 2) << "one split at each end of the tunnel";
    std::size_t tunnel = 0;
    bool begins = false, ends = false;
    for (std::size_t i = 0; i < pieces.size(); ++i) {
        const RoutePiece& p = pieces[i];
        const float mid = 0.5f * (p.measure0 + p.measure1);
        EXPECT_EQ(p.tunnel, mid > 300.0f && mid < 700.0f) << "piece " << i << " at " << mid << " m";
        tunnel += p.tunnel ? 1 : 0;
        begins = begins || std::abs(p.measure0 - 300.0f) < 1e-3f;
        ends = ends || std::abs(p.measure1 - 700.0f) < 1e-3f;
        if (i > 0 && pieces[i - 1].measure1 == p.measure0) {
            EXPECT_EQ(pieces[i - 1].p1, p.p0) << "piece " << i;
        }
    }
    EXPECT_TRUE(begins && ends) << "no piece boundary at the tunnel's ends";
    EXPECT_GT(tunnel, 10u);
    // Morphed, a tunnel piece's class says so (roads_geo.vert dashes it).
    std::vector<RoadInstance> out;
    morphRoute(pieces, TileMorph{}, glm::vec2(0.0f), out);
    ASSERT_EQ(out.size(), pieces.size());
    for (std::size_t i = 0; i < out.size(); ++i) EXPECT_EQ(out[i].road_class, pieces[i].tunnel ? 1.0f : 0.0f);
}
