// SPDX-License-Identifier: Apache-2.0
#include "stream_report.h"

#include <nlohmann/json.hpp>

#include "navmap/ipc/stream/frame_server_stats_json.h"

namespace navmap::ipc::stream_detail {

namespace {

double d(std::uint64_t v) { return static_cast<double>(v); }

void collectTraffic(MetricsRegistry& r, const FrameServerStats& s) {
    r.gauge("navmap_stream_clients", "Frame-stream clients connected now, by transport.")
        .sample({{"transport", "shm"}}, d(s.shm_clients))
        .sample({{"transport", "tcp"}}, d(s.tcp_clients))
        .sample({{"transport", "mjpeg"}}, d(s.mjpeg_clients))
        .sample({{"transport", "dmabuf"}}, d(s.dmabuf_clients));
    r.gauge("navmap_stream_rings",
            "Shared-memory rings: with clients (one per profile and pixel format), and idle ones kept for reuse "
            "because a client may still map them.")
        .sample({{"state", "active"}}, d(s.rings))
        .sample({{"state", "idle"}}, d(s.rings_idle));
    r.counter("navmap_stream_rings_reused_total", "Idle rings that got a client again instead of a new ring.")
        .sample(d(s.rings_reused));
    r.counter("navmap_stream_frames_published_total", "Frames published by the render loop.").sample(d(s.published));
    r.counter("navmap_stream_frames_sent_total", "Frames handed to clients.").sample(d(s.frames_sent));
    r.counter("navmap_stream_dmabuf_frames_sent_total",
              "Of the frames handed to clients, those sent as exported dma-bufs (no pixel copied).")
        .sample(d(s.dmabuf_frames_sent));
    r.counter("navmap_stream_dmabuf_fds_sent_total",
              "Buffer fds passed to dma-buf clients (once per client and buffer allocation).")
        .sample(d(s.dmabuf_fds_sent));
    r.counter("navmap_stream_statuses_sent_total", "Status headers handed to clients waiting for their first frame.")
        .sample(d(s.statuses_sent));
    r.counter("navmap_stream_frames_dropped_total", "Frames skipped because a client was busy.")
        .sample(d(s.frames_dropped));
    r.counter("navmap_stream_held_frames_overwritten_total",
              "Frames written over a slot a client held, because every slot of its ring was held.")
        .sample(d(s.pinned_overwrites));
    r.counter("navmap_stream_connections_total", "Connections accepted.").sample(d(s.accepted));
}

void collectRejections(MetricsRegistry& r, const FrameServerStats& s) {
    r.counter("navmap_stream_errors_total", "Rejected input, by kind.")
        .sample({{"kind", "handshake"}}, d(s.handshake_errors))
        .sample({{"kind", "protocol"}}, d(s.protocol_errors))
        .sample({{"kind", "http"}}, d(s.http_errors));
    r.counter("navmap_stream_stall_disconnects_total", "Clients disconnected after the stall timeout.")
        .sample(d(s.stall_disconnects));
    r.counter("navmap_stream_timeouts_total",
              "Connections closed for not finishing the handshake, or not getting a first frame, in time.")
        .sample({{"kind", "handshake"}}, d(s.handshake_timeouts))
        .sample({{"kind", "first_frame"}}, d(s.first_frame_timeouts));
    r.counter("navmap_stream_refusals_total", "Connections and requests refused, by reason.")
        .sample({{"reason", "peer"}}, d(s.refused_peer))
        .sample({{"reason", "transport_full"}}, d(s.refused_transport_full))
        .sample({{"reason", "uid_full"}}, d(s.refused_uid_full))
        .sample({{"reason", "address_full"}}, d(s.refused_address_full))
        .sample({{"reason", "not_rendered"}}, d(s.refused_not_rendered))
        .sample({{"reason", "ring_memory"}}, d(s.refused_ring_memory))
        .sample({{"reason", "http_host"}}, d(s.refused_host))
        .sample({{"reason", "http_token"}}, d(s.refused_token));
}

void collectCosts(MetricsRegistry& r, const FrameServerStats& s, const EncoderStats& es,
                  std::size_t ring_memory_bytes) {
    r.gauge("navmap_stream_ring_bytes", "Shared memory of all rings, and its ceiling (0: none).")
        .sample({{"stat", "used"}}, d(s.ring_bytes))
        .sample({{"stat", "limit"}}, d(ring_memory_bytes));
    r.gauge("navmap_stream_publish_seconds", "Render-thread cost of publish().")
        .sample({{"stat", "last"}}, s.publish_ms_last / 1000.0)
        .sample({{"stat", "max"}}, s.publish_ms_max / 1000.0);
    r.counter("navmap_stream_encodes_total", "Frames compressed (zlib) or JPEG-encoded by the encoder thread.")
        .sample(d(es.encoded));
    r.counter("navmap_stream_encodes_superseded_total",
              "Encode requests replaced by a newer frame before they started.")
        .sample(d(es.replaced));
    r.gauge("navmap_stream_encode_seconds", "Encoder-thread time per frame.")
        .sample({{"format", "zlib"}, {"stat", "last"}}, es.zlib_ms_last / 1000.0)
        .sample({{"format", "zlib"}, {"stat", "max"}}, es.zlib_ms_max / 1000.0)
        .sample({{"format", "jpeg"}, {"stat", "last"}}, es.jpeg_ms_last / 1000.0)
        .sample({{"format", "jpeg"}, {"stat", "max"}}, es.jpeg_ms_max / 1000.0);
}

}  // namespace

void collectStreamMetrics(MetricsRegistry& r, const FrameServerStats& s, const EncoderStats& es,
                          std::size_t ring_memory_bytes) {
    collectTraffic(r, s);
    collectRejections(r, s);
    collectCosts(r, s, es, ring_memory_bytes);
}

std::string streamStatusJson(const FrameServerStats& s, const std::vector<ActiveProfile>& active,
                             const std::function<std::string()>& daemon_json) {
    nlohmann::json j;
    j["stream"] = frameServerStatsJson(s);
    nlohmann::json profiles = nlohmann::json::array();
    for (const auto& a : active) {
        profiles.push_back(
            {{"view", a.view}, {"width", a.width}, {"height", a.height}, {"fps", a.max_fps}, {"clients", a.clients}});
    }
    j["stream"]["profiles"] = profiles;
    j["daemon"] = nullptr;
    if (daemon_json) {
        const std::string text = daemon_json();
        auto parsed = nlohmann::json::parse(text, nullptr, false);
        j["daemon"] = parsed.is_discarded() ? nlohmann::json(text) : parsed;
    }
    return j.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
}

}  // namespace navmap::ipc::stream_detail
