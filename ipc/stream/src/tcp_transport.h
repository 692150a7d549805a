// SPDX-License-Identifier: Apache-2.0
#pragma once
// TcpTransport: the frame stream over TCP (bind_address:tcp_port): the same handshake and headers
// as the Unix socket, pixels raw or zlib-compressed on the socket; "shm" is refused. Peers have no
// uid: they are bounded by the transport's cap and the cap per peer address. Server thread. Private to ipc/stream.

#include "frame_stream_transport.h"

namespace navmap::ipc::stream_detail {

class TcpTransport : public FrameStreamTransport {
public:
    explicit TcpTransport(ClientHub& hub) : FrameStreamTransport(Via::Tcp, hub) {}

    /// The bound port (the one asked for, or the kernel's pick for port 0); -1 when none.
    int port() const noexcept { return m_port; }

protected:
    Result<int> openListener() override;

private:
    int m_port = -1;
};

}  // namespace navmap::ipc::stream_detail
