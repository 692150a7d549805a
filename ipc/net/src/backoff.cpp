// SPDX-License-Identifier: Apache-2.0
#include "navmap/ipc/net/backoff.h"

#include <algorithm>

namespace navmap::ipc {

Backoff::Backoff(std::chrono::milliseconds initial, std::chrono::milliseconds maximum, double factor)
    : m_initial(std::max(initial, std::chrono::milliseconds(1))),
      m_maximum(std::max(maximum, m_initial)),
      m_factor(std::max(factor, 1.0)),
      m_delay(m_initial) {}

void Backoff::failed(Clock::time_point now) noexcept {
    ++m_failures;
    m_next_attempt = now + m_delay;
    const auto grown =
        std::chrono::milliseconds(static_cast<std::int64_t>(static_cast<double>(m_delay.count()) * m_factor));
    m_delay = std::min(std::max(grown, m_delay), m_maximum);
}

void Backoff::succeeded() noexcept {
    m_delay = m_initial;
    m_next_attempt = Clock::time_point{};
}

}  // namespace navmap::ipc
