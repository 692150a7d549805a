// SPDX-License-Identifier: Apache-2.0
#include "stream_conn.h"

#include <sys/socket.h>

#include <cerrno>

#include "stream_rings.h"

namespace navmap::ipc::stream_detail {

const char* viaName(Via via) { return via == Via::Unix ? "unix" : via == Via::Tcp ? "tcp" : "http"; }

void StreamConn::queue(const void* data, std::size_t n) {
    if (!outPending()) {
        out.clear();
        out_pos = 0;
        if (via == Via::Unix) {
            last_progress = Clock::now();
        }
    }
    const auto* p = static_cast<const std::uint8_t*>(data);
    out.insert(out.end(), p, p + n);
}

bool StreamConn::sendQueued() {
    while (outPending()) {
        const ssize_t n = ::send(fd.get(), out.data() + out_pos, out.size() - out_pos, MSG_NOSIGNAL | MSG_DONTWAIT);
        if (n > 0) {
            out_pos += static_cast<std::size_t>(n);
            bytes_sent += static_cast<std::uint64_t>(n);
            if (via == Via::Unix) {
                last_progress = Clock::now();  // Unix socket buffers are small: a send is progress
            }
            continue;
        }
        if (n < 0 && (errno == EAGAIN || errno == EWOULDBLOCK || errno == EINTR)) {
            return false;
        }
        dead = true;
        return false;
    }
    out.clear();
    out_pos = 0;
    return true;
}

void StreamConn::closeWith(const std::string& bytes) {
    // One try without waiting: the connection is being dropped and must not hold its slot.
    if (!bytes.empty() && !outPending()) {
        [[maybe_unused]] const auto n = ::send(fd.get(), bytes.data(), bytes.size(), MSG_NOSIGNAL | MSG_DONTWAIT);
    }
    ::shutdown(fd.get(), SHUT_WR);
    dead = true;
}

void StreamConn::unpin() {
    if (pinned_slot >= 0 && ring) {
        ring->ring->unpin(static_cast<std::uint32_t>(pinned_slot));
    }
    pinned_slot = -1;
    if (dmabuf_held >= 0 && ring) {
        ring->dmabuf->release(dmabuf_held);
    }
    dmabuf_held = -1;
}

}  // namespace navmap::ipc::stream_detail
