// SPDX-License-Identifier: Apache-2.0
#include "tcp_transport.h"

#include "stream_listen.h"

namespace navmap::ipc::stream_detail {

Result<int> TcpTransport::openListener() {
    const FrameServerOptions& o = m_hub.options();
    if (o.tcp_port < 0) {
        return -1;
    }
    auto fd = listenTcp(o.bind_address, o.tcp_port);
    if (fd) {
        m_port = boundPort(fd.value());
    }
    return fd;
}

}  // namespace navmap::ipc::stream_detail
