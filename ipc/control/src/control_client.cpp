// SPDX-License-Identifier: Apache-2.0
#include "navmap/ipc/control/control_client.h"

#include <poll.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include <nlohmann/json.hpp>

#include "navmap/ipc/net/recv_before.h"
#include "navmap/ipc/net/sys_error.h"

namespace navmap::ipc {

using net::sysError;
using net::UniqueFd;

namespace {

using Clock = std::chrono::steady_clock;

int remainingMs(Clock::time_point deadline) {
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - Clock::now()).count();
    return left < 0 ? 0 : static_cast<int>(left);
}

}  // namespace

Result<ControlClient> ControlClient::connect(const std::string& path) {
    sockaddr_un addr{};
    addr.sun_family = AF_UNIX;
    if (path.empty() || path.size() >= sizeof(addr.sun_path)) {
        return Error{"control socket path \"" + path + "\": invalid length"};
    }
    std::memcpy(addr.sun_path, path.data(), path.size());
    UniqueFd fd(::socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0));
    if (!fd.valid()) {
        return Error{sysError("socket", path)};
    }
    if (::connect(fd.get(), reinterpret_cast<const sockaddr*>(&addr), sizeof addr) != 0) {
        return Error{sysError("connect", path)};
    }
    return ControlClient(std::move(fd), path);
}

ControlClient::~ControlClient() = default;
ControlClient::ControlClient(ControlClient&& other) noexcept = default;
ControlClient& ControlClient::operator=(ControlClient&& other) noexcept = default;

Status ControlClient::send(std::string_view line, std::chrono::milliseconds timeout) {
    std::string data(line);
    data.push_back('\n');
    const auto deadline = Clock::now() + timeout;
    std::size_t off = 0;
    while (off < data.size()) {
        pollfd p{m_fd.get(), POLLOUT, 0};
        const int n = ::poll(&p, 1, remainingMs(deadline));
        if (n < 0 && errno == EINTR) {
            continue;
        }
        if (n <= 0) {
            return Error{n == 0 ? "send(" + m_path + "): timed out" : sysError("poll", m_path)};
        }
        const ssize_t w = ::send(m_fd.get(), data.data() + off, data.size() - off, MSG_NOSIGNAL | MSG_DONTWAIT);
        if (w < 0) {
            if (errno == EINTR || errno == EAGAIN) {
                continue;
            }
            return Error{sysError("send", m_path)};
        }
        off += static_cast<std::size_t>(w);
    }
    return {};
}

Result<std::string> ControlClient::readLine(std::chrono::milliseconds timeout) {
    const auto deadline = Clock::now() + timeout;
    for (;;) {
        const auto nl = m_buffer.find('\n');
        if (nl != std::string::npos) {
            std::string line = m_buffer.substr(0, nl);
            m_buffer.erase(0, nl + 1);
            return line;
        }
        char buf[65536];
        const auto got = net::recvBefore(m_fd.get(), buf, sizeof buf, deadline, m_path);
        if (got.kind == net::Received::Kind::TimedOut) {
            return Error{"recv(" + m_path + "): timed out"};
        }
        if (got.kind == net::Received::Kind::Failed) {
            return Error{got.error};
        }
        m_buffer.append(buf, got.bytes);
    }
}

Result<std::string> ControlClient::request(std::string_view line, std::chrono::milliseconds timeout) {
    const auto deadline = Clock::now() + timeout;
    if (auto st = send(line, timeout); !st.ok()) {
        // A server that refuses this peer answers and closes at once, possibly before the request
        // is out: then the send fails, but the answer is waiting to be read.
        auto answer = readLine(std::chrono::milliseconds(0));
        return answer.ok() ? answer : Result<std::string>(Error{st.message()});
    }
    for (;;) {
        auto r = readLine(std::chrono::milliseconds(remainingMs(deadline)));
        if (!r.ok()) {
            return r;
        }
        const auto j = nlohmann::json::parse(r.value(), nullptr, false);
        if (j.is_object() && j.contains("event")) {
            m_events.push_back(std::move(r.value()));
            continue;
        }
        return r;
    }
}

Result<std::string> ControlClient::nextEvent(std::chrono::milliseconds timeout) {
    if (!m_events.empty()) {
        std::string e = std::move(m_events.front());
        m_events.pop_front();
        return e;
    }
    return readLine(timeout);
}

}  // namespace navmap::ipc
