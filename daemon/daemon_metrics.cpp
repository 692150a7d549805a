// SPDX-License-Identifier: Apache-2.0
#include "daemon_metrics.h"

#include <string>
#include <vector>

#include "navmap/version.h"

namespace navmap::daemon {

void DaemonMetrics::update(const StatusSample& m) {
    auto reg = std::make_shared<ipc::MetricsRegistry>();
    auto d = [](auto v) { return static_cast<double>(v); };
    reg->gauge("navmap_build_info", "The navmap version this daemon was built from.")
        .sample({{"version", NAVMAP_VERSION}}, 1);
    auto& frame =
        reg->summary("navmap_frame_seconds",
                     "Frame time per profile (tiles, render, readback submit); quantiles over the last 600 frames.");
    auto& latency = reg->summary(
        "navmap_latency_seconds",
        "CAN receive time of the pose to frame published, per profile; quantiles over the last 600 frames.");
    auto& rendered = reg->counter("navmap_frames_rendered_total", "Frames rendered, per profile.");
    auto& published = reg->counter("navmap_frames_published_total", "Frames handed to the frame server, per profile.");
    auto& copies = reg->counter("navmap_frame_cpu_copies_total",
                                "Pixel copies the CPU made for a profile's frames: a readback per frame read back and "
                                "a copy per ring it went into; frames exported as dma-bufs cost none.");
    auto& exported = reg->counter("navmap_frames_dmabuf_total",
                                  "Frames handed to dma-buf clients in exported buffers (copied on the GPU), per "
                                  "profile; `state` busy: not exported, every buffer still held by a client.");
    auto& uploads = reg->counter("navmap_gpu_tile_uploads_total", "Tiles uploaded to the GPU for a profile's frames.");
    auto& first_frame = reg->gauge("navmap_first_frame_seconds",
                                   "Process exec to the profile's first published frame (none before it).");
    auto& pass = reg->gauge("navmap_pass_seconds",
                            "Where a profile's frame time goes: select, render and publish of every frame, and the "
                            "renderer's passes of one frame in 30 (timed with a glFinish after each); quantiles over "
                            "the last 600 samples (p50 and p99).");
    for (const auto& display : *m.displays) {
        const std::string& n = display->profile().name;
        const DisplayStats& v = display->stats();
        for (const auto& [name, window] : v.pass_ms) {
            pass.sample({{"profile", n}, {"pass", name}, {"quantile", "0.5"}}, window.quantile(0.5) / 1000.0)
                .sample({{"profile", n}, {"pass", name}, {"quantile", "0.99"}}, window.quantile(0.99) / 1000.0);
        }
        for (const double q : {0.5, 0.99}) {
            const std::string qs = q == 0.5 ? "0.5" : "0.99";
            frame.sample({{"profile", n}, {"quantile", qs}}, v.frame_ms.quantile(q) / 1000.0);
            latency.sample({{"profile", n}, {"quantile", qs}}, v.latency_ms.quantile(q) / 1000.0);
        }
        frame.sample({{"profile", n}}, v.frame_s_sum, "_sum").sample({{"profile", n}}, d(v.rendered), "_count");
        latency.sample({{"profile", n}}, v.latency_s_sum, "_sum")
            .sample({{"profile", n}}, d(v.latency_count), "_count");
        rendered.sample({{"profile", n}}, d(v.rendered));
        published.sample({{"profile", n}}, d(v.published));
        uploads.sample({{"profile", n}}, d(v.tiles_uploaded));
        copies.sample({{"profile", n}}, d(v.cpu_copies));
        exported.sample({{"profile", n}, {"state", "exported"}}, d(v.dmabuf_published))
            .sample({{"profile", n}, {"state", "busy"}}, d(v.dmabuf_busy));
        if (v.first_frame_s >= 0) first_frame.sample({{"profile", n}}, v.first_frame_s);
    }
    reg->counter("navmap_can_frames_total", "CAN frames received.").sample(d(m.input.frames));
    reg->counter("navmap_can_rejected_values_total", "Decoded values rejected (out of range, stale counter).")
        .sample(d(m.input.decoder.rejected));
    reg->counter("navmap_can_error_frames_total", "CAN error frames.").sample(d(m.input.can_error_frames));
    reg->counter("navmap_can_kernel_drops_total", "Frames the kernel dropped before the daemon read them.")
        .sample(d(m.input.can_kernel_drops));
    reg->gauge("navmap_position_stale", "1 while the position is lost (no fix within input.stale_after_s).")
        .sample(m.pose.stale ? 1 : 0);
    reg->gauge("navmap_tile_cache_bytes", "Decoded tiles resident in the tile cache.")
        .sample(d(m.cache.resident_bytes));
    reg->counter("navmap_tile_cache_hits_total", "Tile requests served from the cache.").sample(d(m.cache.hits));
    reg->counter("navmap_tile_cache_misses_total", "Tile requests queued for loading.").sample(d(m.cache.misses));
    reg->summary("navmap_tile_load_seconds", "Tile load time (read and decode); quantiles over the last 4096 loads.")
        .sample({{"quantile", "0.5"}}, m.cache.load_p50_ms / 1000.0)
        .sample({{"quantile", "0.99"}}, m.cache.load_p99_ms / 1000.0)
        .sample(std::vector<ipc::MetricsRegistry::Label>{}, d(m.cache.loads), "_count");
    reg->counter("navmap_control_errors_total", "Control-socket requests answered with an error.")
        .sample(d(m.control.errors));
    reg->counter("navmap_control_refusals_total", "Control-socket connections and subscriptions refused, by reason.")
        .sample({{"reason", "peer"}}, d(m.control.refused_peer))
        .sample({{"reason", "full"}}, d(m.control.refused_full))
        .sample({{"reason", "uid_full"}}, d(m.control.refused_uid_full))
        .sample({{"reason", "subscribers"}}, d(m.control.refused_subscribers));
    reg->counter("navmap_control_evictions_total",
                 "Unprivileged control connections closed to seat a privileged peer (all slots taken).")
        .sample(d(m.control.evictions));
    reg->counter("navmap_control_idle_disconnects_total", "Control connections closed as idle or stalled.")
        .sample(d(m.control.idle_disconnects));
    reg->gauge("navmap_process_resident_bytes", "Resident set size (VmRSS).").sample(d(m.memory.rss));
    reg->gauge("navmap_process_peak_resident_bytes", "Peak resident set size (VmHWM).").sample(d(m.memory.peak));
    reg->counter("navmap_config_reloads_total", "Configuration reloads applied (SIGHUP).").sample(d(m.reloads));
    reg->counter("navmap_config_reload_errors_total", "Configuration reloads refused (the running one stays).")
        .sample(d(m.reload_errors));
    m_snapshot.store(std::move(reg));
}

}  // namespace navmap::daemon
