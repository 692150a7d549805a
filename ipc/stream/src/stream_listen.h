// SPDX-License-Identifier: Apache-2.0
#pragma once
// The server side of the stream sockets (stream_listen.cpp): listening Unix and TCP sockets for the
// frame server's transports. The client library only connects (navmap/ipc/client/stream_socket.h).

#include <sys/types.h>

#include <optional>
#include <string>

#include "navmap/ipc/client/stream_socket.h"
#include "navmap/ipc/net/result.h"

namespace navmap::ipc::stream_detail {

/// Non-blocking listening Unix stream socket; a stale socket file at `path` is replaced. The file
/// gets `mode` whatever the umask, and `group` when given, before the socket listens.
Result<int> listenUnix(const std::string& path, mode_t mode, std::optional<gid_t> group);
/// Non-blocking listening TCP socket on address:port (port 0 = any).
Result<int> listenTcp(const std::string& address, int port);
/// Port a TCP socket is bound to, -1 on error.
int boundPort(int fd);

}  // namespace navmap::ipc::stream_detail
