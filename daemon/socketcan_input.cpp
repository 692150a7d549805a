// SPDX-License-Identifier: Apache-2.0
#include "socketcan_input.h"

#include "navmap/ipc/socketcan_source.h"

namespace navmap::daemon {

SocketCanInput::SocketCanInput(std::string interface_name, std::vector<std::uint32_t> frame_keys)
    : m_interface(std::move(interface_name)) {
    ipc::SocketCanOptions o;
    o.interfaceName = m_interface;
    o.frameKeys = std::move(frame_keys);
    m_can = std::make_unique<ipc::SocketCanSource>(o);
}

SocketCanInput::~SocketCanInput() = default;

void SocketCanInput::poll(ipc::CanTime, const ipc::FrameSink& sink) { m_can->poll(sink); }

void SocketCanInput::wait(std::chrono::milliseconds timeout) { m_can->waitReadable(timeout); }

void SocketCanInput::report(CanSourceStatus& status) {
    const auto& st = m_can->status();
    status.can_error_frames = st.errorFrames;
    status.can_bus_off = st.busOff;
    status.can_kernel_drops = st.kernelDrops;
    status.can_state = st.state == ipc::SocketCanStatus::State::Open ? "open" : "retrying: " + st.lastError;
}

}  // namespace navmap::daemon
