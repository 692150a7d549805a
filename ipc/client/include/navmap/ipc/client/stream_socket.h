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

/// Milliseconds from now to `deadline` for poll(), 0 once it has passed.
int msLeft(std::chrono::steady_clock::time_point deadline) noexcept;

/// DMA_BUF_IOCTL_SYNC around a CPU read of a mapped dma-buf (linux/dma-buf.h), so that caches see
/// what the GPU wrote: `start` before the read, !`start` after. Best effort: a buffer without the
/// ioctl is read as it is.
void dmaBufSync(int fd, bool start) noexcept;

}  // namespace navmap::ipc::stream_detail
