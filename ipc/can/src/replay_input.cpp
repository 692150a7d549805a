// SPDX-License-Identifier: Apache-2.0
#include "navmap/ipc/can/replay_input.h"

#include <cstdio>
#include <stdexcept>
#include <thread>

#include "navmap/ipc/can/candump_file_source.h"
#include "navmap/ipc/can/replayer.h"

namespace navmap::ipc {

ReplayInput::ReplayInput(const std::filesystem::path& log, double speed, bool loop) : m_path(log) {
    auto source = CandumpFileSource::open(log);
    if (!source) throw std::runtime_error(source.error().message);
    m_file = source.value().get();
    ReplayOptions replay;
    replay.speed = speed;
    replay.loop = loop;
    replay.restamp = true;
    m_replayer = std::make_unique<Replayer>(std::move(source).value(), replay);
    if (const std::string error = m_replayer->error(); !error.empty()) throw std::runtime_error(error);
    if (m_replayer->finished()) std::fprintf(stderr, "<4>navmapd: %s: no CAN frames to replay\n", log.c_str());
}

ReplayInput::~ReplayInput() = default;

void ReplayInput::start(CanTime now) { m_replayer->reset(now); }

void ReplayInput::poll(CanTime now, const FrameSink& sink) { m_replayer->advanceTo(now, sink); }

void ReplayInput::wait(std::chrono::milliseconds timeout) { std::this_thread::sleep_for(timeout); }

void ReplayInput::report(CanSourceStatus& status) {
    status.replay_loops = m_replayer->loops();
    status.replay_time_errors = m_replayer->timeErrors();
    const auto& reader = m_file->reader();
    status.replay_malformed_lines = reader.counters().malformed;
    if (!m_logged_malformed && !reader.errors().empty()) {
        m_logged_malformed = true;
        std::fprintf(stderr, "<4>navmapd: malformed candump line skipped: %s (all are counted in status)\n",
                     reader.errors().front().message.c_str());
    }
    if (status.error.empty() && m_replayer->finished()) {
        status.error = m_replayer->error();
        if (!status.error.empty()) {
            status.error = "replay stopped: " + status.error;
            std::fprintf(stderr, "<3>navmapd: %s\n", status.error.c_str());
        }
    }
}

}  // namespace navmap::ipc
