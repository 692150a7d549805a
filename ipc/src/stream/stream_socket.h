// SPDX-License-Identifier: Apache-2.0
#pragma once
// Private socket helpers of ipc/src/stream (not installed): every error names the call and the
// object, "connect(/run/navmap/stream.sock): No such file or directory" (net::sysError).

#include <sys/types.h>
#include <sys/un.h>

#include <chrono>
#include <optional>
#include <string>

#include "navmap/ipc/net/sys_error.h"
#include "navmap/ipc/net/unique_fd.h"
#include "navmap/ipc/result.h"

namespace navmap::ipc::stream_detail {

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
