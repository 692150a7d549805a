// SPDX-License-Identifier: Apache-2.0
#include "http_transport.h"

#include <algorithm>
#include <nlohmann/json.hpp>
#include <sstream>
#include <stdexcept>
#include <utility>
#include <vector>

#include "stream_listen.h"
#include "stream_page.h"
#include "stream_rings.h"

namespace navmap::ipc::stream_detail {

namespace {

// The query of /stream.mjpg as a handshake: ?profile=hud or ?width=640&height=240&view=bird&fps=10.
nlohmann::json mjpegRequest(const StreamHttpRequest& req, const FrameServerOptions& options) {
    nlohmann::json j;
    j["version"] = 1;
    bool has_profile = false;
    for (const auto& [k, v] : req.query) {
        if (k == "token") {
            continue;  // checked by HttpAccess
        }
        const bool numeric = !v.empty() && v.size() < 10 &&
                             std::all_of(v.begin(), v.end(), [](char ch) { return ch >= '0' && ch <= '9'; });
        if (numeric) {
            j[k] = std::stoi(v);
        } else {
            j[k] = v;
        }
        has_profile = has_profile || k == "profile" || k == "width";
    }
    if (!has_profile) {
        j["profile"] = options.mjpeg_profile;
    }
    // A rendered profile by its name (?profile=rear) stands for its view and size.
    if (j.contains("profile") && j["profile"].is_string() && !j.contains("width")) {
        for (const auto& r : options.rendered_profiles) {
            if (r.name == j["profile"].get<std::string>()) {
                j["width"] = r.width;
                j["height"] = r.height;
                j["view"] = r.view;
            }
        }
    }
    j["format"] = "rgba8";
    j["payload"] = "raw";
    return j;
}

bool hasHighBytes(const std::string& s) {
    return std::any_of(s.begin(), s.end(), [](char ch) { return static_cast<unsigned char>(ch) >= 0x80; });
}

}  // namespace

HttpTransport::HttpTransport(ClientHub& hub, std::function<void(MetricsRegistry&)> own_metrics,
                             std::function<std::string()> status_json)
    : StreamTransport(Via::Http, hub),
      m_access(hub.options(), hub.stats()),
      m_own_metrics(std::move(own_metrics)),
      m_status_json(std::move(status_json)) {}

Result<int> HttpTransport::openListener() {
    const FrameServerOptions& o = m_hub.options();
    if (o.http_port < 0) {
        return -1;
    }
    auto fd = listenTcp(o.bind_address, o.http_port);
    if (fd) {
        m_port = boundPort(fd.value());
    }
    return fd;
}

std::string HttpTransport::refusalReply(const std::string& message) const {
    const std::string body = message + "\n";
    return "HTTP/1.0 503 Service Unavailable\r\nContent-Type: text/plain\r\nContent-Length: " +
           std::to_string(body.size()) + "\r\nConnection: close\r\n\r\n" + body;
}

std::string HttpTransport::handshakeTimeoutReply(const std::string& why) const {
    return "HTTP/1.0 408 Request Timeout\r\nContent-Type: text/plain\r\nContent-Length: " +
           std::to_string(why.size() + 1) + "\r\nConnection: close\r\n\r\n" + why + "\n";
}

void HttpTransport::onInput(StreamConn& c) {
    if (c.phase != Phase::HttpHead) {
        c.in.clear();
        return;
    }
    if (hasControlBytes(c.in) || hasHighBytes(c.in)) {
        reply(c, 400, "Bad Request", "text/plain", "bad request: binary data\n");
        return;
    }
    auto end = c.in.find("\r\n\r\n");
    std::size_t end_len = 4;
    if (end == std::string::npos) {
        end = c.in.find("\n\n");
        end_len = 2;
    }
    if ((end == std::string::npos ? c.in.size() : end) > kMaxHttpRequestBytes) {
        reply(c, 431, "Request Header Fields Too Large", "text/plain", "request head too large\n");
        return;
    }
    if (end == std::string::npos) {
        if (c.in.size() >= 4 && c.in.compare(0, 4, "GET ") != 0 && c.in.find('\n') != std::string::npos &&
            c.in.find("HTTP/1.") == std::string::npos) {
            // The first line is complete and is no HTTP request line: answer now.
            reply(c, 400, "Bad Request", "text/plain", "bad request line\n");
        }
        return;
    }
    const std::string head = c.in.substr(0, end + end_len);
    c.in.clear();
    onRequest(c, head);
}

void HttpTransport::onRequest(StreamConn& c, const std::string& head) {
    auto parsed = parseStreamHttpRequest(head);
    if (!parsed) {
        reply(c, 400, "Bad Request", "text/plain", parsed.error().message + "\n");
        return;
    }
    const StreamHttpRequest& req = parsed.value();
    int denied = 0;
    if (const std::string why = m_access.check(c.fd.get(), m_port, req, &denied); !why.empty()) {
        refuseAccess(c, denied, why);
        return;
    }
    if (req.method != "GET") {
        reply(c, 405, "Method Not Allowed", "text/plain", "only GET\n");
    } else if (req.path == "/" || req.path == "/index.html") {
        servePage(c);
    } else if (req.path == "/status") {
        reply(c, 200, "OK", "application/json", m_status_json());
    } else if (req.path == "/metrics") {
        serveMetrics(c);
    } else if (req.path == "/stream.mjpg") {
        startMjpeg(c, req);
    } else {
        reply(c, 404, "Not Found", "text/plain", "no such page: " + req.path.substr(0, 128) + "\n");
    }
}

void HttpTransport::refuseAccess(StreamConn& c, int code, const std::string& why) {
    if (code == 401) {
        reply(c, 401, "Unauthorized", "text/plain", why, "WWW-Authenticate: Bearer realm=\"navmap\"\r\n");
    } else if (code == 421) {
        reply(c, 421, "Misdirected Request", "text/plain", why);
    } else {
        reply(c, 400, "Bad Request", "text/plain", why);
    }
}

void HttpTransport::servePage(StreamConn& c) {
    std::vector<std::string> names;
    for (const auto& r : m_hub.options().rendered_profiles) {
        names.push_back(r.name);
    }
    reply(c, 200, "OK", "text/html; charset=utf-8", viewerPage(m_hub.options().mjpeg_profile, names));
}

void HttpTransport::serveMetrics(StreamConn& c) {
    // One registry per scrape: the server's families, then the daemon's; a family declared
    // twice is a bug, answered with 500 and its name instead of a malformed exposition.
    MetricsRegistry registry;
    try {
        m_own_metrics(registry);
        if (m_hub.options().metrics) {
            m_hub.options().metrics(registry);
        }
    } catch (const std::logic_error& e) {
        reply(c, 500, "Internal Server Error", "text/plain", std::string("metrics: ") + e.what() + "\n");
        return;
    }
    reply(c, 200, "OK", "text/plain; version=0.0.4", registry.text());
}

void HttpTransport::startMjpeg(StreamConn& c, const StreamHttpRequest& req) {
    // The query selects the profile exactly like a handshake and goes through the same validation.
    const nlohmann::json j = mjpegRequest(req, m_hub.options());
    auto r = parseStreamRequest(j.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace));
    if (!r) {
        reply(c, 400, "Bad Request", "text/plain", r.error().message + "\n");
        return;
    }
    auto key = m_hub.rings().resolve(r.value().profile);
    if (!key) {
        reply(c, 400, "Bad Request", "text/plain", key.error().message + "\n");
        return;
    }
    auto ring = m_hub.rings().attach(key.value(), r.value().profile);
    if (!ring) {
        const std::string& message = ring.error().message;
        const bool full = message.rfind("ring memory:", 0) == 0;
        reply(c, full ? 503 : 500, full ? "Service Unavailable" : "Internal Server Error", "text/plain",
              message + "\n");
        return;
    }
    c.ring = ring.value();
    c.fps = r.value().profile.fps;
    c.phase = Phase::Mjpeg;
    c.stream_since = Clock::now();
    static const char kHead[] =
        "HTTP/1.0 200 OK\r\nContent-Type: multipart/x-mixed-replace; boundary=navmapframe\r\n"
        "Cache-Control: no-store\r\nConnection: close\r\n\r\n";
    c.queue(kHead, sizeof(kHead) - 1);
    m_hub.flush(c);
    m_hub.refreshRings();
    m_hub.offerIfNew(c, Clock::now());
}

