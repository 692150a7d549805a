// SPDX-License-Identifier: Apache-2.0
#pragma once
// ControlClient: a small blocking client of the control socket (tests, the simulator, tools
// such as navmap-ctl). One thread; every call has a timeout.

#include <chrono>
#include <deque>
#include <string>
#include <string_view>
#include <utility>

#include "navmap/ipc/net/result.h"
#include "navmap/ipc/net/unique_fd.h"

namespace navmap::ipc {

class ControlClient {
public:
    /// Connects to the server's socket: `connect(/run/navmap/control.sock): No such file or directory`.
    static Result<ControlClient> connect(const std::string& path);
    ~ControlClient();
    ControlClient(ControlClient&& other) noexcept;
    ControlClient& operator=(ControlClient&& other) noexcept;
    ControlClient(const ControlClient&) = delete;
    ControlClient& operator=(const ControlClient&) = delete;

    /// Sends one line (a newline is appended).
    Status send(std::string_view line, std::chrono::milliseconds timeout = std::chrono::seconds(5));
    /// Next line from the server (without newline); an error on timeout or when the server closed.
    Result<std::string> readLine(std::chrono::milliseconds timeout = std::chrono::seconds(5));
    /// Sends a request and returns its reply (the next line with an "ok" member); event lines
    /// that arrive first are kept for nextEvent().
    Result<std::string> request(std::string_view line, std::chrono::milliseconds timeout = std::chrono::seconds(5));
    /// Next event line (kept by request() or read now).
    Result<std::string> nextEvent(std::chrono::milliseconds timeout = std::chrono::seconds(5));

    [[nodiscard]] int fd() const { return m_fd.get(); }

private:
    explicit ControlClient(net::UniqueFd fd, std::string path) : m_fd(std::move(fd)), m_path(std::move(path)) {}
    net::UniqueFd m_fd;
    std::string m_path;
    std::string m_buffer;
    std::deque<std::string> m_events;
};

}  // namespace navmap::ipc
