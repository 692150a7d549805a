// SPDX-License-Identifier: Apache-2.0
#include "sample_window.h"

#include <algorithm>
#include <cmath>
#include <vector>

namespace navmap::daemon {

void SampleWindow::add(double value) {
    m_values.push_back(value);
    if (m_values.size() > m_capacity) m_values.pop_front();
}

double SampleWindow::quantile(double q) const {
    if (m_values.empty()) return 0.0;
    std::vector<double> v(m_values.begin(), m_values.end());
    std::sort(v.begin(), v.end());
    return v[std::min(v.size() - 1, static_cast<std::size_t>(std::lround(q * static_cast<double>(v.size() - 1))))];
}

}  // namespace navmap::daemon
