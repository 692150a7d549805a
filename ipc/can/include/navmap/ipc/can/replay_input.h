// SPDX-License-Identifier: Apache-2.0
#pragma once
// ReplayInput: a candump log as a CanSource, streamed (memory stays bounded whatever the file)
// and played with its recorded timing, restamped to the wall clock, optionally looping.

#include <filesystem>
#include <memory>
#include <string>

#include "navmap/ipc/can/can_source.h"

namespace navmap::ipc {
class CandumpFileSource;
class Replayer;

class ReplayInput final : public CanSource {
public:
    /// Opens the log and reads up to its first frame, so a file that is no candump log (binary
    /// data, /dev/zero, nothing but malformed lines) fails here: std::runtime_error naming it.
    ReplayInput(const std::filesystem::path& log, double speed, bool loop);
    ~ReplayInput() override;

    [[nodiscard]] std::string name() const override { return "replay " + m_path.string(); }
    void start(CanTime now) override;
    void poll(CanTime now, const FrameSink& sink) override;
    void wait(std::chrono::milliseconds timeout) override;
    /// Malformed lines (the first is logged, all are counted) and a replay that stopped early
    /// (logged once; the position then turns stale and shows as lost).
    void report(CanSourceStatus& status) override;

private:
    std::filesystem::path m_path;
    std::unique_ptr<Replayer> m_replayer;
    const CandumpFileSource* m_file = nullptr;  // owned by m_replayer
    bool m_logged_malformed = false;
};

}  // namespace navmap::ipc
