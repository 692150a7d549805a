// SPDX-License-Identifier: Apache-2.0
#pragma once
// Private socket helpers of ipc/src/stream (not installed): every error names the call and the
// object, "connect(/run/navmap/stream.sock): No such file or directory".

#include <sys/types.h>
#include <sys/un.h>

#include <chrono>
#include <optional>
#include <string>

#include "navmap/ipc/result.h"

namespace navmap::ipc::stream_detail {

std::string sysError(const char* call, const std::string& object);

/// Owns a descriptor; closes it on destruction.
class UniqueFd {
public:
    UniqueFd() = default;
    explicit UniqueFd(int fd) : m_fd(fd) {}
    ~UniqueFd();
    UniqueFd(UniqueFd&& o) noexcept : m_fd(o.release()) {}
    UniqueFd& operator=(UniqueFd&& o) noexcept;
    UniqueFd(const UniqueFd&) = delete;
    UniqueFd& operator=(const UniqueFd&) = delete;
    int get() const noexcept { return m_fd; }
    int release() noexcept { const int f = m_fd; m_fd = -1; return f; }
    void reset(int fd = -1) noexcept;
    bool valid() const noexcept { return m_fd >= 0; }

private:
    int m_fd = -1;
};

/// The address of a Unix socket path; an Error when it is empty or too long for sun_path.
Result<sockaddr_un> unixAddress(const std::string& path);

/// Server side (stream_listen.cpp, not in the client library):
/// Non-blocking listening Unix stream socket; a stale socket file at `path` is replaced. The file
/// gets `mode` whatever the umask, and `group` when given, before the socket listens.
Result<int> listenUnix(const std::string& path, mode_t mode, std::optional<gid_t> group);
/// Non-blocking listening TCP socket on address:port (port 0 = any).
Result<int> listenTcp(const std::string& address, int port);
/// Port a TCP socket is bound to, -1 on error.
int boundPort(int fd);
/// Blocking connects (the timeout covers the TCP connect); the returned fd is blocking, CLOEXEC.
Result<int> connectUnixSocket(const std::string& path);
Result<int> connectTcpSocket(const std::string& host, int port, std::chrono::milliseconds timeout);

std::int64_t realtimeNowNs() noexcept;

}  // namespace navmap::ipc::stream_detail
