// SPDX-License-Identifier: Apache-2.0
#pragma once
// DaemonMetrics: navmapd's own /metrics families (frames, latency, CAN input, tile cache, control
// socket, memory, reloads), in base units. The frame server builds one ipc::MetricsRegistry per
// scrape with its navmap_stream_* families and calls registerInto() to add these after them
// (docs/navmapd.md "Observability"). The families are rebuilt from a StatusSample about once a
// second on the render thread and kept as an immutable snapshot for the HTTP thread.

#include <atomic>
#include <memory>

#include "navmap/ipc/stream/metrics_registry.h"
#include "status_sample.h"

namespace navmap::daemon {

class DaemonMetrics {
public:
    DaemonMetrics() : m_snapshot(std::make_shared<const ipc::MetricsRegistry>()) {}

    /// Render thread: new samples of every family from `sample`.
    void update(const StatusSample& sample);
    /// Any thread: adds the newest families to one scrape's registry.
    void registerInto(ipc::MetricsRegistry& registry) const { registry.append(*m_snapshot.load()); }

private:
    std::atomic<std::shared_ptr<const ipc::MetricsRegistry>> m_snapshot;
};

}  // namespace navmap::daemon
