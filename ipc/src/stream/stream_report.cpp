// SPDX-License-Identifier: Apache-2.0
#include "stream_report.h"

#include <nlohmann/json.hpp>

namespace navmap::ipc::stream_detail {

namespace {

double d(std::uint64_t v) { return static_cast<double>(v); }

void collectTraffic(MetricsRegistry& r, const FrameServerStats& s) {
    r.gauge("navmap_stream_clients", "Frame-stream clients connected now, by transport.")
        .sample({{"transport", "shm"}}, d(s.shmClients))
        .sample({{"transport", "tcp"}}, d(s.tcpClients))
        .sample({{"transport", "mjpeg"}}, d(s.mjpegClients));
    r.gauge("navmap_stream_rings", "Shared-memory rings (one per profile and pixel format with clients).")
        .sample(d(s.rings));
    r.counter("navmap_stream_frames_published_total", "Frames published by the render loop.").sample(d(s.published));
    r.counter("navmap_stream_frames_sent_total", "Frames handed to clients.").sample(d(s.framesSent));
    r.counter("navmap_stream_statuses_sent_total", "Status headers handed to clients waiting for their first frame.")
        .sample(d(s.statusesSent));
    r.counter("navmap_stream_frames_dropped_total", "Frames skipped because a client was busy.")
        .sample(d(s.framesDropped));
    r.counter("navmap_stream_held_frames_overwritten_total",
              "Frames written over a slot a client held, because every slot of its ring was held.")
        .sample(d(s.pinnedOverwrites));
    r.counter("navmap_stream_connections_total", "Connections accepted.").sample(d(s.accepted));
}

void collectRejections(MetricsRegistry& r, const FrameServerStats& s) {
    r.counter("navmap_stream_errors_total", "Rejected input, by kind.")
        .sample({{"kind", "handshake"}}, d(s.handshakeErrors))
        .sample({{"kind", "protocol"}}, d(s.protocolErrors))
        .sample({{"kind", "http"}}, d(s.httpErrors));
    r.counter("navmap_stream_stall_disconnects_total", "Clients disconnected after the stall timeout.")
        .sample(d(s.stallDisconnects));
    r.counter("navmap_stream_timeouts_total",
              "Connections closed for not finishing the handshake, or not getting a first frame, in time.")
        .sample({{"kind", "handshake"}}, d(s.handshakeTimeouts))
        .sample({{"kind", "first_frame"}}, d(s.firstFrameTimeouts));
    r.counter("navmap_stream_refusals_total", "Connections and requests refused, by reason.")
        .sample({{"reason", "peer"}}, d(s.refusedPeer))
        .sample({{"reason", "transport_full"}}, d(s.refusedTransportFull))
        .sample({{"reason", "uid_full"}}, d(s.refusedUidFull))
        .sample({{"reason", "not_rendered"}}, d(s.refusedNotRendered))
        .sample({{"reason", "ring_memory"}}, d(s.refusedRingMemory))
        .sample({{"reason", "http_host"}}, d(s.refusedHost))
        .sample({{"reason", "http_token"}}, d(s.refusedToken));
}

void collectCosts(MetricsRegistry& r, const FrameServerStats& s, const EncoderStats& es, std::size_t ringMemoryBytes) {
    r.gauge("navmap_stream_ring_bytes", "Shared memory of all rings, and its ceiling (0: none).")
        .sample({{"stat", "used"}}, d(s.ringBytes))
        .sample({{"stat", "limit"}}, d(ringMemoryBytes));
    r.gauge("navmap_stream_publish_seconds", "Render-thread cost of publish().")
        .sample({{"stat", "last"}}, s.publishMsLast / 1000.0)
        .sample({{"stat", "max"}}, s.publishMsMax / 1000.0);
    r.counter("navmap_stream_encodes_total", "Frames compressed (zlib) or JPEG-encoded by the encoder thread.")
        .sample(d(es.encoded));
    r.counter("navmap_stream_encodes_superseded_total",
              "Encode requests replaced by a newer frame before they started.")
        .sample(d(es.replaced));
    r.gauge("navmap_stream_encode_seconds", "Encoder-thread time per frame.")
        .sample({{"format", "zlib"}, {"stat", "last"}}, es.zlibMsLast / 1000.0)
        .sample({{"format", "zlib"}, {"stat", "max"}}, es.zlibMsMax / 1000.0)
        .sample({{"format", "jpeg"}, {"stat", "last"}}, es.jpegMsLast / 1000.0)
        .sample({{"format", "jpeg"}, {"stat", "max"}}, es.jpegMsMax / 1000.0);
}

nlohmann::json streamCounters(const FrameServerStats& s) {
    return {{"clients", s.clients},
            {"shm_clients", s.shmClients},
            {"tcp_clients", s.tcpClients},
            {"mjpeg_clients", s.mjpegClients},
            {"rings", s.rings},
            {"published", s.published},
            {"sent", s.framesSent},
            {"statuses_sent", s.statusesSent},
            {"dropped", s.framesDropped},
            {"stall_disconnects", s.stallDisconnects},
            {"timeouts", {{"handshake", s.handshakeTimeouts}, {"first_frame", s.firstFrameTimeouts}}},
            {"refusals",
             {{"peer", s.refusedPeer},
              {"transport_full", s.refusedTransportFull},
              {"uid_full", s.refusedUidFull},
              {"not_rendered", s.refusedNotRendered},
              {"ring_memory", s.refusedRingMemory},
              {"http_host", s.refusedHost},
              {"http_token", s.refusedToken}}},
            {"ring_bytes", s.ringBytes},
            {"publish_ms_last", s.publishMsLast}};
}

}  // namespace

void collectStreamMetrics(MetricsRegistry& r, const FrameServerStats& s, const EncoderStats& es,
                          std::size_t ringMemoryBytes) {
    collectTraffic(r, s);
    collectRejections(r, s);
    collectCosts(r, s, es, ringMemoryBytes);
}

std::string streamStatusJson(const FrameServerStats& s, const std::vector<ActiveProfile>& active,
                             const std::function<std::string()>& daemonJson) {
    nlohmann::json j;
    j["stream"] = streamCounters(s);
    nlohmann::json profiles = nlohmann::json::array();
    for (const auto& a : active) {
        profiles.push_back(
            {{"view", a.view}, {"width", a.width}, {"height", a.height}, {"fps", a.maxFps}, {"clients", a.clients}});
    }
    j["stream"]["profiles"] = profiles;
    j["daemon"] = nullptr;
    if (daemonJson) {
        const std::string text = daemonJson();
        auto parsed = nlohmann::json::parse(text, nullptr, false);
        j["daemon"] = parsed.is_discarded() ? nlohmann::json(text) : parsed;
    }
    return j.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
}

}  // namespace navmap::ipc::stream_detail
