// SPDX-License-Identifier: Apache-2.0
#include "socketcan_input.h"

#include "navmap/ipc/socketcan_source.h"

namespace navmap::daemon {

SocketCanInput::SocketCanInput(std::string interface_name, std::vector<std::uint32_t> frame_keys)
    : m_interface(std::move(interface_name)) {
    ipc::SocketCanOptions o;
    o.interface_name = m_interface;
    o.frame_keys = std::move(frame_keys);
    m_can = std::make_unique<ipc::SocketCanSource>(o);
}

SocketCanInput::~SocketCanInput() = default;

void SocketCanInput::poll(ipc::CanTime, const ipc::FrameSink& sink) { m_can->poll(sink); }

void SocketCanInput::wait(std::chrono::milliseconds timeout) { m_can->waitReadable(timeout); }

void SocketCanInput::report(CanSourceStatus& status) {
    const auto& st = m_can->status();
    status.can_error_frames = st.error_frames;
    status.can_bus_off = st.bus_off;
    status.can_kernel_drops = st.kernel_drops;
    status.can_state = st.state == ipc::SocketCanStatus::State::Open ? "open" : "retrying: " + st.last_error;
}

}  // namespace navmap::daemon
