// SPDX-License-Identifier: Apache-2.0
#pragma once
// FrameServer: delivers rendered frames to display clients (docs/frame-protocol.md).
//  - Unix socket: JSON handshake, frames in a shared-memory ring per profile (memfd over
//    SCM_RIGHTS), an 80-byte notification per frame, one ack byte back (credit of one frame);
//  - TCP: same handshake and header, pixels raw or zlib-compressed on the socket;
//  - HTTP: GET / (HTML viewer), /stream.mjpg (MJPEG), /status (JSON), /metrics (Prometheus).
// The render thread calls publish(profile, frame); it copies into that profile's rings and never
// waits for a client. Frames are routed by profile name, so two profiles of the same view and
// size (one with glowing roads, one without) are two streams. All socket I/O, compression and JPEG encoding run on the
// server's own thread (poll()). Each client gets the newest frame; a busy client skips frames (counted as dropped), a
// client that makes no progress for `stall_timeout` is disconnected. Clients are untrusted: the Unix socket file is
// 0660
// (+ a group) and peers are checked by SO_PEERCRED; connections are capped per transport, per uid (Unix) and per peer
// address (TCP, HTTP); only rendered
// profiles are served; a connection without a handshake or a first frame within `handshake_timeout` is closed (a status
// from publishStatus() restarts that wait); rings share a memory ceiling and are sealed so that no client can write
// them.

#include <sys/types.h>

#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "navmap/ipc/client/dmabuf_block.h"
#include "navmap/ipc/client/frame_view.h"
#include "navmap/ipc/client/stream_profile.h"
#include "navmap/ipc/net/result.h"
#include "navmap/ipc/net/socket_access.h"
#include "navmap/ipc/stream/metrics_registry.h"

