// SPDX-License-Identifier: Apache-2.0
#pragma once
// HttpTransport: HTTP/1.0 on bind_address:http_port, one request per connection. GET / (HTML
// viewer), /status (JSON), /metrics (Prometheus text) and /stream.mjpg (MJPEG: the query picks
// the profile like a handshake; JPEGs come from the encoder thread). Every request passes
// HttpAccess first; errors are plain-text 4xx/5xx replies, counted. Server thread. Private to
// ipc/stream.

#include <functional>
#include <string>

#include "http_access.h"
#include "navmap/ipc/stream/metrics_registry.h"
#include "stream_transport.h"

namespace navmap::ipc::stream_detail {

class HttpTransport : public StreamTransport {
public:
    /// `ownMetrics` adds the server's navmap_stream_* families; `status_json` is the /status body.
    HttpTransport(ClientHub& hub, std::function<void(MetricsRegistry&)> own_metrics,
                  std::function<std::string()> status_json);

    int port() const noexcept { return m_port; }

    void onInput(StreamConn& c) override;
    void sendFrame(StreamConn& c) override;
    std::string handshakeTimeoutReply(const std::string& why) const override;

protected:
    Result<int> openListener() override;
    std::string refusalReply(const std::string& message) const override;
    Phase firstPhase() const override { return Phase::HttpHead; }

private:
    void onRequest(StreamConn& c, const std::string& head);
    void refuseAccess(StreamConn& c, int code, const std::string& why);
    void servePage(StreamConn& c);
    void serveMetrics(StreamConn& c);
    void startMjpeg(StreamConn& c, const StreamHttpRequest& req);
    void reply(StreamConn& c, int code, const char* reason, const char* content_type, const std::string& body,
               const char* extra_headers = "");

    HttpAccess m_access;
    std::function<void(MetricsRegistry&)> m_own_metrics;
    std::function<std::string()> m_status_json;
    int m_port = -1;
};

}  // namespace navmap::ipc::stream_detail
