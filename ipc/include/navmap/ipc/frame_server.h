#pragma once
// FrameServer: delivers rendered frames to display clients (docs/frame-protocol.md).
//  - Unix socket: JSON handshake, frames in a shared-memory ring per profile (memfd over
//    SCM_RIGHTS), an 80-byte notification per frame, one ack byte back (credit of one frame);
//  - TCP: same handshake and header, pixels raw or zlib-compressed on the socket;
//  - HTTP: GET / (HTML viewer), /stream.mjpg (MJPEG), /status (JSON), /metrics (Prometheus).
// The render thread calls publish(); it copies into the profile's ring and never waits for a
// client. All socket I/O, compression and JPEG encoding run on the server's own thread (poll()).
// Each client gets the newest frame; a busy client skips frames (counted as dropped), a client
// that makes no progress for `stallTimeout` is disconnected.

#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "navmap/ipc/frame_view.h"
#include "navmap/ipc/result.h"
#include "navmap/ipc/stream_profile.h"

namespace navmap::ipc {

struct FrameServerOptions {
    std::string unixPath;              ///< Unix stream socket; empty = none
    std::string bindAddress = "127.0.0.1";  ///< for TCP and HTTP
    int tcpPort = -1;                  ///< -1 = none, 0 = any free port (see tcpPort())
    int httpPort = -1;                 ///< -1 = none, 0 = any free port (see httpPort())
    /// Slots per profile ring (>= 2). Three give a client two frame periods between the
    /// notification and the end of its copy; each slot costs stride x height bytes of shared memory.
    std::uint32_t ringSlots = 3;
    std::chrono::milliseconds stallTimeout{2000};  ///< no ack / no write progress / no handshake
    std::size_t maxClients = 64;
    int jpegQuality = 80;
    std::string mjpegProfile = "center";  ///< profile of /stream.mjpg without ?profile=
    /// Body of /metrics before the server's own navmap_stream_* lines (Prometheus text). Called on
    /// the server thread; must be thread-safe with respect to the daemon.
    std::function<std::string()> metricsText;
    /// JSON object shown by the HTML page under "daemon" in /status. Server thread.
    std::function<std::string()> statusJson;
};

/// A profile that has at least one client: what the daemon should render.
struct ActiveProfile {
    std::string view;
    int width = 0;
    int height = 0;
    int maxFps = 0;         ///< highest fps any of its clients asked for
    std::size_t clients = 0;
};

/// Counters (snapshot; any thread).
struct FrameServerStats {
    std::size_t connections = 0;      ///< open sockets, including handshakes and HTTP replies in flight
    std::size_t clients = 0;          ///< connected and streaming (all transports)
    std::size_t shmClients = 0;
    std::size_t tcpClients = 0;
    std::size_t mjpegClients = 0;
    std::size_t rings = 0;
    std::uint64_t published = 0;      ///< publish() calls that reached at least one ring
    std::uint64_t framesSent = 0;     ///< frames handed to clients
    /// Frames a client was entitled to (within its fps) but did not get because it was busy.
    std::uint64_t framesDropped = 0;
    std::uint64_t accepted = 0;       ///< connections accepted
    std::uint64_t handshakeErrors = 0;
    std::uint64_t protocolErrors = 0; ///< garbage after the handshake
    std::uint64_t httpErrors = 0;     ///< 4xx replies
    std::uint64_t stallDisconnects = 0;
    std::uint64_t disconnects = 0;    ///< all closed connections
    double publishMsLast = 0;         ///< render-thread cost of the last publish()
    double publishMsMax = 0;
    std::string lastError;            ///< newest problem: "tcp#7: handshake: unknown key \"x\""
};

class FrameServer {
public:
    explicit FrameServer(FrameServerOptions options);
    ~FrameServer();  ///< stops the thread, closes every socket, unlinks the Unix socket
    FrameServer(const FrameServer&) = delete;
    FrameServer& operator=(const FrameServer&) = delete;

    /// Binds the sockets and starts the server thread. Errors name the call and the object,
    /// e.g. "bind(/run/navmap/stream.sock): Address already in use".
    Status start();
    void stop();

    /// Render thread: copies the frame into every ring of `view` with its width and height
    /// (converting the pixel format) and wakes the server thread. Never blocks on a client.
    /// Returns the number of rings written.
    std::size_t publish(const std::string& view, const FrameView& frame);

    /// Profiles with clients now (which views/sizes to render). Any thread.
    std::vector<ActiveProfile> activeProfiles() const;
    FrameServerStats stats() const;
    /// The server's own metrics (Prometheus text, navmap_stream_*). Any thread.
    std::string metricsText() const;

    int tcpPort() const noexcept;   ///< bound port, -1 when none
    int httpPort() const noexcept;  ///< bound port, -1 when none
    const FrameServerOptions& options() const noexcept;

private:
    class Impl;
    std::unique_ptr<Impl> m_impl;
};

}  // namespace navmap::ipc
