// SPDX-License-Identifier: Apache-2.0
#include "daemon_status.h"

#include <sstream>

#include "navmap/ipc/stream/frame_server_stats_json.h"
#include "navmap/version.h"

namespace navmap::daemon {

void DaemonStatus::publish(const StatusSample& m) {
    const auto& in = m.input;
    const auto& pose = m.pose;
    nlohmann::json st;
    st["version"] = NAVMAP_VERSION;
    st["uptime_s"] = m.uptime_s;
    st["memory"] = {{"rss_bytes", m.memory.rss}, {"peak_rss_bytes", m.memory.peak}};
    st["config"] = {{"path", m.config_path},
                    {"reloads", m.reloads},
                    {"reload_errors", m.reload_errors},
                    {"last_reload_error", m.last_reload_error},
                    {"style", m.config_style},
                    {"orthoimage_error", m.ortho_problem}};
    st["input"] = {
        {"source", in.source},
        {"frames", in.frames},
        {"decoded_values", in.decoder.values},
        {"rejected_values", in.decoder.rejected},
        {"counter_gaps", in.decoder.counter_gaps},
        {"rejected_fixes", in.estimator.rejected_jump + in.estimator.rejected_range + in.estimator.rejected_nan},
        {"can_error_frames", in.can_error_frames},
        {"can_bus_off", in.can_bus_off},
        {"can_kernel_drops", in.can_kernel_drops},
        {"can_state", in.can_state},
        {"replay_malformed_lines", in.replay_malformed_lines},
        {"replay_time_errors", in.replay_time_errors},
        {"dbc_skipped_entries", in.dbc_skipped_entries},
        {"error", in.error}};
    st["style"] = {{"mode", m.style.mode},
                   {"shown", m.style.night ? "night" : "day"},
                   {"reason", m.style.reason},
                   {"night_weight", m.style.night_weight}};
    if (m.style.sun_elevation_deg) st["style"]["sun_elevation_deg"] = *m.style.sun_elevation_deg;
    st["road_graph"] = m.road_graph;
    st["position"] = {{"valid", pose.valid},
                      {"stale", pose.stale},
                      {"speed_kmh", pose.speed_mps * 3.6},
                      {"x_m", pose.x},
                      {"y_m", pose.y},
                      {"heading_deg", pose.heading_deg},
                      {"match_confidence", pose.match_confidence}};
    if (pose.valid) {
        st["position"]["lat"] = m.frame.vehicle_lat;
        st["position"]["lon"] = m.frame.vehicle_lon;
    }
    if (!m.route_id.empty()) st["route"] = {{"id", m.route_id}, {"driven_m", m.route_driven_m}};
    nlohmann::json profiles = nlohmann::json::array();
    for (const auto& d : *m.displays) {
        const DisplayStats& s = d->stats();
        nlohmann::json passes = nlohmann::json::object();
        for (const auto& [pass, window] : s.pass_ms) {
            passes[pass] = {
                {"p50_ms", window.quantile(0.5)}, {"p99_ms", window.quantile(0.99)}, {"samples", window.size()}};
        }
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
                            {"cpu_copies", s.cpu_copies},
                            {"dmabuf", {{"exported", s.dmabuf_published}, {"busy", s.dmabuf_busy}}},
                            {"attribution", d->hasAttribution()},
                            {"first_frame_s", s.first_frame_s >= 0 ? nlohmann::json(s.first_frame_s) : nullptr},
                            {"passes", passes},
                            {"passes_sampled", s.passes_sampled}});
    }
    st["profiles"] = profiles;
    st["stream"] = ipc::frameServerStatsJson(m.stream);  // the same object as GET /status "stream"
    // docs/frame-protocol.md "dma-buf frames": the renderer's probe; frames go through shm either way.
    st["dmabuf"] = {{"available", m.dmabuf.available},
                    {"native_fence_sync", m.dmabuf.native_fence_sync},
                    {"reason", m.dmabuf.reason}};
    if (!m.dmabuf.drm_node.empty()) st["dmabuf"]["drm_node"] = m.dmabuf.drm_node;
    st["tile_cache"] = {{"resident_bytes", m.cache.resident_bytes},
                        {"hits", m.cache.hits},
                        {"misses", m.cache.misses},
                        {"load_p99_ms", m.cache.load_p99_ms},
                        {"corrupt", m.cache.corrupt}};
    nlohmann::json stores = nlohmann::json::array();
    for (const auto& store : m.stores)
        stores.push_back({{"path", store.path}, {"tiles", store.tiles}, {"tiles_loaded", store.loads}});
    st["stores"] = std::move(stores);
    st["frame"] = {{"origin_lat", m.frame.origin_lat},
                   {"origin_lon", m.frame.origin_lon},
                   {"recentred", m.frame.recentred},
                   {"scale_error_pct", m.frame.scale_error * 100.0}};
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
