// SPDX-License-Identifier: Apache-2.0
#include "navmap/ipc/client/reconnecting_client.h"

#include <algorithm>
#include <thread>

namespace navmap::ipc {

using Clock = std::chrono::steady_clock;

ReconnectingClient::ReconnectingClient(ReconnectOptions options)
    : m_options(std::move(options)), m_backoff(m_options.initial_backoff, m_options.max_backoff) {}

ReconnectingClient::~ReconnectingClient() = default;

void ReconnectingClient::dropConnection(const std::string& why) {
    m_client.reset();  // closes the socket and unmaps the ring
    m_last_error = why;
    ++m_stats.disconnects;
    // The next attempt waits the initial delay: a daemon that restarts needs a moment to listen.
    m_backoff.failed(Clock::now());
}

bool ReconnectingClient::ensureConnected(Clock::time_point deadline) {
    while (!m_client) {
        const auto now = Clock::now();
        if (!m_backoff.due(now)) {
            const auto wake = std::min(m_backoff.nextAttempt(), deadline);
            if (wake <= now) {
                return false;
            }
            std::this_thread::sleep_until(wake);
            if (Clock::now() >= deadline && !m_backoff.due(Clock::now())) {
                return false;
            }
            continue;
        }
        const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - now);
        const auto timeout = std::clamp(left, std::chrono::milliseconds(1), m_options.connect_timeout);
        auto c = !m_options.unix_path.empty()
                     ? StreamClient::connectUnix(m_options.unix_path, m_options.request, timeout, m_options.inflate)
                     : StreamClient::connectTcp(m_options.tcp_host, m_options.tcp_port, m_options.request, timeout,
                                                m_options.inflate);
        if (!c) {
            m_last_error = c.error().message;
            ++m_stats.failed_attempts;
            m_backoff.failed(Clock::now());
            if (Clock::now() >= deadline) {
                return false;
            }
            continue;
        }
        m_client = std::move(c).value();
        m_backoff.succeeded();
        ++m_stats.connects;
    }
    return true;
}

bool ReconnectingClient::receive(ReceivedFrame* copy, HeldFrame* held, std::chrono::milliseconds timeout) {
    const auto deadline = Clock::now() + timeout;
    for (;;) {
        if (!ensureConnected(deadline)) {
            return false;
        }
        const auto left = std::max(std::chrono::duration_cast<std::chrono::milliseconds>(deadline - Clock::now()),
                                   std::chrono::milliseconds(0));
        auto r = held != nullptr ? m_client->nextHeld(*held, left) : m_client->next(*copy, left);
        if (!r) {
            dropConnection(r.error().message);
            if (Clock::now() >= deadline) {
                return false;
            }
            continue;
        }
        return r.value();
    }
}

bool ReconnectingClient::next(ReceivedFrame& out, std::chrono::milliseconds timeout) {
    return receive(&out, nullptr, timeout);
}

bool ReconnectingClient::nextHeld(HeldFrame& out, std::chrono::milliseconds timeout) {
    if (!m_options.request.hold) {
        m_last_error = "nextHeld() needs request.hold (payload shm: the frame stays in the shared-memory ring)";
        return false;
    }
    return receive(nullptr, &out, timeout);
}

bool ReconnectingClient::release() {
    if (!m_client) {
        return false;
    }
    auto r = m_client->release();
    if (!r) {
        dropConnection(r.error().message);
        return false;
    }
    if (!r.value()) {
        ++m_stats.held_overwritten;
    }
    return r.value();
}

}  // namespace navmap::ipc
