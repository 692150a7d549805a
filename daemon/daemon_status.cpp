// SPDX-License-Identifier: Apache-2.0
#include "daemon_status.h"

#include <sstream>

#include "navmap/version.h"

namespace navmap::daemon {

void DaemonStatus::publish(const StatusSample& m) {
    const auto& in = m.input;
    const auto& fs = m.stream;
    const auto& pose = m.pose;
    nlohmann::json st;
    st["version"] = NAVMAP_VERSION;
    st["uptime_s"] = m.uptime_s;
    st["memory"] = {{"rss_bytes", m.memory.rss}, {"peak_rss_bytes", m.memory.peak}};
    st["config"] = {{"path", m.config_path},
                    {"reloads", m.reloads},
                    {"reload_errors", m.reload_errors},
                    {"last_reload_error", m.last_reload_error},
                    {"style", m.night ? "night" : "day"}};
    st["input"] = {
        {"source", in.source},
        {"frames", in.frames},
        {"decoded_values", in.decoder.values},
        {"rejected_values", in.decoder.rejected},
        {"counter_gaps", in.decoder.counterGaps},
        {"rejected_fixes", in.estimator.rejectedJump + in.estimator.rejectedRange + in.estimator.rejectedNaN},
        {"can_error_frames", in.can_error_frames},
        {"can_bus_off", in.can_bus_off},
        {"can_kernel_drops", in.can_kernel_drops},
        {"can_state", in.can_state},
        {"replay_malformed_lines", in.replay_malformed_lines},
        {"replay_time_errors", in.replay_time_errors},
        {"error", in.error}};
    st["road_graph"] = m.road_graph;
    st["position"] = {{"valid", pose.valid},
                      {"stale", pose.stale},
                      {"speed_kmh", pose.speedMps * 3.6},
                      {"heading_deg", pose.headingDeg},
                      {"match_confidence", pose.matchConfidence}};
    if (!m.route_id.empty()) st["route"] = {{"id", m.route_id}, {"driven_m", m.route_driven_m}};
    nlohmann::json profiles = nlohmann::json::array();
    for (const auto& d : *m.displays) {
        const DisplayStats& s = d->stats();
        profiles.push_back({{"name", d->profile().name},
                            {"rendered", s.rendered},
                            {"published", s.published},
                            {"frame_p50_ms", s.frame_ms.quantile(0.5)},
                            {"frame_p99_ms", s.frame_ms.quantile(0.99)},
                            {"latency_p50_ms", s.latency_ms.quantile(0.5)},
                            {"latency_p99_ms", s.latency_ms.quantile(0.99)},
                            {"tiles_drawn", s.tiles_drawn},
                            {"tiles_pending", s.tiles_pending},
                            {"state", d->mapReady() ? "rendering" : "loading map"},
                            {"held_back", s.held_back},
                            {"tiles_wanted", s.tiles_wanted},
                            {"tiles_uploaded", s.tiles_uploaded},
                            {"attribution", d->hasAttribution()}});
    }
    st["profiles"] = profiles;
    st["stream"] = {{"clients", fs.clients},
                    {"frames_sent", fs.framesSent},
                    {"frames_dropped", fs.framesDropped},
                    {"stall_disconnects", fs.stallDisconnects},
                    {"handshake_errors", fs.handshakeErrors},
                    {"timeouts", {{"handshake", fs.handshakeTimeouts}, {"first_frame", fs.firstFrameTimeouts}}},
                    {"refusals",
                     {{"peer", fs.refusedPeer},
                      {"transport_full", fs.refusedTransportFull},
                      {"uid_full", fs.refusedUidFull},
                      {"not_rendered", fs.refusedNotRendered},
                      {"ring_memory", fs.refusedRingMemory},
                      {"http_host", fs.refusedHost},
                      {"http_token", fs.refusedToken}}},
                    {"ring_bytes", fs.ringBytes},
                    {"last_error", fs.lastError}};
    st["tile_cache"] = {{"resident_bytes", m.cache.resident_bytes},
                        {"hits", m.cache.hits},
                        {"misses", m.cache.misses},
                        {"load_p99_ms", m.cache.load_p99_ms},
                        {"corrupt", m.cache.corrupt}};
    m_json.store(std::make_shared<const nlohmann::json>(std::move(st)));
}

std::string DaemonStatus::systemdLine(const StatusSample& m) {
    std::ostringstream line;
    line << m.stream.clients << " clients, "
         << (m.pose.valid ? (m.pose.stale ? "position lost" : "position ok") : "no position yet");
    for (const auto& d : *m.displays) line << ", " << d->profile().name << " " << d->stats().rendered << " frames";
    return line.str();
}

}  // namespace navmap::daemon
