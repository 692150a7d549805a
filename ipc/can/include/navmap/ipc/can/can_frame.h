// SPDX-License-Identifier: Apache-2.0
#pragma once
// CanFrame: one classic CAN or CAN FD frame as seen by navmap, independent of the kernel's
// struct can_frame / canfd_frame so that logs, the replayer and tests work without AF_CAN.

#include <array>
#include <chrono>
#include <cstdint>
#include <string>

namespace navmap::ipc {

/// Clock of CanFrame::timestamp. It is the realtime clock (CLOCK_REALTIME), because that is what the
/// kernel's SO_TIMESTAMPNS delivers and what candump logs record. Latency figures compare it with
/// CanClock::now() on the same host.
using CanClock = std::chrono::system_clock;
using CanTime = std::chrono::time_point<CanClock, std::chrono::nanoseconds>;

/// Frame flag bits (CanFrame::flags).
enum CanFlag : std::uint8_t {
    kCanExtended = 1U << 0,  ///< 29-bit identifier
    kCanFd = 1U << 1,        ///< CAN FD frame (up to 64 data bytes)
    kCanRtr = 1U << 2,       ///< remote transmission request (classic CAN only)
    kCanError = 1U << 3,     ///< error frame; id holds the CAN_ERR_* class bits, data the details
    kCanBrs = 1U << 4,       ///< CAN FD bit-rate switch
    kCanEsi = 1U << 5,       ///< CAN FD error state indicator
};

inline constexpr std::uint32_t kCanMaxStandardId = 0x7FFU;
inline constexpr std::uint32_t kCanMaxExtendedId = 0x1FFFFFFFU;
inline constexpr std::uint8_t kCanMaxClassicLen = 8;
inline constexpr std::uint8_t kCanMaxFdLen = 64;

/// One frame. `timestamp` is the receive time (kernel timestamp for SocketCAN, the log time for a
/// candump file, the emission time for the replayer unless told to keep the log time).
struct CanFrame {
    std::uint32_t id = 0;    ///< 11 or 29 bit identifier (without flag bits)
    std::uint8_t flags = 0;  ///< CanFlag bits
    std::uint8_t len = 0;    ///< payload length in bytes (0..8 classic, 0..64 FD)
    std::array<std::uint8_t, kCanMaxFdLen> data{};
    CanTime timestamp{};

    bool extended() const noexcept { return (flags & kCanExtended) != 0; }
    bool fd() const noexcept { return (flags & kCanFd) != 0; }
    bool rtr() const noexcept { return (flags & kCanRtr) != 0; }
    bool error() const noexcept { return (flags & kCanError) != 0; }

    /// Key used for DBC lookups: the id, with bit 31 set for extended frames (the DBC convention).
    std::uint32_t key() const noexcept { return extended() ? (id | 0x80000000U) : id; }
};

/// True when `len` is a valid CAN FD payload length (0..8, 12, 16, 20, 24, 32, 48, 64).
bool isValidFdLength(unsigned len) noexcept;

/// Formats a frame as candump's log form without the timestamp/interface: "123#DEADBEEF", "1ABCDEF0#R",
/// "123##1AABB" (FD with flags nibble).
std::string formatCandumpPayload(const CanFrame& frame);

}  // namespace navmap::ipc
