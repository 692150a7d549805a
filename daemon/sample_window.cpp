// SPDX-License-Identifier: Apache-2.0
#include "sample_window.h"

#include "navmap/common/percentile.h"

#include <algorithm>
#include <cmath>
#include <vector>

namespace navmap::daemon {

void SampleWindow::add(double value) {
    m_values.push_back(value);
    if (m_values.size() > m_capacity) m_values.pop_front();
}

double SampleWindow::quantile(double q) const {
    return percentile(std::vector<double>(m_values.begin(), m_values.end()), q);
}

}  // namespace navmap::daemon