void HttpTransport::sendFrame(StreamConn& c) {
    c.pending = false;
    // Encoded by the encoder thread; the newest finished one.
    const std::shared_ptr<const EncodedFrame> encoded = c.ring->jpeg;
    if (!encoded || encoded->sequence <= c.last_sent) {
        return;
    }
    const std::uint64_t seq = encoded->sequence;
    std::ostringstream os;
    os << "--navmapframe\r\nContent-Type: image/jpeg\r\nContent-Length: " << encoded->bytes.size()
       << "\r\nX-Navmap-Sequence: " << seq << "\r\nX-Navmap-Source-Time-Ns: " << encoded->header.source_time_ns
       << "\r\nX-Navmap-Dropped: " << c.dropped << "\r\n\r\n";
    const std::string part_head = os.str();
    c.queue(part_head.data(), part_head.size());
    c.queue(encoded->bytes.data(), encoded->bytes.size());
    c.queue("\r\n", 2);
    m_hub.frameSent(c, seq);
}

void HttpTransport::reply(StreamConn& c, int code, const char* reason, const char* content_type,
                          const std::string& body, const char* extra_headers) {
    if (code >= 400) {
        m_hub.stats().countError(&FrameServerStats::http_errors,
                                 c.peer + ": HTTP " + std::to_string(code) + " " + body);
    }
    std::ostringstream os;
    os << "HTTP/1.0 " << code << ' ' << reason << "\r\nContent-Type: " << content_type
       << "\r\nContent-Length: " << body.size() << "\r\nCache-Control: no-store\r\nConnection: close\r\n"
       << extra_headers << "\r\n"
       << body;
    m_hub.finishWith(c, os.str());
}

}  // namespace navmap::ipc::stream_detail
