// SPDX-License-Identifier: Apache-2.0
#pragma once
// ShmTransport: the frame stream on the Unix socket. Peers are checked by SO_PEERCRED against the
// allow list (the server's uid, root, the socket's group) and capped per uid. Besides the socket
// payloads (raw, zlib) it carries "shm": the handshake reply brings a read-only, sealed memfd of
// the profile's ring (SCM_RIGHTS, like wl_shm), each frame is an 80-byte notification, and the
// client sends one ack byte back per frame (credit of one frame). A client that holds frames has
// its slot pinned from the notification until the ack. And "dmabuf": each frame is its header and
// the 48-byte dma-buf block, with the buffer's fd (the first time) and the fence's (SCM_RIGHTS);
// the buffer is held until the ack. Server thread. Private to ipc/stream.

#include "frame_stream_transport.h"
#include "navmap/ipc/net/socket_access.h"

namespace navmap::ipc::stream_detail {

class ShmTransport : public FrameStreamTransport {
public:
    explicit ShmTransport(ClientHub& hub) : FrameStreamTransport(Via::Unix, hub) {}

    /// Closes the socket and removes its file.
    void close() override;

protected:
    Result<int> openListener() override;
    std::optional<Refusal> checkPeer(int fd, std::optional<uid_t>* uid) override;
    std::string acceptObject() const override;
    bool carriesShm() const override { return true; }
    bool sendReply(StreamConn& c, const std::string& text) override;
    bool takeAck(StreamConn& c, unsigned char byte) override;
    bool readFrame(StreamConn& c, std::uint64_t seq, FrameHeader* h) override;
    void queueFrame(StreamConn& c, FrameHeader h, const EncodedFrame* encoded) override;

public:
    /// dmabuf clients: the newest dma-buf frame, its fds attached (docs/frame-protocol.md "dma-buf
    /// frames"); the others: FrameStreamTransport's.
    void sendFrame(StreamConn& c) override;

private:
    void sendDmabufFrame(StreamConn& c);
    bool sendWithRing(StreamConn& c, const std::string& text);

    PeerAllowList m_allowed;  // allowed_peers plus unix_group
};

}  // namespace navmap::ipc::stream_detail
