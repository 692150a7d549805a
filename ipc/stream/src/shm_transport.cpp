// SPDX-License-Identifier: Apache-2.0
#include "shm_transport.h"

#include <sys/socket.h>
#include <unistd.h>

#include <cstring>

#include "navmap/ipc/net/sys_error.h"
#include "stream_listen.h"
#include "stream_rings.h"

namespace navmap::ipc::stream_detail {

Result<int> ShmTransport::openListener() {
    const FrameServerOptions& o = m_hub.options();
    m_allowed = o.allowed_peers;
    if (o.unix_group) {
        m_allowed.gids.push_back(*o.unix_group);
    }
    if (o.unix_path.empty()) {
        return -1;
    }
    return listenUnix(o.unix_path, o.unix_mode, o.unix_group);
}

void ShmTransport::close() {
    if (listenFd() >= 0) {
        FrameStreamTransport::close();
        ::unlink(m_hub.options().unix_path.c_str());
    }
}

std::string ShmTransport::acceptObject() const { return m_hub.options().unix_path; }

std::optional<Refusal> ShmTransport::checkPeer(int fd, std::optional<uid_t>* uid) {
    const std::string& path = m_hub.options().unix_path;
    auto cred = peerCredentials(fd, path);
    if (!cred) {
        return Refusal{&FrameServerStats::refused_peer, cred.error().message};
    }
    if (!peerAllowed(m_allowed, cred.value())) {
        return Refusal{&FrameServerStats::refused_peer, peerRefusal(cred.value(), path)};
    }
    *uid = cred.value().uid;
    return std::nullopt;
}

bool ShmTransport::sendReply(StreamConn& c, const std::string& text) {
    return c.payload == StreamPayload::Shm ? sendWithRing(c, text) : FrameStreamTransport::sendReply(c, text);
}

bool ShmTransport::sendWithRing(StreamConn& c, const std::string& text) {
    // The reply and the read-only memfd travel in one sendmsg() (SCM_RIGHTS), like wl_shm.
    auto ro = c.ring->ring->openReadOnly();
    if (!ro) {
        handshakeError(c, ro.error().message);
        return false;
    }
    const net::UniqueFd ro_fd(ro.value());
    // From here on a mapping of the ring may live out of the server's sight: it stays counted.
    c.ring->handed_out = true;
    iovec iov{const_cast<char*>(text.data()), text.size()};
    alignas(cmsghdr) char control[CMSG_SPACE(sizeof(int))] = {};
    msghdr msg{};
    msg.msg_iov = &iov;
    msg.msg_iovlen = 1;
    msg.msg_control = control;
    msg.msg_controllen = sizeof(control);
    cmsghdr* cm = CMSG_FIRSTHDR(&msg);
    cm->cmsg_level = SOL_SOCKET;
    cm->cmsg_type = SCM_RIGHTS;
    cm->cmsg_len = CMSG_LEN(sizeof(int));
    const int f = ro_fd.get();
    std::memcpy(CMSG_DATA(cm), &f, sizeof(int));
    const ssize_t n = ::sendmsg(c.fd.get(), &msg, MSG_NOSIGNAL | MSG_DONTWAIT);
    if (n < 0) {
        m_hub.stats().setLastError(net::sysError("sendmsg", c.peer));
        c.dead = true;
        return false;
    }
    if (static_cast<std::size_t>(n) < text.size()) {
        c.queue(text.data() + n, text.size() - static_cast<std::size_t>(n));
    }
    return true;
}

bool ShmTransport::takeAck(StreamConn& c, unsigned char byte) {
    if (c.payload != StreamPayload::Shm || byte != 'A' || !c.awaiting_ack) {
        return false;
    }
    c.awaiting_ack = false;
    c.unpin();  // the client is done with the frame: its slot may be written again
    c.last_progress = Clock::now();
    if (c.pending && !c.busy()) {
        sendFrame(c);
    }
    return true;
}

bool ShmTransport::readFrame(StreamConn& c, std::uint64_t seq, FrameHeader* h) {
    if (c.payload != StreamPayload::Shm) {
        return FrameStreamTransport::readFrame(c, seq, h);
    }
    FrameRing& ring = *c.ring->ring;
    if (!c.hold) {
        return ring.read(seq, h, nullptr);
    }
    // A client that holds frames: the slot is pinned from the notification until the ack, and
    // the writer leaves it alone while another one is free (copying clients pin nothing: their
    // seqlock copy tells them when a frame was overwritten).
    const int slot = ring.pin(seq);
    const bool ok = slot >= 0 && ring.read(seq, h, nullptr);
    if (slot >= 0 && !ok) {
        ring.unpin(static_cast<std::uint32_t>(slot));
    } else if (ok) {
        c.pinned_slot = slot;
    }
    return ok;
}

void ShmTransport::queueFrame(StreamConn& c, FrameHeader h, const EncodedFrame* encoded) {
    if (c.payload != StreamPayload::Shm) {
        FrameStreamTransport::queueFrame(c, h, encoded);
        return;
    }
    h.encoding = FrameEncoding::Shm;
    h.payload_bytes = 0;
    queueHeader(c, h);
    c.awaiting_ack = true;
    c.ack_since = Clock::now();
}

}  // namespace navmap::ipc::stream_detail
