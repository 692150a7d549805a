// SPDX-License-Identifier: Apache-2.0
#include "navmap/ipc/can/socketcan_input.h"

#include "navmap/ipc/can/socketcan_source.h"

namespace navmap::ipc {

SocketCanInput::SocketCanInput(std::string interface_name, std::vector<std::uint32_t> frame_keys)
    : m_interface(std::move(interface_name)) {
    SocketCanOptions o;
    o.interface_name = m_interface;
    o.frame_keys = std::move(frame_keys);
    m_can = std::make_unique<SocketCanSource>(o);
}

SocketCanInput::~SocketCanInput() = default;

void SocketCanInput::poll(CanTime, const FrameSink& sink) { m_can->poll(sink); }

void SocketCanInput::wait(std::chrono::milliseconds timeout) { m_can->waitReadable(timeout); }

void SocketCanInput::report(CanSourceStatus& status) {
    const auto& st = m_can->status();
    status.can_error_frames = st.error_frames;
    status.can_bus_off = st.bus_off;
    status.can_kernel_drops = st.kernel_drops;
    status.can_state = st.state == SocketCanStatus::State::Open ? "open" : "retrying: " + st.last_error;
}

}  // namespace navmap::ipc
