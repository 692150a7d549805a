// SPDX-License-Identifier: Apache-2.0
#pragma once
// StreamConn: one accepted connection of the frame server, whatever its transport: the socket,
// where it is in its protocol, its output queue and what it has been offered and sent. Owned by
// the ClientHub; used on the server thread only. Private to ipc/stream.

#include <sys/types.h>

#include <array>
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "navmap/ipc/client/stream_profile.h"
#include "navmap/ipc/net/unique_fd.h"

namespace navmap::ipc::stream_detail {

struct RingEntry;

using Clock = std::chrono::steady_clock;

enum class Via { Unix, Tcp, Http };
enum class Phase { Handshake, Stream, HttpHead, Mjpeg, Draining };

/// "unix", "tcp", "http": how peers are named in errors ("tcp#7").
const char* viaName(Via via);

struct StreamConn {
    net::UniqueFd fd;
    Via via = Via::Unix;
    Phase phase = Phase::Handshake;
    std::string peer;
    std::optional<uid_t> uid;  // Unix peers (SO_PEERCRED)
    std::string address;       // TCP and HTTP peers: the address they are counted by ("127.0.0.1", "2001:db8::/64")
    std::string in;
    std::vector<std::uint8_t> out;
    std::size_t out_pos = 0;
    bool close_when_flushed = false;
    bool dead = false;
    std::shared_ptr<RingEntry> ring;
    StreamPayload payload = StreamPayload::Shm;
    bool hold = false;  // shm: holds frames in place until its ack (pinned slots)
    bool meta = false;  // asked for the metadata block after each frame header
    int fps = 0;
    bool awaiting_ack = false;
    int pinned_slot = -1;  // shm: the slot of the notified frame, pinned until the ack
    int dmabuf_held = -1;  // dmabuf: the buffer of the notified frame, held until the ack
    /// dmabuf: the allocation of each buffer whose fd this client has (0: none).
    std::array<std::uint64_t, 16> dmabuf_known{};
    bool pending = false;
    std::uint64_t last_sent = 0;
    std::uint64_t seen = 0;  // newest frame (in this client's encoding) it has been offered
    std::uint64_t dropped = 0;
    Clock::time_point since;
    Clock::time_point stream_since;  // handshake done: the first frame is due within handshake_timeout
    Clock::time_point last_progress;
    Clock::time_point ack_since;
    Clock::time_point last_offer;
    bool offered = false;
    bool deferred = false;
    Clock::time_point deferred_until;
    std::uint64_t bytes_sent = 0;   // accepted by the kernel
    std::uint64_t bytes_acked = 0;  // TCP: left the kernel's send queue (the peer took them)

    bool outPending() const { return out_pos < out.size(); }
    bool busy() const { return outPending() || awaiting_ack; }

    /// Appends to the output queue; a queue that was empty restarts a Unix peer's progress clock.
    void queue(const void* data, std::size_t n);
    /// Sends what the socket takes without waiting. True when the queue is empty afterwards;
    /// false when the socket is full or broken (then `dead`).
    bool sendQueued();
    /// Drops the connection: one try to send `bytes` without waiting (when nothing else is
    /// queued), half-close, and `dead`, so it never holds its slot.
    void closeWith(const std::string& bytes);
    /// shm: gives the pinned slot back to the ring; dmabuf: the held buffer (the client is done
    /// with it, or gone).
    void unpin();
};

}  // namespace navmap::ipc::stream_detail
