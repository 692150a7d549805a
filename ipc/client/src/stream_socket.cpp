// SPDX-License-Identifier: Apache-2.0
#include "navmap/ipc/client/stream_socket.h"

#include <arpa/inet.h>
#include <fcntl.h>
#include <netdb.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <poll.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/un.h>
#include <unistd.h>

#include <cerrno>
#include <cstdint>
#include <cstring>

namespace navmap::ipc::stream_detail {

using net::sysError;
using net::UniqueFd;

std::int64_t realtimeNowNs() noexcept {
    timespec ts{};
    clock_gettime(CLOCK_REALTIME, &ts);
    return static_cast<std::int64_t>(ts.tv_sec) * 1000000000LL + ts.tv_nsec;
}

Result<sockaddr_un> unixAddress(const std::string& path) {
    sockaddr_un addr{};
    addr.sun_family = AF_UNIX;
    if (path.empty() || path.size() >= sizeof(addr.sun_path)) {
        return Error{"socket path '" + path + "': empty or longer than " + std::to_string(sizeof(addr.sun_path) - 1) +
                     " bytes"};
    }
    std::memcpy(addr.sun_path, path.c_str(), path.size() + 1);
    return addr;
}

Result<int> connectUnixSocket(const std::string& path) {
    auto addr = unixAddress(path);
    if (!addr) {
        return addr.error();
    }
    UniqueFd fd(socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0));
    if (!fd.valid()) {
        return Error{sysError("socket", path)};
    }
    if (connect(fd.get(), reinterpret_cast<const sockaddr*>(&addr.value()), sizeof(sockaddr_un)) != 0) {
        return Error{sysError("connect", path)};
    }
    return fd.release();
}

Result<int> connectTcpSocket(const std::string& host, int port, std::chrono::milliseconds timeout) {
    const std::string object = host + ":" + std::to_string(port);
    addrinfo hints{};
    hints.ai_family = AF_UNSPEC;
    hints.ai_socktype = SOCK_STREAM;
    addrinfo* res = nullptr;
    const std::string service = std::to_string(port);
    if (const int rc = getaddrinfo(host.c_str(), service.c_str(), &hints, &res); rc != 0) {
        return Error{"getaddrinfo(" + object + "): " + gai_strerror(rc)};
    }
    std::string last_error = "connect(" + object + "): no address";
    for (addrinfo* ai = res; ai != nullptr; ai = ai->ai_next) {
        UniqueFd fd(socket(ai->ai_family, ai->ai_socktype | SOCK_NONBLOCK | SOCK_CLOEXEC, ai->ai_protocol));
        if (!fd.valid()) {
            last_error = sysError("socket", object);
            continue;
        }
        if (connect(fd.get(), ai->ai_addr, ai->ai_addrlen) != 0) {
            if (errno != EINPROGRESS) {
                last_error = sysError("connect", object);
                continue;
            }
            pollfd p{fd.get(), POLLOUT, 0};
            const int n = poll(&p, 1, static_cast<int>(timeout.count()));
            int err = 0;
            socklen_t len = sizeof(err);
            if (n <= 0) {
                errno = n == 0 ? ETIMEDOUT : errno;
                last_error = sysError("connect", object);
                continue;
            }
            getsockopt(fd.get(), SOL_SOCKET, SO_ERROR, &err, &len);
            if (err != 0) {
                errno = err;
                last_error = sysError("connect", object);
                continue;
            }
        }
        const int flags = fcntl(fd.get(), F_GETFL);
        fcntl(fd.get(), F_SETFL, flags & ~O_NONBLOCK);
        const int one = 1;
        setsockopt(fd.get(), IPPROTO_TCP, TCP_NODELAY, &one, sizeof(one));
        freeaddrinfo(res);
        return fd.release();
    }
    freeaddrinfo(res);
    return Error{last_error};
}

int msLeft(std::chrono::steady_clock::time_point deadline) noexcept {
    const auto left =
        std::chrono::duration_cast<std::chrono::milliseconds>(deadline - std::chrono::steady_clock::now()).count();
    return left < 0 ? 0 : static_cast<int>(left);
}

}  // namespace navmap::ipc::stream_detail
