// SPDX-License-Identifier: Apache-2.0
#pragma once
// recvBefore(): the clients' one wait-and-receive step on a socket (the control client, the
// frame-stream client), with the retries every such reader needs: poll() or recv() interrupted
// by a signal, a readable socket that has nothing after all. Errors name the call and the peer.

#include <chrono>
#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

namespace navmap::ipc::net {

/// What one recvBefore() got.
struct Received {
    enum class Kind { Data, TimedOut, Failed };
    Kind kind = Kind::Failed;
    std::size_t bytes = 0;  ///< Data: how many bytes arrived (at least one)
    /// Failed: "poll(<peer>): <strerror>", "recv(<peer>): <strerror>", or
    /// "recv(<peer>): connection closed by the server" when the peer closed the stream.
    std::string error;
};

/// Waits until `deadline` for `fd` to turn readable, then receives up to `size` (> 0) bytes into
/// `buf` without blocking. Retries when poll() or recv() is interrupted (EINTR) and when recv()
/// finds nothing (EAGAIN); never waits past `deadline`. With `fds` (a Unix socket), descriptors
/// that arrive with the bytes (SCM_RIGHTS) are appended to it, close-on-exec, for the caller to
/// own; without it the kernel closes any that come.
Received recvBefore(int fd, void* buf, std::size_t size, std::chrono::steady_clock::time_point deadline,
                    std::string_view peer, std::vector<int>* fds = nullptr);

}  // namespace navmap::ipc::net
