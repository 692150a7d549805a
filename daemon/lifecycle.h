// SPDX-License-Identifier: Apache-2.0
#pragma once
// Process lifecycle: SIGTERM/SIGINT/SIGHUP delivered through a signalfd (the handlers do nothing
// at all; the loop reads the fd), and systemd notification (Type=notify: READY, STATUS,
// WATCHDOG, RELOADING, STOPPING) through sd_notify.

#include <chrono>
#include <string>

#include "navmap/ipc/net/unique_fd.h"

namespace navmap::daemon {

enum class SignalEvent { None, Stop, Reload };

class Signals {
public:
    /// Blocks SIGTERM, SIGINT and SIGHUP for the process and opens a signalfd for them.
    /// Throws std::runtime_error naming the failing call.
    Signals();
    ~Signals();
    Signals(const Signals&) = delete;
    Signals& operator=(const Signals&) = delete;

    /// Waits up to `timeout` for a signal; returns what arrived (None on timeout).
    SignalEvent wait(std::chrono::milliseconds timeout);
    [[nodiscard]] int fd() const { return m_fd.get(); }

private:
    ipc::net::UniqueFd m_fd;
};

class SystemdNotifier {
public:
    SystemdNotifier();
    /// True when started by systemd with NOTIFY_SOCKET.
    [[nodiscard]] bool active() const { return m_active; }
    /// The watchdog interval systemd asked for (WatchdogSec), zero when none.
    [[nodiscard]] std::chrono::microseconds watchdogInterval() const { return m_watchdog; }

    void ready(const std::string& status);
    void status(const std::string& status);
    /// Sends WATCHDOG=1 at most every half interval; the caller calls it only while healthy.
    void watchdog();
    void reloading();
    void stopping();

private:
    void notify(const std::string& text);
    bool m_active = false;
    std::chrono::microseconds m_watchdog{0};
    std::chrono::steady_clock::time_point m_last_ping{};
};

}  // namespace navmap::daemon
