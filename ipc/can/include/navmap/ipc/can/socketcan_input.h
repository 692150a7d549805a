// SPDX-License-Identifier: Apache-2.0
#pragma once
// SocketCanInput: the vehicle's CAN bus as a CanSource, through SocketCanSource (kernel
// filters for the decoder's frames, re-opened with backoff while the interface is down).

#include <memory>
#include <string>
#include <vector>

#include "navmap/ipc/can/can_source.h"

namespace navmap::ipc {
class SocketCanSource;

class SocketCanInput final : public CanSource {
public:
    /// `frame_keys`: the frames the decoder knows (CAN_RAW_FILTER); the socket opens on first poll.
    SocketCanInput(std::string interface_name, std::vector<std::uint32_t> frame_keys);
    ~SocketCanInput() override;

    [[nodiscard]] std::string name() const override { return "socketcan " + m_interface; }
    void start(CanTime) override {}
    void poll(CanTime now, const FrameSink& sink) override;
    /// Wakes as soon as frames arrive.
    void wait(std::chrono::milliseconds timeout) override;
    void report(CanSourceStatus& status) override;

private:
    std::string m_interface;
    std::unique_ptr<SocketCanSource> m_can;
};

}  // namespace navmap::ipc
