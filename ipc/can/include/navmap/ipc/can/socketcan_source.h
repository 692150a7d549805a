// SPDX-License-Identifier: Apache-2.0
#pragma once
// SocketCanSource: non-blocking SocketCAN raw socket reader.
//  - CAN_RAW_FILTER for the configured frame keys, CAN FD frames (CAN_RAW_FD_FRAMES),
//    error frames (CAN_RAW_ERR_FILTER) counted and described in status();
//  - kernel receive timestamps (SO_TIMESTAMPNS, realtime clock) become CanFrame::timestamp;
//  - kernel drop counts (SO_RXQ_OVFL) are reported as status().kernel_drops;
//  - when the interface is missing or goes down (ENETDOWN/ENODEV), the socket is closed and
//    re-opened with exponential Backoff once the interface exists and is up again.
// poll() never blocks; call it from the input thread (waitReadable() to sleep there), never from the
// render loop. Not thread-safe: one thread owns it.

#include <chrono>
#include <cstdint>
#include <string>
#include <vector>

#include "navmap/ipc/can/can_frame.h"
#include "navmap/ipc/can/replayer.h"  // FrameSink
#include "navmap/ipc/net/backoff.h"
#include "navmap/ipc/net/result.h"
#include "navmap/ipc/net/unique_fd.h"

namespace navmap::ipc {

struct SocketCanOptions {
    std::string interface_name = "can0";
    /// Frame keys (CanFrame::key()) to receive; empty = everything.
    std::vector<std::uint32_t> frame_keys;
    bool receive_fd = true;
    bool receive_error_frames = true;
    /// SO_RCVBUF in bytes, 0 = system default.
    int receive_buffer_bytes = 0;
    std::chrono::milliseconds backoff_initial{100};
    std::chrono::milliseconds backoff_maximum{5000};
};

struct SocketCanStatus {
    enum class State { Closed, Open, Retrying };
    State state = State::Closed;
    std::uint64_t frames = 0;  ///< data frames delivered (classic + FD)
    std::uint64_t fd_frames = 0;
    std::uint64_t error_frames = 0;
    std::uint64_t bus_off = 0;
    std::uint64_t controller_problems = 0;
    std::uint64_t other_errors = 0;  ///< protocol, transceiver, ACK, arbitration, bus errors
    std::uint64_t kernel_drops = 0;  ///< SO_RXQ_OVFL, summed over re-opens
    std::uint64_t bad_frames = 0;    ///< reads of an unexpected size
    std::uint64_t opens = 0;         ///< successful opens (1 + re-opens)
    std::uint64_t open_failures = 0;
    std::string last_error;        ///< "bind(can0): No such device", "recvmsg(can0): Network is down"
    std::string last_error_frame;  ///< ErrorFrameInfo::describe() of the newest error frame
    CanTime last_error_frame_time{};
    bool fd_enabled = false;  ///< CAN_RAW_FD_FRAMES accepted by the kernel

    static const char* stateName(State s) noexcept;
};

class SocketCanSource {
public:
    explicit SocketCanSource(SocketCanOptions options);
    ~SocketCanSource();
    SocketCanSource(const SocketCanSource&) = delete;
    SocketCanSource& operator=(const SocketCanSource&) = delete;

    /// Opens the socket if it is closed and the backoff allows, then reads up to `maxFrames`
    /// pending frames without blocking and passes data frames to `sink` (error frames are counted,
    /// not passed). Returns the number of frames passed.
    std::size_t poll(const FrameSink& sink, std::size_t max_frames = 256);

    /// Sleeps until the socket is readable, `timeout` passes, or (while closed) the next re-open is
    /// due, whichever is first. For the input thread only.
    void waitReadable(std::chrono::milliseconds timeout);

    /// Writes one frame (non-blocking). Fails when closed or the kernel refuses (e.g. ENOBUFS).
    Status send(const CanFrame& frame);

    /// Socket descriptor for an external poll/epoll loop; -1 while closed.
    int fd() const noexcept { return m_fd.get(); }
    const SocketCanStatus& status() const noexcept { return m_status; }
    const SocketCanOptions& options() const noexcept { return m_options; }
    const Backoff& backoff() const noexcept { return m_backoff; }

private:
    bool open();
    void closeSocket();
    void failOpen(std::string error);

    SocketCanOptions m_options;
    SocketCanStatus m_status;
    Backoff m_backoff;
    net::UniqueFd m_fd;
    std::uint32_t m_drops_at_open = 0;  // SO_RXQ_OVFL value of the current socket already counted
    std::uint64_t m_drops_before = 0;   // drops of earlier sockets
};

}  // namespace navmap::ipc
