// SPDX-License-Identifier: Apache-2.0
#include "navmap/ipc/stream/frame_server_stats_json.h"

namespace navmap::ipc {

nlohmann::json frameServerStatsJson(const FrameServerStats& s) {
    return {{"clients", s.clients},
            {"shm_clients", s.shm_clients},
            {"tcp_clients", s.tcp_clients},
            {"mjpeg_clients", s.mjpeg_clients},
            {"dmabuf_clients", s.dmabuf_clients},
            {"dmabuf_frames_sent", s.dmabuf_frames_sent},
            {"dmabuf_fds_sent", s.dmabuf_fds_sent},
            {"rings", s.rings},
            {"rings_idle", s.rings_idle},
            {"rings_reused", s.rings_reused},
            {"published", s.published},
            {"frames_sent", s.frames_sent},
            {"statuses_sent", s.statuses_sent},
            {"frames_dropped", s.frames_dropped},
            {"stall_disconnects", s.stall_disconnects},
            {"handshake_errors", s.handshake_errors},
            {"timeouts", {{"handshake", s.handshake_timeouts}, {"first_frame", s.first_frame_timeouts}}},
            {"refusals",
             {{"peer", s.refused_peer},
              {"transport_full", s.refused_transport_full},
              {"uid_full", s.refused_uid_full},
              {"address_full", s.refused_address_full},
              {"not_rendered", s.refused_not_rendered},
              {"ring_memory", s.refused_ring_memory},
              {"http_host", s.refused_host},
              {"http_token", s.refused_token}}},
            {"ring_bytes", s.ring_bytes},
            {"publish_ms_last", s.publish_ms_last},
            {"last_error", s.last_error}};
}

}  // namespace navmap::ipc
