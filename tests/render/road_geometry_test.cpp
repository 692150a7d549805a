// SPDX-License-Identifier: Apache-2.0
// Unit tests of the road geometry: the analytic caps (seed 3.4), barycentric clipping against
// the terrain grid (seed 3.6.1) and distance-based width scaling (seed 3.6.3).
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "navmap/render/road_style.h"
#include "road_draping.h"

namespace {

using namespace navmap::render;

TEST(RoadCaps, PointsAgainstTheAnalyticCircle) {
    // Segment of length d = 30 between caps of radius w/2 = 5: the quad spans 40 along the road,
    // x in [-(L + 1), L + 1] half widths with L = 3.
    const float d = 30.0f, w = 10.0f;
    const float l = capHalfLength(d, w);
    EXPECT_FLOAT_EQ(l, 3.0f);
    // The seed's quad-local x_q in [-1, 1] maps to road coordinates s = x_q * (d + w) / 2; the cap
    // circle is centred on the end point s = d / 2 with radius w / 2. Check a dense set of points,
    // and that the seed's own form x_cap = (|x_q| - 1) / h + 1 agrees (h = w / (d + w)).
    const float h = w / (d + w);
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    int in_cap_region = 0;
    for (int i = 0; i < 20000; ++i) {
        const float xq = u(rng), y = u(rng);
        const float s = std::abs(xq) * (d + w) / 2.0f;  // distance along the road from the centre
        const float t = std::abs(y) * w / 2.0f;         // distance across
        bool expected;
        if (s <= d / 2.0f) {
            expected = true;  // body of the segment
        } else {
            ++in_cap_region;
            expected = std::hypot(s - d / 2.0f, t) <= w / 2.0f;
        }
        // Skip points within float noise of the circle or the cap's start.
        if (s > d / 2.0f && std::abs(std::hypot(s - d / 2.0f, t) - w / 2.0f) < 1e-3f) continue;
        const float x = xq * (l + 1.0f);
        EXPECT_EQ(capCovers(x, y, l), expected) << "x_q=" << xq << " y=" << y;
        EXPECT_NEAR(std::abs(x) - l, (std::abs(xq) - 1.0f) / h + 1.0f, 1e-5f) << "x_q=" << xq;
    }
    EXPECT_GT(in_cap_region, 1000);
    // The quad's corners are outside the caps; the tip on the axis is inside.
    EXPECT_FALSE(capCovers(l + 1.0f, 1.0f, l));
    EXPECT_FALSE(capCovers(-0.99f * (l + 1.0f), -0.99f, l));
    EXPECT_TRUE(capCovers(0.999f * (l + 1.0f), 0.0f, l));
    EXPECT_TRUE(capCovers(0.0f, 0.999f, l));
}

TEST(RoadWidth, ScalesOnlyBeyondTheThreshold) {
    EXPECT_FLOAT_EQ(distanceWidthScale(100.0f, 1500.0f, 12.0f), 1.0f);
    EXPECT_FLOAT_EQ(distanceWidthScale(1500.0f, 1500.0f, 12.0f), 1.0f);
    EXPECT_FLOAT_EQ(distanceWidthScale(3000.0f, 1500.0f, 12.0f), 2.0f);
    EXPECT_FLOAT_EQ(distanceWidthScale(6000.0f, 1500.0f, 12.0f), 4.0f);
    EXPECT_FLOAT_EQ(distanceWidthScale(1e6f, 1500.0f, 12.0f), 12.0f);
    // Continuous at the threshold and monotonic.
    float last = 0.0f;
    for (float dist = 0.0f; dist < 40000.0f; dist += 250.0f) {
        const float s = distanceWidthScale(dist, 1500.0f, 12.0f);
        EXPECT_GE(s, last);
        last = s;
    }
}

// The least on-screen width (roads_geo.vert): the upper side moves by at most the least width
// times the pass's share of the fill, so that the casing keeps its share.
TEST(RoadWidth, LeastWidthGrowsEveryPassInProportion) {
    EXPECT_FLOAT_EQ(leastWidthGrowthPx(1.1f, 12.0f, 12.0f), 1.1f);                  // the fill itself
    EXPECT_FLOAT_EQ(leastWidthGrowthPx(1.1f, 16.0f, 12.0f), 1.1f * 16.0f / 12.0f);  // its casing
    EXPECT_FLOAT_EQ(leastWidthGrowthPx(0.0f, 16.0f, 12.0f), 0.0f);                  // turned off
    EXPECT_FLOAT_EQ(leastWidthGrowthPx(1.1f, 16.0f, 0.0f), 0.0f);                   // no fill: nothing drawn
}

// seed 7.3: a selected class keeps its whole width while its true width covers at least 1.5 times
// its threshold on screen, none at or below the threshold, and fades linearly in between.
TEST(RoadWidth, SelectedClassFadesOutContinuouslyBelowItsThreshold) {
    const float focal = 600.0f, width = 2.0f;  // true width on screen: 1200 / distance pixels
    const SelectionFade fade = selectionFade(width, 1.0f, focal);
    EXPECT_FLOAT_EQ(fade.at(700.0f), 1.0f);     // 1.71 px
    EXPECT_FLOAT_EQ(fade.at(800.0f), 1.0f);     // 1.5 px
    EXPECT_NEAR(fade.at(960.0f), 0.5f, 1e-5f);  // 1.25 px
    EXPECT_FLOAT_EQ(fade.at(1200.0f), 0.0f);    // 1 px
    EXPECT_FLOAT_EQ(fade.at(5000.0f), 0.0f);
    EXPECT_NEAR(fade.goneFromM(), 1200.0f, 1e-2f);  // where RoadPass::cull leaves the pieces out
    EXPECT_FLOAT_EQ(fade.at(0.0f), 1.0f);           // at the eye
    // Not selected, or the selection off: drawn at every distance.
    EXPECT_FLOAT_EQ(selectionFade(width, 0.0f, focal).at(1e6f), 1.0f);
    EXPECT_TRUE(std::isinf(selectionFade(width, 0.0f, focal).goneFromM()));
    const RoadStyle day = RoadStyle::day();
    const auto path = static_cast<std::size_t>(kStyledRoadClasses - 1);
    EXPECT_FLOAT_EQ(selectionFades(day, focal, true)[path].at(1e6f), 0.0f);
    EXPECT_FLOAT_EQ(selectionFades(day, focal, false)[path].at(1e6f), 1.0f);
    // Monotonic, and continuous: no step between 1 m apart bigger than the slope allows.
    float last = 1.0f;
    for (float d = 1.0f; d < 2000.0f; d += 1.0f) {
        const float f = fade.at(d);
        EXPECT_LE(f, last) << d;
        EXPECT_LT(last - f, 0.01f) << "a jump at " << d << " m";
        last = f;
    }
}

// The default style leaves only minor classes out, the ones below tertiary, and the least
// important first.
TEST(RoadWidth, DefaultStyleSelectsOnlyMinorClasses) {
    const RoadStyle s = RoadStyle::day();
    for (int c = 0; c <= 4; ++c) EXPECT_EQ(s.classes[static_cast<std::size_t>(c)].select_px, 0.0f) << "class " << c;
    for (int c = 5; c < kStyledRoadClasses; ++c) {
        const RoadClassStyle& k = s.classes[static_cast<std::size_t>(c)];
        EXPECT_GT(k.select_px, 0.0f) << "class " << c;
        // The distance where it is gone, at a focal length of 600 px, does not grow with the class.
        const RoadClassStyle& more = s.classes[static_cast<std::size_t>(c - 1)];
        if (more.select_px > 0.0f) {
            EXPECT_LE(k.width_m / k.select_px, more.width_m / more.select_px) << "class " << c;
        }
    }
}

struct Grid {
    std::vector<float> heights;
    HeightGrid view;
};

Grid bumpyGrid(int size, double spacing) {
    Grid g;
    g.heights.resize(static_cast<std::size_t>(size) * size);
    for (int r = 0; r < size; ++r)
        for (int c = 0; c < size; ++c)
            g.heights[static_cast<std::size_t>(r) * size + c] =
                static_cast<float>(1000.0 + 40.0 * std::sin(r * 0.7) * std::cos(c * 1.3) + 3.0 * r);
    g.view = HeightGrid{size, spacing, g.heights.data()};
    return g;
}

bool onGridEdge(const glm::dvec3& p, double spacing) {
    const double fx = p.x / spacing, fy = p.y / spacing;
    const double ex = std::abs(fx - std::round(fx)), ey = std::abs(fy - std::round(fy));
    // Diagonals of the split: y - x = integer within a cell.
    const double d = (p.y - p.x) / spacing;
    const double ed = std::abs(d - std::round(d));
    return ex < 1e-7 || ey < 1e-7 || ed < 1e-7;
}

TEST(RoadClipping, InsertedVerticesLieOnTriangleEdgesAndOnTheSurface) {
    const Grid g = bumpyGrid(17, 30.0);
    const std::vector<glm::dvec2> line{{5.0, 7.0}, {200.0, 130.0}, {410.0, 55.0}};
    const auto draped = drapePolyline(g.view, line);
    ASSERT_GT(draped.size(), 30u) << "crossing ~20 cells must insert many vertices";
    // The original vertices are kept, in order.
    EXPECT_DOUBLE_EQ(draped.front().x, 5.0);
    EXPECT_DOUBLE_EQ(draped.back().x, 410.0);
    bool saw_middle = false;
    for (const auto& p : draped) saw_middle |= (p.x == 200.0 && p.y == 130.0);
    EXPECT_TRUE(saw_middle);
    for (std::size_t i = 1; i + 1 < draped.size(); ++i) {
        const auto& p = draped[i];
        if ((p.x == 200.0 && p.y == 130.0)) continue;
        EXPECT_TRUE(onGridEdge(p, 30.0)) << "vertex " << i << " (" << p.x << ", " << p.y << ") is not on an edge";
    }
    // Every vertex lies on the triangulated surface, and so does the midpoint of every piece
    // (a piece within one triangle is planar).
    for (std::size_t i = 0; i < draped.size(); ++i) {
        EXPECT_NEAR(draped[i].z, g.view.heightAt(draped[i].x, draped[i].y), 1e-6);
        if (i + 1 < draped.size()) {
            const glm::dvec3 m = (draped[i] + draped[i + 1]) * 0.5;
            EXPECT_NEAR(m.z, g.view.heightAt(m.x, m.y), 1e-6) << "piece " << i << " leaves the surface";
        }
    }
}

TEST(RoadClipping, PreservesThePolylineShape) {
    const Grid g = bumpyGrid(33, 10.0);
    const std::vector<glm::dvec2> line{{3.0, 3.0}, {300.0, 17.0}, {150.0, 290.0}};
    const auto draped = drapePolyline(g.view, line);
    // Every inserted vertex lies on one of the original segments (2D distance ~0).
    for (const auto& p : draped) {
        double best = 1e9;
        for (std::size_t i = 0; i + 1 < line.size(); ++i) {
            const glm::dvec2 a = line[i], b = line[i + 1], q{p.x, p.y};
            const double t = std::clamp(glm::dot(q - a, b - a) / glm::dot(b - a, b - a), 0.0, 1.0);
            best = std::min(best, glm::length(q - (a + t * (b - a))));
        }
        EXPECT_LT(best, 1e-7);
    }
    // Same 2D length as the input.
    double in_len = 0, out_len = 0;
    for (std::size_t i = 0; i + 1 < line.size(); ++i) in_len += glm::length(line[i + 1] - line[i]);
    for (std::size_t i = 0; i + 1 < draped.size(); ++i)
        out_len += glm::length(glm::dvec2(draped[i + 1]) - glm::dvec2(draped[i]));
    EXPECT_NEAR(out_len, in_len, 1e-6);
}

TEST(RoadClipping, AxisAlignedAndVertexCrossingLinesTerminate) {
    const Grid g = bumpyGrid(9, 10.0);
    // Along a grid line, along a diagonal through vertices, and starting on a vertex.
    for (const auto& line : std::vector<std::vector<glm::dvec2>>{{{0.0, 20.0}, {80.0, 20.0}},
                                                                 {{0.0, 0.0}, {80.0, 80.0}},
                                                                 {{10.0, 10.0}, {10.0, 70.0}},
                                                                 {{80.0, 80.0}, {0.0, 0.0}},
                                                                 {{40.0, 40.0}, {40.0, 40.0}}}) {
        const auto draped = drapePolyline(g.view, line);
        ASSERT_FALSE(draped.empty());
        for (const auto& p : draped) EXPECT_NEAR(p.z, g.view.heightAt(p.x, p.y), 1e-6);
        EXPECT_LE(draped.size(), 40u);
    }
}

TEST(RoadMerging, APlaneNeedsOnePiecePerStraightSegment) {
    // A tilted plane: draping cuts the road at every triangle edge, yet every piece lies on one plane.
    std::vector<float> heights(17 * 17);
    for (int r = 0; r < 17; ++r)
        for (int c = 0; c < 17; ++c)
            heights[static_cast<std::size_t>(r) * 17 + c] = static_cast<float>(500.0 + 2.0 * c - 1.5 * r);
    const HeightGrid plane{17, 30.0, heights.data()};
    const std::vector<glm::dvec2> line{{5.0, 7.0}, {200.0, 130.0}, {410.0, 55.0}};
    const auto draped = drapePolyline(plane, line);
    ASSERT_GT(draped.size(), 30u);
    const auto merged = mergeDrapedPieces(draped, 0.01);
    ASSERT_EQ(merged.size(), 3u) << "the corner of the polyline must stay, every edge crossing must go";
    EXPECT_DOUBLE_EQ(merged[1].x, 200.0);
    EXPECT_DOUBLE_EQ(merged[1].y, 130.0);
    for (const auto& p : merged) EXPECT_NEAR(p.z, plane.heightAt(p.x, p.y), 1e-6);
}

TEST(RoadMerging, StaysWithinTheToleranceOfTheSurfaceAndKeepsTheShape) {
    const Grid g = bumpyGrid(33, 10.0);
    const std::vector<glm::dvec2> line{{3.0, 3.0}, {300.0, 17.0}, {150.0, 290.0}};
    const auto draped = drapePolyline(g.view, line);
    std::size_t previous = draped.size() + 1;
    for (const double tol : {0.0, 0.5, 3.0, 20.0}) {
        const auto merged = mergeDrapedPieces(draped, tol);
        ASSERT_GE(merged.size(), 3u);
        EXPECT_LT(merged.size(), previous) << "a larger tolerance merges more (tolerance " << tol << ")";
        previous = merged.size();
        // Every draped vertex (on the surface) lies on the merged 2D path, within the tolerance
        // of the height of the merged piece over it.
        for (const auto& p : draped) {
            double best = 1e9, dz = 0.0;
            for (std::size_t k = 0; k + 1 < merged.size(); ++k) {
                const glm::dvec2 a(merged[k]), b(merged[k + 1]);
                const double t = std::clamp(glm::dot(glm::dvec2(p) - a, b - a) / glm::dot(b - a, b - a), 0.0, 1.0);
                const double d = glm::length(glm::dvec2(p) - (a + t * (b - a)));
                if (d < best) {
                    best = d;
                    dz = std::abs(merged[k].z + t * (merged[k + 1].z - merged[k].z) - p.z);
                }
            }
            EXPECT_LT(best, 0.011);
            EXPECT_LE(dz, tol + 1e-9) << "tolerance " << tol << " at (" << p.x << ", " << p.y << ")";
        }
    }
}

TEST(RoadClipping, GridIndicesUseTheSameSplit) {
    const auto idx = gridTriangleIndices(3);
    ASSERT_EQ(idx.size(), 2u * 2u * 6u);
    // First cell: SW(0) SE(1) NE(4), SW(0) NE(4) NW(3).
    EXPECT_EQ(idx[0], 0u);
    EXPECT_EQ(idx[1], 1u);
    EXPECT_EQ(idx[2], 4u);
    EXPECT_EQ(idx[3], 0u);
    EXPECT_EQ(idx[4], 4u);
    EXPECT_EQ(idx[5], 3u);
}

}  // namespace
