// SPDX-License-Identifier: Apache-2.0
#pragma once
// The one quantile definition the status, the tools and the benchmarks report: the nearest rank
// on the sorted samples, index round(q (n - 1)), so q = 0.5 of an even count is the upper middle
// value and q = 1 the largest.

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <iterator>
#include <vector>

namespace navmap {

/// The q-quantile (q in [0, 1]) of `values`; 0 for no values.
[[nodiscard]] inline double percentile(std::vector<double> values, double q) {
    if (values.empty()) return 0.0;
    const auto last = static_cast<double>(values.size() - 1);
    const auto k = static_cast<std::size_t>(std::lround(std::clamp(q, 0.0, 1.0) * last));
    const auto nth = values.begin() + static_cast<std::iterator_traits<decltype(values.begin())>::difference_type>(k);
    std::nth_element(values.begin(), nth, values.end());
    return *nth;
}

}  // namespace navmap
