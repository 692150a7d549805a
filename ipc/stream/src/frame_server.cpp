// SPDX-License-Identifier: Apache-2.0
// FrameServer: composes the frame server from its parts (docs/frame-protocol.md, "Inside the
// server"): one poll loop on the server thread, three transports that listen on it (ShmTransport:
// Unix socket, TcpTransport, HttpTransport), the ClientHub their connections share, the RingSet
// publish() writes into and the FrameEncoder thread that compresses and JPEG-encodes. The render
// thread only copies into rings and hands over statuses; it never waits for a client.

#include "navmap/ipc/stream/frame_server.h"

#include <algorithm>
#include <atomic>
#include <mutex>
#include <nlohmann/json.hpp>
#include <thread>

#include "client_hub.h"
#include "frame_encoder.h"
#include "http_transport.h"
#include "navmap/ipc/client/frame_header.h"
#include "navmap/ipc/net/poll_loop.h"
#include "shm_transport.h"
#include "stream_report.h"
#include "stream_rings.h"
#include "stream_stats.h"
#include "tcp_transport.h"

namespace navmap::ipc {

using stream_detail::Clock;
using stream_detail::PendingStatus;

class FrameServer::Impl {
public:
    explicit Impl(FrameServerOptions options);
    ~Impl() { stop(); }

    Status start();
    void stop();
    std::size_t publish(const std::string& profile, const FrameView& frame);
    std::size_t publishDmabuf(const std::string& profile, const FrameView& info, const DmabufBuffer& buffer);
    std::uint32_t dmabufBusy(const std::string& profile) const { return m_rings.dmabufBusy(profile); }
    Status publishStatus(const std::string& key, int width, int height, std::string json);
    FrameServerStats stats() const { return m_stats.snapshot(); }
    std::vector<ActiveProfile> activeProfiles() const { return m_stats.active(); }
    void collectMetrics(MetricsRegistry& registry) const;
    std::string statusJson() const;
    int tcpPort() const noexcept { return m_tcp.port(); }
    int httpPort() const noexcept { return m_http.port(); }

    FrameServerOptions m_options;

private:
    Status checkOptions() const;
    Status listen();
    void run();
    std::vector<PendingStatus> takeStatuses();

    stream_detail::StreamStats m_stats;
    net::PollLoop m_loop{"frame server"};
    stream_detail::FrameEncoder m_encoder;  // zlib/JPEG off the I/O thread
    stream_detail::RingSet m_rings;
    stream_detail::ClientHub m_hub;
    stream_detail::ShmTransport m_shm;
    stream_detail::TcpTransport m_tcp;
    stream_detail::HttpTransport m_http;
    std::thread m_thread;
    std::atomic<bool> m_running{false};

