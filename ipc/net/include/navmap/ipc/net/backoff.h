// SPDX-License-Identifier: Apache-2.0
#pragma once
// Backoff: exponential retry delay (initial, doubling, capped) for re-opening a CAN interface that
// went down or does not exist yet. Deterministic (no jitter) so that tests can check the schedule;
// uses the steady clock. Part of libnavmap-client (ReconnectingClient reconnects with it).

#include <chrono>
#include <cstdint>

#include "navmap/ipc/net/client_api.h"

namespace navmap::ipc {

class NAVMAP_CLIENT_API Backoff {
public:
    using Clock = std::chrono::steady_clock;

    explicit Backoff(std::chrono::milliseconds initial = std::chrono::milliseconds(100),
                     std::chrono::milliseconds maximum = std::chrono::milliseconds(5000), double factor = 2.0);

    /// Records a failure at `now`: the next attempt is due after the current delay, which then grows.
    void failed(Clock::time_point now) noexcept;
    /// Records a success: the delay goes back to the initial value and an attempt is due at once.
    void succeeded() noexcept;
    /// True when an attempt may be made at `now`.
    bool due(Clock::time_point now) const noexcept { return now >= m_next_attempt; }
    Clock::time_point nextAttempt() const noexcept { return m_next_attempt; }
    /// The delay that the next failure will wait.
    std::chrono::milliseconds currentDelay() const noexcept { return m_delay; }
    std::uint64_t failures() const noexcept { return m_failures; }

private:
    std::chrono::milliseconds m_initial;
    std::chrono::milliseconds m_maximum;
    double m_factor;
    std::chrono::milliseconds m_delay;
    Clock::time_point m_next_attempt{};
    std::uint64_t m_failures = 0;
};

}  // namespace navmap::ipc
