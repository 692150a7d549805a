// SPDX-License-Identifier: Apache-2.0
#pragma once
// StreamTimeouts: which time limit a connection has passed. Every connection must earn its slot:
// a handshake (or HTTP request head) within handshake_timeout of the accept, then a first frame
// within handshake_timeout of the handshake; after that it must keep taking what it is sent
// (stall_timeout). TCP progress is the peer taking bytes out of the kernel's send queue, not a
// send() that only proves the kernel had room. Server thread. Private to ipc/stream.

#include <string>

#include "navmap/ipc/stream/frame_server.h"
#include "stream_conn.h"

namespace navmap::ipc::stream_detail {

struct TimeoutVerdict {
    enum class Kind { None, Handshake, FirstFrame, Stall };
    Kind kind = Kind::None;
    std::string why;  ///< "no complete handshake within 5000 ms", "not reading for 2000 ms"
};

class StreamTimeouts {
public:
    explicit StreamTimeouts(const FrameServerOptions& options) : m_options(options) {}

    /// Updates a TCP connection's progress from its send queue, then says which limit it passed.
    TimeoutVerdict check(StreamConn& c, Clock::time_point now) const;

private:
    /// SIOCOUTQ: bytes the peer has not acknowledged yet (0 for Unix sockets).
    static int trackProgress(StreamConn& c, Clock::time_point now);
    std::string within() const;
    std::string firstFrameWhy(const StreamConn& c) const;
    std::string stallWhy(const StreamConn& c, int outq, Clock::time_point now) const;

    const FrameServerOptions& m_options;
};

}  // namespace navmap::ipc::stream_detail
