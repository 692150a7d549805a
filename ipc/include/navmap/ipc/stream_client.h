#pragma once
// StreamClient: the display-client side of docs/frame-protocol.md. Connects over the Unix socket
// (shared-memory ring) or TCP (raw/zlib), then next() returns the newest frames; statuses the
// server sends before the first frame are kept (lastStatus) and passed to a handler, and next()
// goes on waiting for the frame. Not thread-safe: one thread owns a client.

#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "navmap/ipc/frame_header.h"
#include "navmap/ipc/result.h"
#include "navmap/ipc/stream_profile.h"

namespace navmap::ipc {

struct ReceivedFrame {
    FrameHeader header;                 ///< dropped = server-side drops + frames lost locally
    std::vector<std::uint8_t> pixels;   ///< header.stride * header.height bytes, header.format
    std::int64_t receiveTimeNs = 0;     ///< CLOCK_REALTIME ns when the pixels were complete
};

struct StreamClientStats {
    std::uint64_t frames = 0;
    std::uint64_t serverDropped = 0;   ///< the newest header's dropped count
    std::uint64_t lostLocally = 0;     ///< shm slots overwritten before we copied them
    std::uint64_t bytes = 0;           ///< payload bytes received (compressed size for zlib)
    std::uint64_t statuses = 0;        ///< status headers received
};

class StreamClient {
public:
    /// Connects to the server's Unix socket and sends `request` (payload shm, raw or zlib).
    static Result<std::unique_ptr<StreamClient>> connectUnix(const std::string& path, const StreamRequest& request,
                                                             std::chrono::milliseconds timeout = std::chrono::seconds(5));
    /// Connects to host:port (numeric IPv4/IPv6 or a name) and sends `request` (raw or zlib).
    static Result<std::unique_ptr<StreamClient>> connectTcp(const std::string& host, int port,
                                                            const StreamRequest& request,
                                                            std::chrono::milliseconds timeout = std::chrono::seconds(5));
    ~StreamClient();
    StreamClient(const StreamClient&) = delete;
    StreamClient& operator=(const StreamClient&) = delete;

    /// Waits up to `timeout` for the next frame. true: `out` holds it; false: timeout; Error: the
    /// server closed the connection or broke the protocol (the message says which, including the
    /// server's error text).
    /// A status (header kind 2, before the first frame) is not a frame: it is checked (UTF-8, at
    /// most 64 KiB), kept as lastStatus(), handed to the status handler, and the wait goes on.
    Result<bool> next(ReceivedFrame& out, std::chrono::milliseconds timeout);

    /// Called inside next() with each status's text (a JSON object from the server, e.g.
    /// {"state":"loading",...}) as it arrives; the caller's thread. Empty: statuses are only kept.
    void setStatusHandler(std::function<void(const std::string&)> handler) { m_onStatus = std::move(handler); }
    /// The newest status text; empty when none came.
    const std::string& lastStatus() const noexcept { return m_lastStatus; }

    /// The profile the server granted (after defaults were applied).
    const StreamProfile& profile() const noexcept { return m_profile; }
    StreamPayload payload() const noexcept { return m_payload; }
    const StreamClientStats& stats() const noexcept { return m_stats; }
    int fd() const noexcept { return m_fd; }

private:
    StreamClient() = default;
    static Result<std::unique_ptr<StreamClient>> handshake(int fd, std::string peer, const StreamRequest& request,
                                                           std::chrono::milliseconds timeout);
    Status readExact(std::uint8_t* dst, std::size_t n, std::chrono::steady_clock::time_point deadline, bool* timedOut);

    int m_fd = -1;
    std::string m_peer;
    StreamProfile m_profile;
    StreamPayload m_payload = StreamPayload::Shm;
    std::uint64_t m_lastSequence = 0;  ///< newest frame handed out (never hand one out twice)
    const std::uint8_t* m_map = nullptr;
    std::size_t m_mapBytes = 0;
    std::uint32_t m_slots = 0;
    std::vector<std::uint8_t> m_in;   // bytes received beyond what was consumed
    std::size_t m_inPos = 0;
    std::vector<std::uint8_t> m_compressed;
    StreamClientStats m_stats;
    std::uint8_t m_headerBuf[kFrameHeaderBytes] = {};
    std::size_t m_headerHave = 0;     // partial header kept across timeouts
    std::string m_lastStatus;
    std::function<void(const std::string&)> m_onStatus;
};

}  // namespace navmap::ipc
