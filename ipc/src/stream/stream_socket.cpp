#include "stream_socket.h"

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
#include <cstring>

#include "navmap/ipc/socket_access.h"

namespace navmap::ipc::stream_detail {

std::string sysError(const char* call, const std::string& object) {
    return std::string(call) + "(" + object + "): " + std::strerror(errno);
}

UniqueFd::~UniqueFd() { reset(); }

UniqueFd& UniqueFd::operator=(UniqueFd&& o) noexcept {
    if (this != &o) {
        reset(o.release());
    }
    return *this;
}

void UniqueFd::reset(int fd) noexcept {
    if (m_fd >= 0) {
        ::close(m_fd);
    }
    m_fd = fd;
}

std::int64_t realtimeNowNs() noexcept {
    timespec ts{};
    clock_gettime(CLOCK_REALTIME, &ts);
    return static_cast<std::int64_t>(ts.tv_sec) * 1000000000LL + ts.tv_nsec;
}

namespace {

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

}  // namespace

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
    // listen(), and no peer can connect before listen(): there is no moment with wider access.
    if (auto access = restrictSocketBeforeBind(fd.get(), mode, path); !access) {
        return Error{access.message()};
    }
    if (bind(fd.get(), reinterpret_cast<const sockaddr*>(&addr.value()), sizeof(sockaddr_un)) != 0) {
        return Error{sysError("bind", path)};
    }
    if (auto access = applySocketFileAccess(path, mode, group); !access) {
        unlink(path.c_str());
        return Error{access.message()};
    }
    if (listen(fd.get(), 64) != 0) {
        const std::string err = sysError("listen", path);
        unlink(path.c_str());
        return Error{err};
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
    std::string lastError = "connect(" + object + "): no address";
    for (addrinfo* ai = res; ai != nullptr; ai = ai->ai_next) {
        UniqueFd fd(socket(ai->ai_family, ai->ai_socktype | SOCK_NONBLOCK | SOCK_CLOEXEC, ai->ai_protocol));
        if (!fd.valid()) {
            lastError = sysError("socket", object);
            continue;
        }
        if (connect(fd.get(), ai->ai_addr, ai->ai_addrlen) != 0) {
            if (errno != EINPROGRESS) {
                lastError = sysError("connect", object);
                continue;
            }
            pollfd p{fd.get(), POLLOUT, 0};
            const int n = poll(&p, 1, static_cast<int>(timeout.count()));
            int err = 0;
            socklen_t len = sizeof(err);
            if (n <= 0) {
                errno = n == 0 ? ETIMEDOUT : errno;
                lastError = sysError("connect", object);
                continue;
            }
            getsockopt(fd.get(), SOL_SOCKET, SO_ERROR, &err, &len);
            if (err != 0) {
                errno = err;
                lastError = sysError("connect", object);
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
    return Error{lastError};
}

}  // namespace navmap::ipc::stream_detail
