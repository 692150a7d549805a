// SPDX-License-Identifier: Apache-2.0
#include <algorithm>
#include <random>
#include <set>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "navmap/render/labels/spatial_grid.h"

namespace nl = navmap::render::labels;

namespace {

bool touch(glm::vec2 ca, glm::vec2 ha, glm::vec2 cb, glm::vec2 hb) {
    return std::abs(ca.x - cb.x) <= ha.x + hb.x && std::abs(ca.y - cb.y) <= ha.y + hb.y;
}

struct Scene {
    std::vector<glm::vec2> c;
    std::vector<glm::vec2> h;
};

Scene randomScene(unsigned seed, int n, float world) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> pos(0.0F, world);
    std::uniform_real_distribution<float> w(5.0F, 80.0F);
    std::uniform_real_distribution<float> hh(4.0F, 12.0F);
    Scene s;
    for (int i = 0; i < n; ++i) {
        s.c.emplace_back(pos(rng), pos(rng));
        s.h.emplace_back(w(rng), hh(rng));
    }
    // One far outlier and one huge box exercise clipping and multi-cell boxes.
    s.c.emplace_back(1e6F, -1e6F);
    s.h.emplace_back(10.0F, 10.0F);
    s.c.emplace_back(world / 2, world / 2);
    s.h.emplace_back(world / 3, 30.0F);
    return s;
}

}  // namespace

TEST(SpatialGrid, PairsMatchBruteForceExactlyOnce) {
    for (unsigned seed = 1; seed <= 3; ++seed) {
        const Scene s = randomScene(seed, 400, 1000.0F);
        nl::SpatialGrid grid;
        grid.build(s.c, s.h, {60, 20}, {-500, -500}, {1500, 1500});
        std::vector<std::pair<std::uint32_t, std::uint32_t>> got;
        grid.forEachPair([&](std::uint32_t a, std::uint32_t b) { got.emplace_back(a, b); });
        std::set<std::pair<std::uint32_t, std::uint32_t>> expected;
        for (std::uint32_t a = 0; a < s.c.size(); ++a) {
            for (std::uint32_t b = a + 1; b < s.c.size(); ++b) {
                if (touch(s.c[a], s.h[a], s.c[b], s.h[b])) expected.emplace(a, b);
            }
        }
        const std::set<std::pair<std::uint32_t, std::uint32_t>> got_set(got.begin(), got.end());
        EXPECT_EQ(got.size(), got_set.size()) << "a pair was reported twice";
        EXPECT_EQ(got_set, expected);
        for (const auto& [a, b] : got) EXPECT_LT(a, b);
    }
}

TEST(SpatialGrid, QueryMatchesBruteForce) {
    const Scene s = randomScene(7, 300, 800.0F);
    nl::SpatialGrid grid;
    grid.build(s.c, s.h, {50, 20}, {-400, -400}, {1200, 1200});
    std::mt19937 rng(11);
    std::uniform_real_distribution<float> pos(-100.0F, 900.0F);
    for (int q = 0; q < 200; ++q) {
        const glm::vec2 qc{pos(rng), pos(rng)};
        const glm::vec2 qh{30.0F, 10.0F};
        std::vector<std::uint32_t> got;
        grid.query(qc, qh, [&](std::uint32_t i) { got.push_back(i); });
        std::sort(got.begin(), got.end());
        std::vector<std::uint32_t> expected;
        for (std::uint32_t i = 0; i < s.c.size(); ++i) {
            if (touch(qc, qh, s.c[i], s.h[i])) expected.push_back(i);
        }
        EXPECT_EQ(got, expected) << "query " << q;
    }
    // Far away from everything (beyond the clip): finds the outlier only if it touches.
    std::vector<std::uint32_t> far;
    grid.query({1e6F, -1e6F}, {1, 1}, [&](std::uint32_t i) { far.push_back(i); });
    ASSERT_EQ(far.size(), 1U);
    EXPECT_EQ(far[0], 300U);
}

TEST(SpatialGrid, CellCountStaysBounded) {
    const Scene s = randomScene(3, 100, 100000.0F);
    nl::SpatialGrid grid;
    grid.build(s.c, s.h, {1, 1});
    EXPECT_LE(static_cast<double>(grid.columns()) * grid.rows(), 4.0 * 102 + 16);
    nl::SpatialGrid empty;
    empty.build({}, {}, {10, 10});
    int calls = 0;
    empty.forEachPair([&](std::uint32_t, std::uint32_t) { ++calls; });
    empty.query({0, 0}, {5, 5}, [&](std::uint32_t) { ++calls; });
    EXPECT_EQ(calls, 0);
}
