// SPDX-License-Identifier: Apache-2.0
#include "navmap/ipc/can/socketcan_codec.h"

#include <linux/can/error.h>
#include <linux/can/raw.h>

#include <cstring>

namespace navmap::ipc {

std::optional<CanFrame> frameFromKernel(const void* buffer, std::size_t bytes, CanTime receive_time) noexcept {
    if (buffer == nullptr || (bytes != CAN_MTU && bytes != CANFD_MTU)) {
        return std::nullopt;
    }
    canfd_frame k{};
    std::memcpy(&k, buffer, bytes);
    CanFrame f;
    f.timestamp = receive_time;
    const bool fd = bytes == CANFD_MTU;
    if (fd) {
        if (!isValidFdLength(k.len)) {
            return std::nullopt;
        }
        f.flags |= kCanFd;
        if ((k.flags & CANFD_BRS) != 0) {
            f.flags |= kCanBrs;
        }
        if ((k.flags & CANFD_ESI) != 0) {
            f.flags |= kCanEsi;
        }
    } else if (k.len > CAN_MAX_DLEN) {
        return std::nullopt;
    }
    if ((k.can_id & CAN_ERR_FLAG) != 0) {
        f.flags |= kCanError;
        f.id = k.can_id & CAN_ERR_MASK;
    } else if ((k.can_id & CAN_EFF_FLAG) != 0) {
        f.flags |= kCanExtended;
        f.id = k.can_id & CAN_EFF_MASK;
    } else {
        f.id = k.can_id & CAN_SFF_MASK;
    }
    if (!fd && (k.can_id & CAN_RTR_FLAG) != 0) {
        f.flags |= kCanRtr;
    }
    f.len = k.len;
    if (!f.rtr()) {
        std::memcpy(f.data.data(), k.data, f.len);
    }
    return f;
}

std::size_t frameToKernel(const CanFrame& frame, canfd_frame& out) noexcept {
    out = canfd_frame{};
    if (frame.error()) {
        out.can_id = (frame.id & CAN_ERR_MASK) | CAN_ERR_FLAG;
    } else if (frame.extended()) {
        out.can_id = (frame.id & CAN_EFF_MASK) | CAN_EFF_FLAG;
    } else {
        out.can_id = frame.id & CAN_SFF_MASK;
    }
    if (frame.fd()) {
        out.len = isValidFdLength(frame.len) ? frame.len : 0;
        out.flags = static_cast<std::uint8_t>(((frame.flags & kCanBrs) != 0 ? CANFD_BRS : 0) |
                                              ((frame.flags & kCanEsi) != 0 ? CANFD_ESI : 0));
        std::memcpy(out.data, frame.data.data(), out.len);
        return CANFD_MTU;
    }
    out.len = frame.len > CAN_MAX_DLEN ? CAN_MAX_DLEN : frame.len;
    if (frame.rtr()) {
        out.can_id |= CAN_RTR_FLAG;
    } else {
        std::memcpy(out.data, frame.data.data(), out.len);
    }
    return CAN_MTU;
}

std::vector<can_filter> buildRawFilters(std::span<const std::uint32_t> frame_keys) {
    std::vector<can_filter> out;
    if (frame_keys.empty() || frame_keys.size() > CAN_RAW_FILTER_MAX) {
        return out;
    }
    out.reserve(frame_keys.size());
    for (const std::uint32_t key : frame_keys) {
        can_filter f{};
        if ((key & 0x80000000U) != 0) {
            f.can_id = (key & CAN_EFF_MASK) | CAN_EFF_FLAG;
            f.can_mask = CAN_EFF_MASK | CAN_EFF_FLAG | CAN_RTR_FLAG;
        } else {
            f.can_id = key & CAN_SFF_MASK;
            f.can_mask = CAN_SFF_MASK | CAN_EFF_FLAG | CAN_RTR_FLAG;
        }
        out.push_back(f);
    }
    return out;
}

ErrorFrameInfo classifyErrorFrame(const CanFrame& frame) noexcept {
    ErrorFrameInfo info;
    if (!frame.error()) {
        return info;
    }
    const std::uint32_t cls = frame.id;
    info.bus_off = (cls & CAN_ERR_BUSOFF) != 0;
    info.restarted = (cls & CAN_ERR_RESTARTED) != 0;
    info.controller_problem = (cls & CAN_ERR_CRTL) != 0;
    info.protocol_violation = (cls & CAN_ERR_PROT) != 0;
    info.transceiver = (cls & CAN_ERR_TRX) != 0;
    info.no_ack = (cls & CAN_ERR_ACK) != 0;
    info.lost_arbitration = (cls & CAN_ERR_LOSTARB) != 0;
    info.tx_timeout = (cls & CAN_ERR_TX_TIMEOUT) != 0;
    info.bus_error = (cls & CAN_ERR_BUSERROR) != 0;
    if (info.controller_problem && frame.len > 1) {
        const std::uint8_t c = frame.data[1];
        info.rx_overflow = (c & (CAN_ERR_CRTL_RX_OVERFLOW | CAN_ERR_CRTL_TX_OVERFLOW)) != 0;
        info.error_passive = (c & (CAN_ERR_CRTL_RX_PASSIVE | CAN_ERR_CRTL_TX_PASSIVE)) != 0;
        info.error_warning = (c & (CAN_ERR_CRTL_RX_WARNING | CAN_ERR_CRTL_TX_WARNING)) != 0;
    }
    return info;
}

std::string ErrorFrameInfo::describe() const {
    std::string out;
    const auto add = [&out](const char* s) {
        if (!out.empty()) {
            out += "; ";
        }
        out += s;
    };
    if (bus_off) add("bus-off");
    if (restarted) add("controller restarted");
    if (controller_problem) {
        std::string c = "controller problem";
        std::string details;
        if (rx_overflow) details += "overflow";
        if (error_passive) details += std::string(details.empty() ? "" : ", ") + "error passive";
        if (error_warning) details += std::string(details.empty() ? "" : ", ") + "error warning";
        if (!details.empty()) c += " (" + details + ")";
        add(c.c_str());
    }
    if (protocol_violation) add("protocol violation");
    if (transceiver) add("transceiver status");
    if (no_ack) add("no ACK");
    if (lost_arbitration) add("lost arbitration");
    if (tx_timeout) add("TX timeout");
    if (bus_error) add("bus error");
    if (out.empty()) out = "error frame";
    return out;
}

}  // namespace navmap::ipc
