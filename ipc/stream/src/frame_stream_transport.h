// SPDX-License-Identifier: Apache-2.0
#pragma once
// FrameStreamTransport: the frame-stream protocol of docs/frame-protocol.md on a socket: one JSON
// handshake line, a JSON reply, then an 80-byte header per frame with the pixels raw or
// zlib-compressed on the socket; after the handshake a client sends nothing (shm clients: acks,
// see ShmTransport). Errors go back as a JSON line (handshake) or a header of kind Error (later),
// and the connection is closed. Base of ShmTransport (Unix socket) and TcpTransport. Server
// thread. Private to ipc/stream.

#include <cstdint>
#include <memory>
#include <string>

#include "frame_encoder.h"
#include "navmap/ipc/client/frame_header.h"
#include "navmap/ipc/client/stream_profile.h"
#include "stream_transport.h"

namespace navmap::ipc::stream_detail {

class FrameStreamTransport : public StreamTransport {
public:
    using StreamTransport::StreamTransport;

    void onInput(StreamConn& c) override;
    void sendFrame(StreamConn& c) override;
    std::string firstFrameTimeoutReply(const StreamConn& c, const std::string& text) const override;

protected:
    enum class ReadOutcome { Nothing, Retry, Ready };

    /// Whether handshakes may ask for the "shm" payload (the Unix socket only).
    virtual bool carriesShm() const { return false; }
    /// Sends the handshake reply; false when the connection broke (then `dead`).
    virtual bool sendReply(StreamConn& c, const std::string& text);
    /// One byte from a streaming client: true when it was an ack this transport expects.
    virtual bool takeAck(StreamConn& c, unsigned char byte);
    /// Reads frame `seq` of c's ring into `*h` (and the raw cache); false when overwritten.
    virtual bool readFrame(StreamConn& c, std::uint64_t seq, FrameHeader* h);
    /// Queues the header (and payload) of a frame for `c`.
    virtual void queueFrame(StreamConn& c, FrameHeader h, const EncodedFrame* encoded);
    /// Queues the header of a frame, with its metadata block after it when the client asked.
    void queueHeader(StreamConn& c, FrameHeader h);

    void handshakeError(StreamConn& c, const std::string& message);
    void protocolError(StreamConn& c, const std::string& message);

private:
    void onHandshakeBytes(StreamConn& c);
    void onHandshake(StreamConn& c, const std::string& line);
    void onStreamBytes(StreamConn& c);
    std::string handshakeReply(const StreamConn& c, const StreamRequest& r) const;
    ReadOutcome readNewest(StreamConn& c, std::uint64_t* seq, FrameHeader* h);
};

/// A header of kind Error carrying `text` (the server's last word on a frame stream).
std::string errorFrame(const std::string& text);

}  // namespace navmap::ipc::stream_detail
