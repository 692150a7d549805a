// SPDX-License-Identifier: Apache-2.0
#include "navmap/ipc/net/recv_before.h"

#include <poll.h>
#include <sys/socket.h>

#include <algorithm>
#include <cerrno>
#include <climits>
#include <cstring>

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
                    std::string_view peer, std::vector<int>* fds) {
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
        iovec iov{buf, size};
        alignas(cmsghdr) char control[CMSG_SPACE(sizeof(int) * 8)] = {};
        msghdr msg{};
        msg.msg_iov = &iov;
        msg.msg_iovlen = 1;
        if (fds) {
            msg.msg_control = control;
            msg.msg_controllen = sizeof(control);
        }
        const ssize_t got = ::recvmsg(fd, &msg, MSG_DONTWAIT | MSG_CMSG_CLOEXEC);
        for (cmsghdr* cm = fds ? CMSG_FIRSTHDR(&msg) : nullptr; cm != nullptr; cm = CMSG_NXTHDR(&msg, cm)) {
            if (cm->cmsg_level != SOL_SOCKET || cm->cmsg_type != SCM_RIGHTS) continue;
            for (std::size_t i = 0; i < (cm->cmsg_len - CMSG_LEN(0)) / sizeof(int); ++i) {
                int f = -1;
                std::memcpy(&f, CMSG_DATA(cm) + i * sizeof(int), sizeof(int));
                fds->push_back(f);
            }
        }
        if (got > 0) {
            return {Received::Kind::Data, static_cast<std::size_t>(got), {}};
        }
        if (got == 0) {
            return {Received::Kind::Failed, 0, "recv(" + std::string(peer) + "): connection closed by the server"};
        }
        if (errno == EINTR || errno == EAGAIN || errno == EWOULDBLOCK) {
            continue;
        }
        return {Received::Kind::Failed, 0, sysError(fds ? "recvmsg" : "recv", peer)};
    }
}

}  // namespace navmap::ipc::net