namespace navmap::ipc {

/// A profile the daemon renders (its [[profile]] entry): what clients may ask for. A request
/// names it by name (or, with another name, by its view and size: the first such profile).
struct RenderedProfile {
    std::string name;  ///< the key publish() uses: "cluster"
    std::string view;  ///< stream view: "snail", "bird", "hud"
    int width = 0;
    int height = 0;
};

struct FrameServerOptions {
    std::string unix_path;            ///< Unix stream socket; empty = none
    mode_t unix_mode = 0660;          ///< the socket file's mode, whatever the umask
    std::optional<gid_t> unix_group;  ///< the socket file's group (chown before listen); none: the process's
    /// Who may connect to the Unix socket (SO_PEERCRED/SO_PEERGROUPS, checked on accept): by
    /// default the server's own uid and root; `unix_group` is allowed as well.
    PeerAllowList allowed_peers;
    std::string bind_address = "127.0.0.1";  ///< for TCP and HTTP
    int tcp_port = -1;                       ///< -1 = none, 0 = any free port (see tcpPort())
    int http_port = -1;                      ///< -1 = none, 0 = any free port (see httpPort())
    /// HTTP: when not empty, every request needs `Authorization: Bearer <token>` or `?token=<token>`.
    std::string http_token;
    /// Slots per profile ring (>= 2). Three give a client two frame periods between the
    /// notification and the end of its copy; each slot costs stride x height bytes of shared memory.
    std::uint32_t ring_slots = 3;
    std::chrono::milliseconds stall_timeout{2000};  ///< no ack / no write progress
    /// A connection must finish its handshake (or HTTP request head) within this time of being
    /// accepted, and a streaming client must get its first frame within this time of its
    /// handshake; otherwise it is closed (counted, reason in last_error).
    std::chrono::milliseconds handshake_timeout{5000};
    /// Connections per transport (Unix, TCP, HTTP each have this many, handshakes included); one
    /// more is refused with an error and closed at once.
    std::size_t max_clients_per_transport = 32;
    /// Unix-socket connections per peer uid, so one uid cannot take every slot. TCP and HTTP
    /// peers have no uid: max_clients_per_address bounds them.
    std::size_t max_clients_per_uid = 8;
    /// TCP connections per peer address, and HTTP connections per peer address (each transport
    /// counts its own), so one host cannot take every slot of a transport. IPv6 peers count per
    /// /64 prefix (one host usually has a whole /64); an IPv4 peer on an IPv6 socket by its IPv4
    /// address.
    std::size_t max_clients_per_address = 8;
    /// Shared memory of all rings together (memfd sizes); a request that needs a new ring beyond
    /// it is refused with an error and counted. 0 = no ceiling. A ring a Unix client was given
    /// stays counted after its clients leave (idle, reused by the next client of its profile,
    /// size and format), because a client's mapping may outlive its connection.
    std::size_t ring_memory_bytes = std::size_t{256} << 20;
    /// What the daemon renders; a request for another profile, view or size is refused naming
    /// these, and rings are keyed by these names. Empty: any view and size is accepted and rings
    /// are keyed by the view (for tests and tools that publish what they are asked for).
    std::vector<RenderedProfile> rendered_profiles;
    int jpeg_quality = 80;
    std::string mjpeg_profile = "center";  ///< profile of /stream.mjpg without ?profile=
    /// Whether a handshake asking for payload dmabuf is accepted (docs/frame-protocol.md "dma-buf
    /// frames"): an empty string accepts it (the publisher then calls publishDmabuf() for those
    /// clients); any other text refuses it with `handshake: dmabuf frames are not available here
    /// (<text>); ask for shm`. navmapd returns its renderer's probe (render/dmabuf_probe.h), known
    /// only once the renderer is up. Server thread; must be thread-safe. No function: refused,
    /// "this server exports no dma-buf frames".
    std::function<std::string()> dmabuf_unavailable_reason;
    /// Adds the daemon's families to /metrics, after the server's own navmap_stream_* ones (one
    /// registry per scrape, so no family appears twice). Called on the server thread; must be
    /// thread-safe with respect to the daemon.
    std::function<void(MetricsRegistry&)> metrics;
    /// JSON object shown by the HTML page under "daemon" in /status. Server thread.
    std::function<std::string()> status_json;
};

/// A frame in a buffer the renderer exported (docs/frame-protocol.md "dma-buf frames"), for
/// FrameServer::publishDmabuf().
struct DmabufBuffer {
    int index = -1;                ///< the buffer's index, 0..kDmabufMaxBuffers-1 (the header's slot)
    std::uint64_t generation = 0;  ///< its allocation: a new one makes the server send the fd again
    int fd = -1;                   ///< the buffer's dma-buf, borrowed: the server keeps a duplicate
    DmabufBlock layout;            ///< fourcc, modifier, stride, offset, width, height (flags unused)
    int fence_fd = -1;             ///< the frame's sync fence, given to the server; -1: finished
};

/// A profile that has at least one client: what the daemon should render.
struct ActiveProfile {
    std::string profile;  ///< the ring key: a RenderedProfile's name (or the view without rendered_profiles)
    std::string view;
    int width = 0;
    int height = 0;
    int max_fps = 0;  ///< highest fps any of its clients asked for
    std::size_t clients = 0;
    /// Of `clients`, those that take dma-buf frames (publishDmabuf); the others need pixels
    /// (publish).
    std::size_t dmabuf_clients = 0;
};

/// Counters (snapshot; any thread).
struct FrameServerStats {
    std::size_t connections = 0;  ///< open sockets, including handshakes and HTTP replies in flight
    std::size_t clients = 0;      ///< connected and streaming (all transports)
    std::size_t shm_clients = 0;
    std::size_t tcp_clients = 0;
    std::size_t mjpeg_clients = 0;
    std::size_t dmabuf_clients = 0;  ///< Unix clients taking dma-buf frames
    std::size_t rings = 0;           ///< rings with clients
    /// Rings without clients kept for reuse: a client was given their memfd, and its mapping may
    /// outlive its connection (counted in ring_bytes; docs/frame-protocol.md "Ring memory").
    std::size_t rings_idle = 0;
    std::uint64_t rings_reused = 0;        ///< idle rings that got a client again instead of a new ring
    std::uint64_t published = 0;           ///< publish() and publishDmabuf() calls that reached a client
    std::uint64_t frames_sent = 0;         ///< frames handed to clients
    std::uint64_t statuses_sent = 0;       ///< status headers handed to clients (publishStatus)
    std::uint64_t dmabuf_frames_sent = 0;  ///< of frames_sent, dma-buf frames
    std::uint64_t dmabuf_fds_sent = 0;     ///< buffer fds passed (a client's first frame of each allocation)
    /// Frames a client was entitled to (within its fps) but did not get because it was busy.
    std::uint64_t frames_dropped = 0;
    std::uint64_t accepted = 0;  ///< connections accepted
    std::uint64_t handshake_errors = 0;
    std::uint64_t protocol_errors = 0;  ///< garbage after the handshake
    std::uint64_t http_errors = 0;      ///< 4xx replies
    std::uint64_t stall_disconnects = 0;
    std::uint64_t handshake_timeouts = 0;      ///< closed without a complete handshake / HTTP head in time
    std::uint64_t first_frame_timeouts = 0;    ///< streaming, but no first frame within handshake_timeout
    std::uint64_t refused_peer = 0;            ///< Unix peers not on the allow list
    std::uint64_t refused_transport_full = 0;  ///< max_clients_per_transport reached
    std::uint64_t refused_uid_full = 0;        ///< max_clients_per_uid reached
    std::uint64_t refused_address_full = 0;    ///< max_clients_per_address reached (TCP, HTTP)
    std::uint64_t refused_not_rendered = 0;    ///< a view/size the daemon does not render
    std::uint64_t refused_ring_memory = 0;     ///< a new ring would pass ring_memory_bytes
    std::uint64_t refused_host = 0;            ///< HTTP Host header missing or not this server
    std::uint64_t refused_token = 0;           ///< HTTP token missing or wrong
    std::size_t ring_bytes = 0;                ///< shared memory of all rings now, idle ones included
    std::uint64_t disconnects = 0;             ///< all closed connections
    std::uint64_t pinned_overwrites = 0;       ///< frames written over a held slot (every slot of a ring held)
    double publish_ms_last = 0;                ///< render-thread cost of the last publish()
    double publish_ms_max = 0;
    std::string last_error;  ///< newest problem: "tcp#7: handshake: unknown key \"x\""
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

