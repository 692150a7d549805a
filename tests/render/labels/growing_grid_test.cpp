// SPDX-License-Identifier: Apache-2.0
#include <cmath>
#include <random>
#include <set>
#include <vector>

#include <gtest/gtest.h>

#include "navmap/render/labels/growing_grid.h"

namespace nl = navmap::render::labels;

namespace {

bool touch(glm::vec2 ca, glm::vec2 ha, glm::vec2 cb, glm::vec2 hb) {
    return std::abs(ca.x - cb.x) <= ha.x + hb.x && std::abs(ca.y - cb.y) <= ha.y + hb.y;
}

}  // namespace

// Between inserts, every query reports exactly the boxes inserted so far that touch it, once:
// small boxes, boxes over many cells, far outliers and queries larger than the screen.
TEST(GrowingGrid, QueriesBetweenInsertsMatchBruteForceExactlyOnce) {
    for (unsigned seed = 1; seed <= 3; ++seed) {
        std::mt19937 rng(seed);
        std::uniform_real_distribution<float> pos(0.0F, 1000.0F);
        std::uniform_real_distribution<float> w(5.0F, 80.0F);
        std::uniform_real_distribution<float> h(4.0F, 12.0F);
        nl::GrowingGrid grid;
        grid.reset({40.0F, 20.0F});
        std::vector<glm::vec2> c;
        std::vector<glm::vec2> hh;
        for (int i = 0; i < 300; ++i) {
            glm::vec2 center{pos(rng), pos(rng)};
            glm::vec2 half{w(rng), h(rng)};
            if (i % 50 == 7) half = {400.0F, 300.0F};  // over many cells
            if (i % 97 == 3) center = {1e6F, -1e6F};   // far outside
            const glm::vec2 qc{pos(rng), pos(rng)};
            const glm::vec2 qh = i % 40 == 0 ? glm::vec2(2000.0F) : glm::vec2(w(rng), h(rng));
            std::multiset<std::uint32_t> got;
            grid.query(qc, qh, [&](std::uint32_t k) { got.insert(k); });
            std::multiset<std::uint32_t> expected;
            for (std::uint32_t k = 0; k < c.size(); ++k) {
                if (touch(qc, qh, c[k], hh[k])) expected.insert(k);
            }
            ASSERT_EQ(got, expected) << "seed " << seed << " query " << i;
            grid.insert(center, half);
            c.push_back(center);
            hh.push_back(half);
        }
        EXPECT_EQ(grid.size(), 300U);
        EXPECT_GT(grid.cellsVisited(), 0U);
        grid.reset({40.0F, 20.0F});  // empty again
        int after = 0;
        grid.query({500.0F, 500.0F}, glm::vec2(5000.0F), [&](std::uint32_t) { ++after; });
        EXPECT_EQ(after, 0);
        EXPECT_EQ(grid.cellsVisited(), 0U);
    }
}
