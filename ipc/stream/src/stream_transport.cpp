// SPDX-License-Identifier: Apache-2.0
#include "stream_transport.h"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <sys/socket.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <nlohmann/json.hpp>
#include <utility>

#include "navmap/ipc/net/poll_loop.h"
#include "navmap/ipc/net/sys_error.h"

namespace navmap::ipc::stream_detail {

std::string jsonErrorLine(const std::string& message) {
    return "{\"ok\":false,\"error\":" +
           nlohmann::json(message).dump(-1, ' ', false, nlohmann::json::error_handler_t::replace) + "}\n";
}

bool hasControlBytes(const std::string& s) {
    return std::any_of(s.begin(), s.end(), [](char ch) {
        const auto b = static_cast<unsigned char>(ch);
        return (b < 0x20 && b != '\t' && b != '\r' && b != '\n') || b == 0x7F;
    });
}

std::string peerAddressKey(const sockaddr_storage& ss) {
    char text[INET6_ADDRSTRLEN] = {};
    if (ss.ss_family == AF_INET) {
        sockaddr_in in4{};
        std::memcpy(&in4, &ss, sizeof(in4));
        return ::inet_ntop(AF_INET, &in4.sin_addr, text, sizeof(text)) ? text : "";
    }
    if (ss.ss_family != AF_INET6) {
        return {};
    }
    sockaddr_in6 in6{};
    std::memcpy(&in6, &ss, sizeof(in6));
    if (IN6_IS_ADDR_V4MAPPED(&in6.sin6_addr)) {
        in_addr v4{};
        std::memcpy(&v4, in6.sin6_addr.s6_addr + 12, sizeof(v4));
        return ::inet_ntop(AF_INET, &v4, text, sizeof(text)) ? text : "";
    }
    in6_addr prefix = in6.sin6_addr;
    std::memset(prefix.s6_addr + 8, 0, 8);
    return ::inet_ntop(AF_INET6, &prefix, text, sizeof(text)) ? std::string(text) + "/64" : "";
}

StreamTransport::StreamTransport(Via via, ClientHub& hub) : m_hub(hub), m_via(via) {}

StreamTransport::~StreamTransport() = default;

Status StreamTransport::listen(PollLoop& loop) {
    auto fd = openListener();
    if (!fd) {
        return Error{fd.error().message};
    }
    if (fd.value() < 0) {
        return {};  // not configured
    }
    m_listen_fd.reset(fd.value());
    loop.add(
        fd.value(), [] { return static_cast<short>(POLLIN); },
        [this](short revents) {
            if ((revents & POLLIN) != 0) {
                acceptAll();
            }
        });
    return {};
}

void StreamTransport::close() { m_listen_fd.reset(); }

std::string StreamTransport::handshakeTimeoutReply(const std::string& why) const { return jsonErrorLine(why); }

std::string StreamTransport::firstFrameTimeoutReply(const StreamConn&, const std::string&) const { return {}; }

std::optional<Refusal> StreamTransport::checkPeer(int, std::optional<uid_t>*) { return std::nullopt; }

std::string StreamTransport::refusalReply(const std::string& message) const { return jsonErrorLine(message); }

void StreamTransport::acceptAll() {
    for (;;) {
        sockaddr_storage ss{};
        socklen_t len = sizeof(ss);
        net::UniqueFd fd(
            ::accept4(m_listen_fd.get(), reinterpret_cast<sockaddr*>(&ss), &len, SOCK_NONBLOCK | SOCK_CLOEXEC));
        if (!fd.valid()) {
            if (errno != EAGAIN && errno != EWOULDBLOCK && errno != EINTR) {
                m_hub.stats().setLastError(net::sysError("accept", acceptObject()));
            }
            return;
        }
        admit(std::move(fd), peerAddressKey(ss));
    }
}

void StreamTransport::admit(net::UniqueFd fd, const std::string& address) {
    std::string peer = std::string(viaName(m_via)) + "#" + std::to_string(fd.get());
    if (!address.empty()) {
        peer += " (" + address + ")";
    }
    m_hub.stats().count(&FrameServerStats::accepted);
    // Who may connect, and how many: refusals are answered and closed at once, so they never
    // hold a slot (a refused peer that keeps reconnecting costs one accept each time).
    std::optional<uid_t> uid;
    auto refusal = checkPeer(fd.get(), &uid);
    if (!refusal) {
        refusal = m_hub.checkCaps(m_via, uid, address);
    }
    if (refusal) {
        refuse(fd, peer, *refusal);
        return;
    }
    m_hub.add(makeConn(std::move(fd), peer, uid, address));
}

std::unique_ptr<StreamConn> StreamTransport::makeConn(net::UniqueFd fd, const std::string& peer,
                                                      std::optional<uid_t> uid, const std::string& address) const {
    if (m_via != Via::Unix) {
        // A small kernel queue keeps frames fresh (a slow reader gets the newest frame, not a
        // backlog) and lets a reader that stopped show up as a stall within a few frames.
        const int sndbuf = 256 * 1024;
        ::setsockopt(fd.get(), SOL_SOCKET, SO_SNDBUF, &sndbuf, sizeof(sndbuf));
        const int one = 1;
        ::setsockopt(fd.get(), IPPROTO_TCP, TCP_NODELAY, &one, sizeof(one));
    }
    auto c = std::make_unique<StreamConn>();
    c->fd = std::move(fd);
    c->via = m_via;
    c->uid = uid;
    c->address = address;
    c->phase = firstPhase();
    c->since = c->last_progress = Clock::now();
    c->peer = uid ? peer + " (uid " + std::to_string(*uid) + ")" : peer;
    return c;
}

void StreamTransport::refuse(net::UniqueFd& fd, const std::string& peer, const Refusal& refusal) {
    m_hub.stats().countError(refusal.counter, peer + ": refused: " + refusal.message);
    // Read what already arrived (usually the handshake), so closing does not turn into a reset
    // that could destroy the answer on its way; then answer without waiting and close.
    char buf[4096];
    for (int i = 0; i < 16 && ::recv(fd.get(), buf, sizeof(buf), MSG_DONTWAIT) > 0; ++i) {}
    const std::string reply = refusalReply(refusal.message);
    [[maybe_unused]] const auto n = ::send(fd.get(), reply.data(), reply.size(), MSG_NOSIGNAL | MSG_DONTWAIT);
    ::shutdown(fd.get(), SHUT_WR);
    fd.reset();
    m_hub.stats().count(&FrameServerStats::disconnects);
}

}  // namespace navmap::ipc::stream_detail
