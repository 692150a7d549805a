// SPDX-License-Identifier: Apache-2.0
#pragma once
// ReconnectingClient: a StreamClient that a display process can keep for its whole life. It
// connects on first use, and when navmapd is not there yet, restarts or drops the connection it
// connects again with exponential backoff (Backoff: 100 ms doubling to 5 s by default), while
// next() keeps returning "no frame yet" instead of an error. Part of libnavmap-client; the C API
// (navmap_client.h) wraps it. Not thread-safe: one thread owns a client.

#include <chrono>
#include <cstdint>
#include <memory>
#include <string>

#include "navmap/ipc/client/stream_client.h"
#include "navmap/ipc/net/backoff.h"
#include "navmap/ipc/net/client_api.h"

namespace navmap::ipc {

struct ReconnectOptions {
    std::string unix_path;  ///< the frame socket (payload shm or raw); or
    std::string tcp_host;   ///< host and port of the TCP frame server (payload raw or zlib)
    int tcp_port = -1;
    StreamRequest request;
    std::chrono::milliseconds connect_timeout{2000};  ///< connect + handshake, each attempt
    std::chrono::milliseconds initial_backoff{100};   ///< first wait after a failure, doubling ...
    std::chrono::milliseconds max_backoff{5000};      ///< ... up to this
    FrameInflater inflate;                            ///< for payload zlib
};

struct ReconnectStats {
    std::uint64_t connects = 0;          ///< successful handshakes
    std::uint64_t failed_attempts = 0;   ///< connection attempts that failed (refused, no socket, timeout)
    std::uint64_t disconnects = 0;       ///< established streams that ended
    std::uint64_t held_overwritten = 0;  ///< held frames the server overwrote before their release
};

class NAVMAP_CLIENT_API ReconnectingClient {
public:
    explicit ReconnectingClient(ReconnectOptions options);
    ~ReconnectingClient();
    ReconnectingClient(const ReconnectingClient&) = delete;
    ReconnectingClient& operator=(const ReconnectingClient&) = delete;

    /// Waits up to `timeout` for the next frame (a copy), connecting and reconnecting as needed.
    /// true: `out` holds a frame; false: none within the timeout (lastError() says why when
    /// there is no connection).
    bool next(ReceivedFrame& out, std::chrono::milliseconds timeout);
    /// The same, but the frame stays in the shared-memory ring until release() (payload shm).
    bool nextHeld(HeldFrame& out, std::chrono::milliseconds timeout);
    /// Releases a held frame; false when the server had overwritten it (or the connection ended
    /// meanwhile: then the pixels were never at risk of changing, but the frame is gone).
    bool release();

    bool connected() const noexcept { return m_client != nullptr; }
    /// Asks for the metadata block (StreamRequest::meta) from the next connection on.
    void requestMeta(bool on) noexcept { m_options.request.meta = on; }
    /// Asks for payload dmabuf from the next connection on, falling back to shm when the server
    /// refuses it (StreamRequest::dmabuf_fallback_shm); client()->payload() says which one was granted.
    void requestDmabuf(bool fallback_shm) noexcept {
        m_options.request.payload = StreamPayload::Dmabuf;
        m_options.request.dmabuf_fallback_shm = fallback_shm;
    }
    /// Why the last attempt failed or the last stream ended; empty when none did.
    const std::string& lastError() const noexcept { return m_last_error; }
    const ReconnectStats& reconnectStats() const noexcept { return m_stats; }
    /// The connected client (profile granted, stream statistics), nullptr while disconnected.
    const StreamClient* client() const noexcept { return m_client.get(); }
    const ReconnectOptions& options() const noexcept { return m_options; }

private:
    bool ensureConnected(std::chrono::steady_clock::time_point deadline);
    void dropConnection(const std::string& why);
    bool receive(ReceivedFrame* copy, HeldFrame* held, std::chrono::milliseconds timeout);

    ReconnectOptions m_options;
    Backoff m_backoff;
    std::unique_ptr<StreamClient> m_client;
    std::string m_last_error;
    ReconnectStats m_stats;
};

}  // namespace navmap::ipc
