// SPDX-License-Identifier: Apache-2.0
#pragma once
// What the frame server tells about itself: its navmap_stream_* metric families (Prometheus, for
// /metrics and FrameServer::collectMetrics) and the JSON of /status. Built from snapshots, so
// any thread may call them. Private to ipc/stream.

#include <cstddef>
#include <functional>
#include <string>
#include <vector>

#include "frame_encoder.h"
#include "navmap/ipc/stream/frame_server.h"
#include "navmap/ipc/stream/metrics_registry.h"

namespace navmap::ipc::stream_detail {

/// The server's own families; `ring_memory_bytes` is the ceiling shown next to the bytes in use.
void collectStreamMetrics(MetricsRegistry& r, const FrameServerStats& s, const EncoderStats& es,
                          std::size_t ring_memory_bytes);

/// /status: {"stream": counters and profiles, "daemon": what `daemonJson` returns (or null)}.
std::string streamStatusJson(const FrameServerStats& s, const std::vector<ActiveProfile>& active,
                             const std::function<std::string()>& daemon_json);

}  // namespace navmap::ipc::stream_detail
