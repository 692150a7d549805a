// SPDX-License-Identifier: Apache-2.0
#pragma once
// A bounded window of the newest samples (frame times, latencies) for percentiles in status and
// /metrics. Render-thread only.

#include <cstddef>
#include <deque>

namespace navmap::daemon {

class SampleWindow {
public:
    /// Keeps the newest `capacity` samples.
    explicit SampleWindow(std::size_t capacity = 600) : m_capacity(capacity) {}

    void add(double value);
    /// The q-quantile (0..1, nearest rank) of the samples in the window; 0 when empty.
    [[nodiscard]] double quantile(double q) const;
    [[nodiscard]] std::size_t size() const { return m_values.size(); }

private:
    std::size_t m_capacity;
    std::deque<double> m_values;
};

}  // namespace navmap::daemon
