// SPDX-License-Identifier: Apache-2.0
#pragma once
// HttpAccess: who may use the HTTP transport. The Host header must name this server (a page from
// another origin that reaches the port through DNS rebinding carries its own host name); when
// http_token is set, a request needs it as a bearer token or ?token=. Refusals are counted.
// Server thread. Private to ipc/stream.

#include <string>

#include "navmap/ipc/stream/frame_server.h"
#include "navmap/ipc/stream/stream_http_request.h"

namespace navmap::ipc::stream_detail {

class StreamStats;

class HttpAccess {
public:
    HttpAccess(const FrameServerOptions& options, StreamStats& stats) : m_options(options), m_stats(stats) {}

    /// Empty when `req` (on socket `fd`, server port `port`) may pass; otherwise the reply body,
    /// with `*code` set to 400 (no Host), 421 (another host) or 401 (token).
    std::string check(int fd, int port, const StreamHttpRequest& req, int* code) const;

private:
    std::string checkHost(int fd, int port, const std::string& value, int* code) const;
    std::string checkToken(const StreamHttpRequest& req, int* code) const;
    /// The address clients should name: bind_address, or the one `fd` came in on when bound to all.
    std::string serverAddress(int fd) const;

    const FrameServerOptions& m_options;
    StreamStats& m_stats;
};

}  // namespace navmap::ipc::stream_detail
