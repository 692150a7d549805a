// SPDX-License-Identifier: Apache-2.0
#include "shm_transport.h"

#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <vector>

#include "navmap/ipc/client/dmabuf_block.h"

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
    const bool acks = c.payload == StreamPayload::Shm || c.payload == StreamPayload::Dmabuf;
    if (!acks || byte != 'A' || !c.awaiting_ack) {
        return false;
    }
    c.awaiting_ack = false;
    c.unpin();  // the client is done with the frame: its slot (or buffer) may be written again
    c.last_progress = Clock::now();
    if (c.pending && !c.busy()) {
        sendFrame(c);
    }
    return true;
}

void ShmTransport::sendFrame(StreamConn& c) {
    if (c.payload == StreamPayload::Dmabuf) {
        sendDmabufFrame(c);
    } else {
        FrameStreamTransport::sendFrame(c);
    }
}

void ShmTransport::sendDmabufFrame(StreamConn& c) {
    c.pending = false;
    auto t = c.ring->dmabuf->take(c.last_sent, c.dmabuf_known);
    if (!t) {
        return;
    }
    // Header, the metadata block when asked for, the dma-buf block; the fds travel with the first
    // byte (SCM_RIGHTS). Frames go only to a client whose queue is empty (not busy), so nothing
    // queued before can separate the fds from their frame.
    const auto meta = c.meta ? t->meta : nullptr;
    t->header.dropped = c.dropped;
    t->header.meta_bytes = meta ? static_cast<std::uint16_t>(meta->size()) : 0;
    const auto hb = encodeFrameHeader(t->header);
    const auto bb = encodeDmabufBlock(t->block);
    std::vector<std::uint8_t> bytes(hb.begin(), hb.end());
    if (meta) {
        bytes.insert(bytes.end(), meta->begin(), meta->end());
    }
    bytes.insert(bytes.end(), bb.begin(), bb.end());
    int fds[2];
    std::size_t nfds = 0;
    if (t->buffer_fd.valid()) fds[nfds++] = t->buffer_fd.get();
    if (t->fence_fd.valid()) fds[nfds++] = t->fence_fd.get();
    iovec iov{bytes.data(), bytes.size()};
    alignas(cmsghdr) char control[CMSG_SPACE(sizeof(fds))] = {};
    msghdr msg{};
    msg.msg_iov = &iov;
    msg.msg_iovlen = 1;
    if (nfds > 0) {
        msg.msg_control = control;
        msg.msg_controllen = CMSG_SPACE(nfds * sizeof(int));
        cmsghdr* cm = CMSG_FIRSTHDR(&msg);
        cm->cmsg_level = SOL_SOCKET;
        cm->cmsg_type = SCM_RIGHTS;
        cm->cmsg_len = CMSG_LEN(nfds * sizeof(int));
        std::memcpy(CMSG_DATA(cm), fds, nfds * sizeof(int));
    }
    const ssize_t n = ::sendmsg(c.fd.get(), &msg, MSG_NOSIGNAL | MSG_DONTWAIT);
    if (n < 0) {
        c.ring->dmabuf->release(t->buffer);
        if (t->buffer_fd.valid()) {
            c.dmabuf_known[static_cast<std::size_t>(t->buffer)] = 0;  // not received: send it again
        }
        if (errno == EAGAIN || errno == EWOULDBLOCK) {
            ++c.dropped;  // the socket is full: this frame is lost to the client, the next one is not
            m_hub.stats().count(&FrameServerStats::frames_dropped);
            return;
        }
        m_hub.stats().setLastError(net::sysError("sendmsg", c.peer));
        c.dead = true;
        return;
    }
    if (static_cast<std::size_t>(n) < bytes.size()) {
        c.queue(bytes.data() + n, bytes.size() - static_cast<std::size_t>(n));
    }
    c.dmabuf_held = t->buffer;
    c.awaiting_ack = true;
    c.ack_since = Clock::now();
    m_hub.stats().count(&FrameServerStats::dmabuf_frames_sent);
    if (t->buffer_fd.valid()) {
        m_hub.stats().count(&FrameServerStats::dmabuf_fds_sent);
    }
    m_hub.frameSent(c, t->sequence);
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
