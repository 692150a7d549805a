// SPDX-License-Identifier: Apache-2.0
#pragma once
// DaemonStatus: the get_status (control socket) and GET /status (HTTP) object, rebuilt from a
// StatusSample about once a second on the render thread and read by the control and HTTP threads
// as an immutable snapshot; and the one-line STATUS= that systemd shows.

#include <atomic>
#include <memory>
#include <string>

#include <nlohmann/json.hpp>

#include "status_sample.h"

namespace navmap::daemon {

class DaemonStatus {
public:
    DaemonStatus() : m_json(std::make_shared<const nlohmann::json>(nlohmann::json::object())) {}

    /// Render thread: a new snapshot from `sample`.
    void publish(const StatusSample& sample);
    /// Any thread: the newest snapshot.
    [[nodiscard]] nlohmann::json json() const { return *m_json.load(); }
    [[nodiscard]] std::string text() const { return m_json.load()->dump(); }

    /// "2 clients, position ok, cluster 300 frames, ..." for systemd's STATUS=.
    static std::string systemdLine(const StatusSample& sample);

private:
    std::atomic<std::shared_ptr<const nlohmann::json>> m_json;
};

}  // namespace navmap::daemon
