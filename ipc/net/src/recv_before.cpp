// SPDX-License-Identifier: Apache-2.0
#include "navmap/ipc/net/recv_before.h"

#include <poll.h>
#include <sys/socket.h>

#include <algorithm>
#include <cerrno>
#include <climits>

#include "navmap/ipc/net/sys_error.h"

namespace navmap::ipc::net {

namespace {

int msLeft(std::chrono::steady_clock::time_point deadline) {
    const auto left =
        std::chrono::duration_cast<std::chrono::milliseconds>(deadline - std::chrono::steady_clock::now()).count();
    return static_cast<int>(std::clamp<decltype(left)>(left, 0, INT_MAX));
}

}  // namespace

Received recvBefore(int fd, void* buf, std::size_t size, std::chrono::steady_clock::time_point deadline,
                    std::string_view peer) {
    for (;;) {
        pollfd p{fd, POLLIN, 0};
        const int ready = ::poll(&p, 1, msLeft(deadline));
        if (ready == 0) {
            return {Received::Kind::TimedOut, 0, {}};
        }
        if (ready < 0) {
            if (errno == EINTR) {
                continue;
            }
            return {Received::Kind::Failed, 0, sysError("poll", peer)};
        }
        const ssize_t got = ::recv(fd, buf, size, MSG_DONTWAIT);
        if (got > 0) {
            return {Received::Kind::Data, static_cast<std::size_t>(got), {}};
        }
        if (got == 0) {
            return {Received::Kind::Failed, 0, "recv(" + std::string(peer) + "): connection closed by the server"};
        }
        if (errno == EINTR || errno == EAGAIN || errno == EWOULDBLOCK) {
            continue;
        }
        return {Received::Kind::Failed, 0, sysError("recv", peer)};
    }
}

}  // namespace navmap::ipc::net
