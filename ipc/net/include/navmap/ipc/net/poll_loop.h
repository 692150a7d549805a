// SPDX-License-Identifier: Apache-2.0
#pragma once
// PollLoop: the one poll() loop of navmap's socket servers (the frame server, the control
// socket), in the manner of Redis ae.c. Descriptors are registered with a callback that says
// which events they wait for (asked before every poll) and a callback for what arrived; an
// eventfd lets other threads (render, encoder, publish, stop) wake it. Callbacks run on the
// loop's thread in registration order; a descriptor added by a callback is polled from the next
// round on.

#include <poll.h>

#include <chrono>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "navmap/ipc/net/result.h"
#include "navmap/ipc/net/unique_fd.h"

namespace navmap::ipc::net {

class PollLoop {
public:
    using Interest = std::function<short()>;             ///< poll() events to wait for (POLLIN | ...)
    using Handler = std::function<void(short revents)>;  ///< called when revents != 0

    /// `name` goes into error texts: "poll(frame server): ...".
    explicit PollLoop(std::string name);
    ~PollLoop();
    PollLoop(const PollLoop&) = delete;
    PollLoop& operator=(const PollLoop&) = delete;

    /// Makes the wake-up eventfd; "eventfd(<name> wake-up): ..." on failure.
    Status open();
    /// Closes the eventfd and forgets every registration.
    void close();
    /// Any thread: the next (or current) runOnce() returns without waiting. Never blocks.
    void wake() noexcept;

    void add(int fd, Interest interest, Handler handler);
    /// Forgets `fd` (safe inside a callback); the caller closes it.
    void remove(int fd);

    /// One round: waits up to `timeout` (or a wake-up) and runs the callbacks of the descriptors
    /// with events. An Error when poll() fails (EINTR is none).
    Status runOnce(std::chrono::milliseconds timeout);

private:
    struct Entry {
        int fd = -1;
        Interest interest;
        Handler handler;
        bool removed = false;
    };

    void buildPollSet();
    void dispatch(std::size_t polled);

    std::string m_name;
    net::UniqueFd m_wake_fd;
    std::vector<std::unique_ptr<Entry>> m_entries;  // stable addresses: callbacks may add
    std::vector<pollfd> m_pfds;
};

}  // namespace navmap::ipc::net
