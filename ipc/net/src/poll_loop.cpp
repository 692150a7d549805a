// SPDX-License-Identifier: Apache-2.0
#include "navmap/ipc/net/poll_loop.h"

#include <poll.h>
#include <sys/eventfd.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdint>
#include <utility>

#include "navmap/ipc/net/sys_error.h"

namespace navmap::ipc::net {

PollLoop::PollLoop(std::string name) : m_name(std::move(name)) {}

PollLoop::~PollLoop() = default;

Status PollLoop::open() {
    m_wake_fd.reset(::eventfd(0, EFD_NONBLOCK | EFD_CLOEXEC));
    if (!m_wake_fd.valid()) {
        return Error{sysError("eventfd", m_name + " wake-up")};
    }
    return {};
}

void PollLoop::close() {
    m_entries.clear();
    m_wake_fd.reset();
}

void PollLoop::wake() noexcept {
    // eventfd writes never block (the counter saturates far away).
    const std::uint64_t one = 1;
    [[maybe_unused]] const auto n = ::write(m_wake_fd.get(), &one, sizeof(one));
}

void PollLoop::add(int fd, Interest interest, Handler handler) {
    m_entries.push_back(std::make_unique<Entry>(Entry{fd, std::move(interest), std::move(handler)}));
}

void PollLoop::remove(int fd) {
    for (auto& e : m_entries) {
        if (e->fd == fd && !e->removed) {
            e->removed = true;  // erased before the next poll: a running dispatch keeps its indices
            return;
        }
    }
}

void PollLoop::buildPollSet() {
    std::erase_if(m_entries, [](const auto& e) { return e->removed; });
    m_pfds.clear();
    m_pfds.push_back({m_wake_fd.get(), POLLIN, 0});
    for (const auto& e : m_entries) {
        m_pfds.push_back({e->fd, e->interest(), 0});
    }
}

void PollLoop::dispatch(std::size_t polled) {
    if ((m_pfds[0].revents & POLLIN) != 0) {
        std::uint64_t v = 0;
        [[maybe_unused]] const auto r = ::read(m_wake_fd.get(), &v, sizeof(v));
    }
    for (std::size_t i = 0; i < polled; ++i) {
        Entry& e = *m_entries[i];
        const short revents = m_pfds[i + 1].revents;
        if (revents != 0 && !e.removed) {
            e.handler(revents);
        }
    }
}

Status PollLoop::runOnce(std::chrono::milliseconds timeout) {
    buildPollSet();
    const std::size_t polled = m_entries.size();
    const int n = ::poll(m_pfds.data(), m_pfds.size(), static_cast<int>(timeout.count()));
    if (n < 0) {
        return errno == EINTR ? Status{} : Status{Error{sysError("poll", m_name)}};
    }
    if (n > 0) {
        dispatch(polled);
    }
    return {};
}

}  // namespace navmap::ipc::net
