// SPDX-License-Identifier: Apache-2.0
#pragma once
// Conversions between the kernel's SocketCAN structures and CanFrame, CAN_RAW_FILTER building and
// error-frame classification. Pure functions: unit-tested without AF_CAN.

#include <linux/can.h>

#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "navmap/ipc/can/can_frame.h"

namespace navmap::ipc {

/// Kernel frame bytes (CAN_MTU = classic, CANFD_MTU = FD) -> CanFrame; nullopt for any other size
/// or an invalid length. `receiveTime` becomes the frame's timestamp.
std::optional<CanFrame> frameFromKernel(const void* buffer, std::size_t bytes, CanTime receive_time) noexcept;

/// CanFrame -> kernel frame; returns the number of bytes to write (CAN_MTU or CANFD_MTU).
std::size_t frameToKernel(const CanFrame& frame, canfd_frame& out) noexcept;

/// One exact-match filter per frame key (CanFrame::key()); RTR frames do not match.
/// Returns an empty vector (= receive everything, filter in user space) for more than
/// CAN_RAW_FILTER_MAX keys or for no keys.
std::vector<can_filter> buildRawFilters(std::span<const std::uint32_t> frame_keys);

/// What an error frame says (linux/can/error.h).
struct ErrorFrameInfo {
    bool bus_off = false;
    bool restarted = false;
    bool controller_problem = false;
    bool protocol_violation = false;
    bool transceiver = false;
    bool no_ack = false;
    bool lost_arbitration = false;
    bool tx_timeout = false;
    bool bus_error = false;
    bool rx_overflow = false;    ///< controller: RX buffer overflow
    bool error_passive = false;  ///< controller: RX or TX error passive
    bool error_warning = false;  ///< controller: RX or TX warning level
    /// "bus-off", "controller problem (rx overflow, error passive)", ... joined by "; ".
    std::string describe() const;
};
ErrorFrameInfo classifyErrorFrame(const CanFrame& frame) noexcept;

}  // namespace navmap::ipc
