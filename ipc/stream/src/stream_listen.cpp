// SPDX-License-Identifier: Apache-2.0
#include "stream_listen.h"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/un.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include "navmap/ipc/net/socket_access.h"

// The server side of the stream sockets (navmap_ipc_stream; the client library only connects).
namespace navmap::ipc::stream_detail {

using net::sysError;
using net::UniqueFd;

Result<int> listenUnix(const std::string& path, mode_t mode, std::optional<gid_t> group) {
    auto addr = unixAddress(path);
    if (!addr) {
        return addr.error();
    }
    struct stat st {};
    if (lstat(path.c_str(), &st) == 0) {
        if (!S_ISSOCK(st.st_mode)) {
            return Error{"bind(" + path + "): exists and is not a socket"};
        }
        if (unlink(path.c_str()) != 0) {
            return Error{sysError("unlink", path)};
        }
    }
    UniqueFd fd(socket(AF_UNIX, SOCK_STREAM | SOCK_NONBLOCK | SOCK_CLOEXEC, 0));
    if (!fd.valid()) {
        return Error{sysError("socket", path)};
    }
    // The file bind() creates is never wider than `mode`; its exact mode and group are set before
    // listen(), and no peer can connect before listen(): there is no moment with wider access. The
    // file appears at `path` only once the socket listens.
    if (auto access = restrictSocketBeforeBind(fd.get(), mode, path); !access) {
        return Error{access.message()};
    }
    if (auto bound = bindAndListenUnix(fd.get(), path, mode, group, 64); !bound) {
        return Error{bound.message()};
    }
    return fd.release();
}

Result<int> listenTcp(const std::string& address, int port) {
    const std::string object = address + ":" + std::to_string(port);
    if (port < 0 || port > 65535) {
        return Error{"listen(" + object + "): bad port"};
    }
    sockaddr_storage ss{};
    socklen_t len = 0;
    int family = AF_INET;
    auto* in4 = reinterpret_cast<sockaddr_in*>(&ss);
    auto* in6 = reinterpret_cast<sockaddr_in6*>(&ss);
    if (inet_pton(AF_INET, address.c_str(), &in4->sin_addr) == 1) {
        in4->sin_family = AF_INET;
        in4->sin_port = htons(static_cast<std::uint16_t>(port));
        len = sizeof(sockaddr_in);
    } else if (inet_pton(AF_INET6, address.c_str(), &in6->sin6_addr) == 1) {
        family = AF_INET6;
        in6->sin6_family = AF_INET6;
        in6->sin6_port = htons(static_cast<std::uint16_t>(port));
        len = sizeof(sockaddr_in6);
    } else {
        return Error{"listen(" + object + "): not a numeric IPv4/IPv6 address"};
    }
    UniqueFd fd(socket(family, SOCK_STREAM | SOCK_NONBLOCK | SOCK_CLOEXEC, 0));
    if (!fd.valid()) {
        return Error{sysError("socket", object)};
    }
    const int one = 1;
    setsockopt(fd.get(), SOL_SOCKET, SO_REUSEADDR, &one, sizeof(one));
    if (bind(fd.get(), reinterpret_cast<const sockaddr*>(&ss), len) != 0) {
        return Error{sysError("bind", object)};
    }
    if (listen(fd.get(), 64) != 0) {
        return Error{sysError("listen", object)};
    }
    return fd.release();
}

int boundPort(int fd) {
    sockaddr_storage ss{};
    socklen_t len = sizeof(ss);
    if (getsockname(fd, reinterpret_cast<sockaddr*>(&ss), &len) != 0) {
        return -1;
    }
    if (ss.ss_family == AF_INET) {
        return ntohs(reinterpret_cast<sockaddr_in*>(&ss)->sin_port);
    }
    if (ss.ss_family == AF_INET6) {
        return ntohs(reinterpret_cast<sockaddr_in6*>(&ss)->sin6_port);
    }
    return -1;
}

}  // namespace navmap::ipc::stream_detail
