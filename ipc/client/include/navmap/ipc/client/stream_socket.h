// SPDX-License-Identifier: Apache-2.0
#pragma once
// Socket helpers of the stream client and the frame server (not installed): every error names the
// call and the object, "connect(/run/navmap/stream.sock): No such file or directory"
// (net::sysError). The server's listening side is ipc/stream/src/stream_listen.h.

#include <sys/types.h>
#include <sys/un.h>

#include <chrono>
#include <optional>
#include <string>

#include "navmap/ipc/net/result.h"
#include "navmap/ipc/net/sys_error.h"
#include "navmap/ipc/net/unique_fd.h"

namespace navmap::ipc::stream_detail {

/// The address of a Unix socket path; an Error when it is empty or too long for sun_path.
Result<sockaddr_un> unixAddress(const std::string& path);

/// Blocking connects (the timeout covers the TCP connect); the returned fd is blocking, CLOEXEC.
Result<int> connectUnixSocket(const std::string& path);
Result<int> connectTcpSocket(const std::string& host, int port, std::chrono::milliseconds timeout);

std::int64_t realtimeNowNs() noexcept;

}  // namespace navmap::ipc::stream_detail