    std::mutex m_status_mutex;  // guards the hand-over of statuses only, never I/O
    std::vector<PendingStatus> m_statuses;
};

FrameServer::Impl::Impl(FrameServerOptions options)
    : m_options(std::move(options)),
      m_encoder(m_options.jpeg_quality, [this] { m_loop.wake(); }),
      m_rings(m_options, m_stats),
      m_hub(m_options, m_stats, m_rings, m_loop, m_encoder),
      m_shm(m_hub),
      m_tcp(m_hub),
      m_http(
          m_hub, [this](MetricsRegistry& r) { collectMetrics(r); }, [this] { return statusJson(); }) {
    m_hub.setTransport(m_shm);
    m_hub.setTransport(m_tcp);
    m_hub.setTransport(m_http);
}

Status FrameServer::Impl::checkOptions() const {
    if (m_options.ring_slots < 2 || m_options.ring_slots > 64) {
        return Error{"FrameServer: ringSlots must be in [2, 64]"};
    }
    if (m_options.max_clients_per_transport < 1 || m_options.max_clients_per_uid < 1) {
        return Error{"FrameServer: maxClientsPerTransport and maxClientsPerUid must be at least 1"};
    }
    return {};
}

Status FrameServer::Impl::listen() {
    if (auto st = m_loop.open(); !st) {
        return st;
    }
    for (stream_detail::StreamTransport* t :
         {static_cast<stream_detail::StreamTransport*>(&m_shm), static_cast<stream_detail::StreamTransport*>(&m_tcp),
          static_cast<stream_detail::StreamTransport*>(&m_http)}) {
        if (auto st = t->listen(m_loop); !st) {
            return st;
        }
    }
    return {};
}

Status FrameServer::Impl::start() {
    if (m_running) {
        return {};
    }
    if (auto st = checkOptions(); !st) {
        return st;
    }
    if (auto st = listen(); !st) {
        return st;
    }
    if (auto st = m_encoder.start(); !st) {
        return st;
    }
    m_running = true;
    m_thread = std::thread([this] { run(); });
    return {};
}

void FrameServer::Impl::stop() {
    if (m_running.exchange(false)) {
        m_loop.wake();
        m_thread.join();
    }
    m_encoder.stop();  // before the wake-up eventfd goes
    m_hub.clear();
    m_rings.clear();
    m_shm.close();
    m_tcp.close();
    m_http.close();
    m_loop.close();
}

void FrameServer::Impl::run() {
    while (m_running) {
        if (auto st = m_loop.runOnce(m_hub.nextWait()); !st) {
            m_stats.setLastError(st.message());
        }
        m_hub.deliverStatuses(takeStatuses());  // before frames: a status published before a frame arrives before it
        m_hub.deliverNewFrames();
        m_hub.checkTimeouts();
        m_hub.reap();
    }
}

std::size_t FrameServer::Impl::publish(const std::string& profile, const FrameView& frame) {
    const auto t0 = Clock::now();
    const std::size_t written = m_rings.publish(profile, frame);
    if (written > 0) {
        m_stats.countPublished();
        m_loop.wake();
        m_stats.recordPublishTime(std::chrono::duration_cast<std::chrono::nanoseconds>(Clock::now() - t0).count());
    }
    return written;
}

std::size_t FrameServer::Impl::publishDmabuf(const std::string& profile, const FrameView& info,
                                             const DmabufBuffer& buffer) {
    const std::size_t reached = m_rings.publishDmabuf(profile, info, buffer);
    if (reached > 0) {
        m_stats.countPublished();
        m_loop.wake();
    }
    return reached;
}

Status FrameServer::Impl::publishStatus(const std::string& key, int width, int height, std::string json) {
    const auto* text = reinterpret_cast<const std::uint8_t*>(json.data());
    if (auto s = validateTextPayload(FrameKind::Status, text, json.size()); !s) {
        return Error{"publishStatus(" + key + "): " + s.message()};
    }
    if (const auto j = nlohmann::json::parse(json, nullptr, false); j.is_discarded() || !j.is_object()) {
        return Error{"publishStatus(" + key + "): status: not a JSON object"};
    }
    if (width <= 0 || height <= 0) {
        return Error{"publishStatus(" + key + "): bad size " + std::to_string(width) + "x" + std::to_string(height)};
    }
    // Header and text are built here, once; the server thread only queues the bytes per client.
    FrameHeader h;
    h.kind = FrameKind::Status;
    h.payload_bytes = static_cast<std::uint32_t>(json.size());
    const auto hb = encodeFrameHeader(h);
    auto bytes = std::make_shared<std::string>(hb.begin(), hb.end());
    bytes->append(json);
    PendingStatus st{key, static_cast<std::uint32_t>(width), static_cast<std::uint32_t>(height), std::move(bytes)};
    {
        std::lock_guard lock(m_status_mutex);
        const auto same = std::find_if(m_statuses.begin(), m_statuses.end(), [&](const PendingStatus& p) {
            return p.key == st.key && p.width == st.width && p.height == st.height;
        });
        if (same != m_statuses.end()) {
            *same = std::move(st);  // not sent yet: the newer status replaces it
        } else {
            m_statuses.push_back(std::move(st));
        }
    }
    m_loop.wake();
    return {};
}

std::vector<PendingStatus> FrameServer::Impl::takeStatuses() {
    std::vector<PendingStatus> statuses;
    std::lock_guard lock(m_status_mutex);
    statuses.swap(m_statuses);
    return statuses;
}

void FrameServer::Impl::collectMetrics(MetricsRegistry& registry) const {
    // zlib and JPEG figures come from the encoder thread.
    stream_detail::collectStreamMetrics(registry, stats(), m_encoder.stats(), m_options.ring_memory_bytes);
}

std::string FrameServer::Impl::statusJson() const {
    const FrameServerStats s = stats();
    return stream_detail::streamStatusJson(s, activeProfiles(), m_options.status_json);
}

// --- FrameServer ---

FrameServer::FrameServer(FrameServerOptions options) : m_impl(std::make_unique<Impl>(std::move(options))) {}
FrameServer::~FrameServer() = default;
Status FrameServer::start() { return m_impl->start(); }
void FrameServer::stop() { m_impl->stop(); }
std::size_t FrameServer::publish(const std::string& profile, const FrameView& frame) {
    return m_impl->publish(profile, frame);
}
Status FrameServer::publishStatus(const std::string& profile, int width, int height, std::string json) {
    return m_impl->publishStatus(profile, width, height, std::move(json));
}
std::size_t FrameServer::publishDmabuf(const std::string& profile, const FrameView& info, DmabufBuffer buffer) {
    return m_impl->publishDmabuf(profile, info, buffer);
}
std::uint32_t FrameServer::dmabufBusy(const std::string& profile) const { return m_impl->dmabufBusy(profile); }
std::vector<ActiveProfile> FrameServer::activeProfiles() const { return m_impl->activeProfiles(); }
FrameServerStats FrameServer::stats() const { return m_impl->stats(); }
void FrameServer::collectMetrics(MetricsRegistry& registry) const { m_impl->collectMetrics(registry); }
std::string FrameServer::metricsText() const {
    MetricsRegistry registry;
    m_impl->collectMetrics(registry);
    return registry.text();
}
int FrameServer::tcpPort() const noexcept { return m_impl->tcpPort(); }
int FrameServer::httpPort() const noexcept { return m_impl->httpPort(); }
const FrameServerOptions& FrameServer::options() const noexcept { return m_impl->m_options; }

}  // namespace navmap::ipc