    /// Render thread: copies the frame into every ring of `profile` (a RenderedProfile's name;
    /// the view when the server has no rendered_profiles) with its width and height, converting
    /// the pixel format, and wakes the server thread. Never blocks on a client. Returns the
    /// number of rings written.
    std::size_t publish(const std::string& profile, const FrameView& frame);

    /// Render thread: the frame of `profile` is in exported buffer `buffer` (docs/frame-protocol.md
    /// "dma-buf frames"); its dma-buf clients of that size get it, with the buffer's fd the first
    /// time each gets that allocation and the fence fd (duplicated per client). `info` gives the
    /// header's times, validity and metadata block (its pixels are not used). Never blocks on a
    /// client. Returns the number of rings whose dma-buf clients it reached; 0 also closes the fence.
    std::size_t publishDmabuf(const std::string& profile, const FrameView& info, DmabufBuffer buffer);
    /// Render thread: the buffers of `profile` it must not write now (bit i: buffer i), because a
    /// client holds one (until its ack) or it holds the newest frame (not yet sent to everyone).
    std::uint32_t dmabufBusy(const std::string& profile) const;

    /// Render thread, before the first frame of `profile` (the name publish() gets) at width x
    /// height: sends `json` (a UTF-8 JSON object, at most 64 KiB) as a status header to each
    /// client of that profile and size (either format) that has finished its handshake and has
    /// had no frame yet, over the Unix
    /// socket (shm, raw, zlib) and TCP; MJPEG clients get none. Each status restarts that
    /// client's first-frame timeout. Like publish() it hands the text to the server thread and
    /// never waits for a client; a newer status of the same profile and size replaces one not sent
    /// yet, and a client whose socket still holds unsent bytes skips it. Error (nothing sent):
    /// the text is too long or not UTF-8.
    Status publishStatus(const std::string& profile, int width, int height, std::string json);

    /// Profiles with clients now (which views/sizes to render). Any thread.
    std::vector<ActiveProfile> activeProfiles() const;
    FrameServerStats stats() const;
    /// Adds the server's own metric families (navmap_stream_*) to `registry`. Any thread.
    void collectMetrics(MetricsRegistry& registry) const;
    /// The server's own families as Prometheus text. Any thread.
    std::string metricsText() const;

    int tcpPort() const noexcept;   ///< bound port, -1 when none
    int httpPort() const noexcept;  ///< bound port, -1 when none
    const FrameServerOptions& options() const noexcept;

private:
    class Impl;
    std::unique_ptr<Impl> m_impl;
};

}  // namespace navmap::ipc
