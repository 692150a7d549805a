// SPDX-License-Identifier: Apache-2.0
#include "lifecycle.h"

#include <poll.h>
#include <signal.h>
#include <sys/signalfd.h>
#include <systemd/sd-daemon.h>
#include <unistd.h>

#include <cerrno>
#include <cstdint>
#include <cstring>
#include <stdexcept>

#include "navmap/ipc/net/sys_error.h"

namespace navmap::daemon {

Signals::Signals() {
    sigset_t set;
    sigemptyset(&set);
    sigaddset(&set, SIGTERM);
    sigaddset(&set, SIGINT);
    sigaddset(&set, SIGHUP);
    // Threads started later inherit the mask, so only the signalfd sees these signals.
    if (pthread_sigmask(SIG_BLOCK, &set, nullptr) != 0) throw std::runtime_error("pthread_sigmask(SIG_BLOCK) failed");
    m_fd.reset(signalfd(-1, &set, SFD_NONBLOCK | SFD_CLOEXEC));
    if (!m_fd.valid()) throw std::runtime_error(ipc::net::sysError("signalfd", "TERM|INT|HUP"));
    // A client that vanishes mid-write must not kill the daemon.
    ::signal(SIGPIPE, SIG_IGN);
}

Signals::~Signals() = default;

SignalEvent Signals::wait(std::chrono::milliseconds timeout) {
    pollfd p{m_fd.get(), POLLIN, 0};
    const int n = ::poll(&p, 1, static_cast<int>(std::max<std::int64_t>(0, timeout.count())));
    if (n <= 0) return SignalEvent::None;
    signalfd_siginfo info{};
    SignalEvent event = SignalEvent::None;
    while (::read(m_fd.get(), &info, sizeof info) == static_cast<ssize_t>(sizeof info)) {
        if (info.ssi_signo == SIGHUP) {
            if (event == SignalEvent::None) event = SignalEvent::Reload;
        } else {
            event = SignalEvent::Stop;  // a stop wins over a reload
        }
    }
    return event;
}

SystemdNotifier::SystemdNotifier() {
    const char* socket = std::getenv("NOTIFY_SOCKET");
    m_active = socket && *socket;
    std::uint64_t usec = 0;
    if (m_active && sd_watchdog_enabled(0, &usec) > 0) m_watchdog = std::chrono::microseconds(usec);
}

void SystemdNotifier::notify(const std::string& text) {
    if (m_active) sd_notify(0, text.c_str());
}

void SystemdNotifier::ready(const std::string& s) { notify("READY=1\nSTATUS=" + s); }
void SystemdNotifier::status(const std::string& s) { notify("STATUS=" + s); }
void SystemdNotifier::reloading() { notify("RELOADING=1"); }
void SystemdNotifier::stopping() { notify("STOPPING=1"); }

void SystemdNotifier::watchdog() {
    if (!m_active || m_watchdog.count() == 0) return;
    const auto now = std::chrono::steady_clock::now();
    if (now - m_last_ping < m_watchdog / 2) return;
    m_last_ping = now;
    notify("WATCHDOG=1");
}

}  // namespace navmap::daemon
