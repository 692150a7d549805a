// SPDX-License-Identifier: Apache-2.0
// navmap::percentile: the nearest rank on the sorted samples, index round(q (n - 1)).
#include "navmap/common/percentile.h"

#include <gtest/gtest.h>

#include <numeric>
#include <vector>

namespace {

TEST(Percentile, NoSamplesIsZero) { EXPECT_EQ(navmap::percentile({}, 0.5), 0.0); }

TEST(Percentile, NearestRankOnTheSortedSamples) {
    const std::vector<double> unsorted{7.0, 1.0, 5.0, 3.0};
    EXPECT_EQ(navmap::percentile(unsorted, 0.0), 1.0);
    EXPECT_EQ(navmap::percentile(unsorted, 0.5), 5.0);  // round(1.5) = 2: the upper middle value
    EXPECT_EQ(navmap::percentile(unsorted, 1.0), 7.0);
    std::vector<double> hundred(100);
    std::iota(hundred.rbegin(), hundred.rend(), 1.0);    // 100 .. 1
    EXPECT_EQ(navmap::percentile(hundred, 0.99), 99.0);  // round(98.01) = 98
    EXPECT_EQ(navmap::percentile(hundred, 0.95), 95.0);  // round(94.05) = 94
}

TEST(Percentile, AQuantileOutsideZeroToOneIsClamped) {
    const std::vector<double> v{2.0, 4.0, 6.0};
    EXPECT_EQ(navmap::percentile(v, -1.0), 2.0);
    EXPECT_EQ(navmap::percentile(v, 3.0), 6.0);
}

}  // namespace
