// SPDX-License-Identifier: Apache-2.0
#pragma once
// frameServerStatsJson(): the frame server's counters as JSON, the one "stream" object of both
// navmapd's get_status (control socket, docs/navmapd.md "Observability") and the frame server's
// GET /status (docs/frame-protocol.md). Pure; any thread.

#include <nlohmann/json.hpp>

#include "navmap/ipc/stream/frame_server.h"

namespace navmap::ipc {

/// {"clients", "shm_clients", "tcp_clients", "mjpeg_clients", "rings", "rings_idle",
/// "rings_reused", "published", "frames_sent", "statuses_sent", "frames_dropped",
/// "stall_disconnects", "handshake_errors", "timeouts": {...}, "refusals": {...}, "ring_bytes",
/// "publish_ms_last", "last_error"}.
nlohmann::json frameServerStatsJson(const FrameServerStats& s);

}  // namespace navmap::ipc
