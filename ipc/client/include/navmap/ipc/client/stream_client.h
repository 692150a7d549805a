// SPDX-License-Identifier: Apache-2.0
#pragma once
// StreamClient: the display-client side of docs/frame-protocol.md. Connects over the Unix socket
// (shared-memory ring) or TCP (raw/zlib), then next() returns the newest frames as a copy, or
// nextHeld() hands out a frame in place in the mapped ring (no copy) until release(); statuses the
// server sends before the first frame are kept (lastStatus) and passed to a handler, and the wait
// goes on. Part of libnavmap-client, which links nothing but the C and C++ runtime. Not
// thread-safe: one thread owns a client. ReconnectingClient (reconnecting_client.h) adds
// reconnection with backoff.

#include <array>
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "navmap/ipc/client/dmabuf_block.h"
#include "navmap/ipc/client/frame_header.h"
#include "navmap/ipc/client/stream_profile.h"
#include "navmap/ipc/net/client_api.h"
#include "navmap/ipc/net/result.h"

namespace navmap::ipc {

struct ReceivedFrame {
    FrameHeader header;                ///< dropped = server-side drops + frames lost locally
    std::vector<std::uint8_t> pixels;  ///< header.stride * header.height bytes, header.format
    std::int64_t receive_time_ns = 0;  ///< CLOCK_REALTIME ns when the pixels were complete
    /// The frame's metadata block (request.meta), validated; none when not asked for, when the
    /// server sent none, or when the notified shm frame was overwritten and a newer one taken.
    std::optional<FrameMeta> meta;
};

/// A frame left where the server wrote it (payload shm): `pixels` points into the client's
/// read-only mapping of the ring, header.stride * header.height bytes in header.format, and stays
/// valid until StreamClient::release(). The server does not overwrite a held slot while its ring
/// has a slot nobody holds (docs/frame-protocol.md "Holding a frame"). On a stream of payload
/// dmabuf the pixels are in the client's read-only mapping of the frame's exported buffer
/// (header.stride is the buffer's), and `dmabuf_fd` and `dmabuf` say how to import that buffer
/// instead.
struct HeldFrame {
    FrameHeader header;
    const std::uint8_t* pixels = nullptr;
    std::int64_t receive_time_ns = 0;  ///< CLOCK_REALTIME ns when the notification was read
    std::optional<FrameMeta> meta;     ///< as ReceivedFrame::meta
    int dmabuf_fd = -1;                ///< payload dmabuf: the buffer's fd (owned by the client); else -1
    DmabufBlock dmabuf;                ///< payload dmabuf: its layout
};

/// A frame left in the buffer the server rendered it into (payload dmabuf; docs/frame-protocol.md
/// "dma-buf frames"): import `fd` as an EGLImage (EGL_EXT_image_dma_buf_import) or hand it to the
/// compositor (zwp_linux_dmabuf_v1) with the block's fourcc, modifier, stride and offset, or map it.
/// The frame is complete when nextDmabuf() returns (its fence, if any, has signalled); the server
/// does not write the buffer again until release().
struct DmabufFrameRef {
    FrameHeader header;  ///< slot: the buffer's index
    DmabufBlock block;   ///< how to import it (flags: what came with this frame)
    /// The buffer's dma-buf, owned by the client: valid until the server replaces that buffer
    /// (new_buffer) or the client is destroyed; dup it to keep it longer.
    int fd = -1;
    bool new_buffer = false;  ///< this index got a new fd with this frame: import it (again)
    std::int64_t receive_time_ns = 0;
    std::optional<FrameMeta> meta;
};

struct StreamClientStats {
    std::uint64_t frames = 0;
    std::uint64_t server_dropped = 0;    ///< the newest header's dropped count
    std::uint64_t lost_locally = 0;      ///< shm slots overwritten before we copied them
    std::uint64_t held_overwritten = 0;  ///< held frames the server had to overwrite before release()
    std::uint64_t bytes = 0;             ///< payload bytes received (compressed size for zlib)
    std::uint64_t statuses = 0;          ///< status headers received
    std::uint64_t dmabuf_fds = 0;        ///< payload dmabuf: buffer fds received
    /// Pixel copies this client made on the CPU (next(): one per frame; nextHeld() and
    /// nextDmabuf(): none).
    std::uint64_t cpu_copies = 0;
};

/// Inflates a zlib payload of `inBytes` into exactly `outBytes` at `out`; false when it does not.
/// The client library links no compression library: a client that asks for payload zlib passes
/// one (navmap's own programs use navmap::ipc::zlibInflater() from frame_png.h's library; any
/// client can wrap zlib's uncompress() in these few lines).
using FrameInflater =
    std::function<bool(const std::uint8_t* in, std::size_t in_bytes, std::uint8_t* out, std::size_t out_bytes)>;

class NAVMAP_CLIENT_API StreamClient {
public:
    /// Connects to the server's Unix socket and sends `request` (payload shm, raw, zlib or
    /// dmabuf). Payload dmabuf with request.dmabuf_fallback_shm: when that handshake fails (the
    /// server refuses it, as every server does today, or this library cannot import what it
    /// offers), connects again asking for shm; payload() then says Shm and fallbackReason() why.
    static Result<std::unique_ptr<StreamClient>> connectUnix(
        const std::string& path, const StreamRequest& request,
        std::chrono::milliseconds timeout = std::chrono::seconds(5), FrameInflater inflate = {});
    /// Connects to host:port (numeric IPv4/IPv6 or a name) and sends `request` (raw or zlib).
    static Result<std::unique_ptr<StreamClient>> connectTcp(const std::string& host, int port,
                                                            const StreamRequest& request,
                                                            std::chrono::milliseconds timeout = std::chrono::seconds(5),
                                                            FrameInflater inflate = {});
    ~StreamClient();
    StreamClient(const StreamClient&) = delete;
    StreamClient& operator=(const StreamClient&) = delete;

    /// Waits up to `timeout` for the next frame. true: `out` holds it; false: timeout; Error: the
    /// server closed the connection or broke the protocol (the message says which, including the
    /// server's error text). A held frame is released first.
    /// A status (header kind 2, before the first frame) is not a frame: it is checked (UTF-8, at
    /// most 64 KiB), kept as lastStatus(), handed to the status handler, and the wait goes on.
    Result<bool> next(ReceivedFrame& out, std::chrono::milliseconds timeout);

    /// For a stream opened with request.hold (payload shm, or dmabuf): like next(), but the frame
    /// stays in the ring or its exported buffer (no copy) and the server gets no ack until
    /// release(); no new frame arrives meanwhile. A held frame is released
    /// first. Hold a frame for less than the server's stall timeout (FrameServerOptions::
    /// stall_timeout; navmapd's client_timeout_s, 5 s), or the server disconnects the client.
    Result<bool> nextHeld(HeldFrame& out, std::chrono::milliseconds timeout);
    /// Gives a held frame back (sends the ack). true: the frame was unchanged all the time it was
    /// held; false: every slot of the ring was held at once and the server overwrote this one
    /// (counted in stats().held_overwritten); Error: the connection is gone. true without a held frame.
    Result<bool> release();
    bool holding() const noexcept { return m_held >= 0; }

    /// For a stream of payload dmabuf: the next frame in its exported buffer (no copy); the
    /// server gets no ack until release() (or the next call), as with nextHeld(). next() works on
    /// such a stream too: it copies the pixels out of the mapped buffer and acks at once.
    Result<bool> nextDmabuf(DmabufFrameRef& out, std::chrono::milliseconds timeout);

    /// Called inside next() with each status's text (a JSON object from the server, e.g.
    /// {"state":"loading",...}) as it arrives; the caller's thread. Empty: statuses are only kept.
    void setStatusHandler(std::function<void(const std::string&)> handler) { m_on_status = std::move(handler); }
    /// The newest status text; empty when none came.
    const std::string& lastStatus() const noexcept { return m_last_status; }

    /// The profile the server granted (after defaults were applied).
    const StreamProfile& profile() const noexcept { return m_profile; }
    /// The payload granted: after a dmabuf request that fell back, Shm.
    StreamPayload payload() const noexcept { return m_payload; }
    /// Why a dmabuf request fell back to shm (the refusal or reply error); empty when it did not.
    const std::string& fallbackReason() const noexcept { return m_fallback_reason; }
    const StreamClientStats& stats() const noexcept { return m_stats; }
    int fd() const noexcept { return m_fd; }

private:
    StreamClient() { m_dmabufs.fill(-1); }
    static Result<std::unique_ptr<StreamClient>> handshake(int fd, const std::string& peer,
                                                           const StreamRequest& request,
                                                           std::chrono::milliseconds timeout, FrameInflater inflate);
    Status readExact(std::uint8_t* dst, std::size_t n, std::chrono::steady_clock::time_point deadline, bool* timed_out);
    /// Reads the next header (kept across timeouts); false on timeout.
    Result<bool> readHeader(FrameHeader& out, std::chrono::steady_clock::time_point deadline);
    /// Reads a status header's text, checks it and hands it to the handler.
    Status takeStatus(const FrameHeader& h, std::chrono::steady_clock::time_point deadline);
    /// Reads and checks the metadata block after `h` (none when h.meta_bytes is 0).
    Status readMeta(const FrameHeader& h, std::chrono::steady_clock::time_point deadline,
                    std::optional<FrameMeta>* out);
    /// Where a frame goes: copied out, held in the ring, or referenced in its dma-buf.
    struct Out {
        ReceivedFrame* copy = nullptr;
        HeldFrame* held = nullptr;
        DmabufFrameRef* dmabuf = nullptr;
    };
    Result<bool> receive(Out out, std::chrono::milliseconds timeout);
    /// Shm frame `h`: copies or holds it. false: overwritten before it was read (acked already).
    Result<bool> takeShm(FrameHeader& h, Out out, std::optional<FrameMeta>& meta, const std::uint8_t** held_pixels);
    /// Dma-buf frame `h`: reads its block, takes the fds that came with it, waits for its fence,
    /// then copies the pixels (out.copy, acked) or hands the buffer out (held until release()).
    Status takeDmabuf(const FrameHeader& h, Out out, std::chrono::steady_clock::time_point deadline);
    /// The next descriptor that came with the stream's bytes; Error naming `what` when none did.
    Result<int> takeFd(const FrameHeader& h, const char* what);
    Status sendAck();
    /// The fds buffer to receive into: the stream's when it carries dma-bufs, else none.
    std::vector<int>* fdSink() { return m_payload == StreamPayload::Dmabuf ? &m_fds : nullptr; }

    int m_fd = -1;
    std::string m_peer;
    StreamProfile m_profile;
    StreamPayload m_payload = StreamPayload::Shm;
    std::string m_fallback_reason;
    std::uint64_t m_last_sequence = 0;  ///< newest frame handed out (never hand one out twice)
    const std::uint8_t* m_map = nullptr;
    std::size_t m_map_bytes = 0;
    std::uint32_t m_slots = 0;
    std::vector<std::uint8_t> m_in;  // bytes received beyond what was consumed
    std::size_t m_in_pos = 0;
    std::vector<std::uint8_t> m_compressed;
    StreamClientStats m_stats;
    std::uint8_t m_header_buf[kFrameHeaderBytes] = {};
    std::size_t m_header_have = 0;  // partial header kept across timeouts
    FrameInflater m_inflate;
    bool m_hold = false;                           // opened with request.hold: frames may be held
    bool m_meta = false;                           // opened with request.meta: frames may carry a metadata block
    int m_held = -1;                               // slot of the held frame, -1: none
    std::uint64_t m_held_lock = 0;                 // its lock word when it was handed out
    std::vector<int> m_fds;                        // payload dmabuf: descriptors received, not yet taken
    std::array<int, kDmabufMaxBuffers> m_dmabufs;  // payload dmabuf: each buffer's fd (-1: none yet)
    struct Mapping {
        void* at = nullptr;
        std::size_t bytes = 0;
    };
    std::array<Mapping, kDmabufMaxBuffers> m_dmabuf_maps{};  // nextHeld() on dmabuf: read-only mappings
    /// Buffer `index`'s read-only mapping (made on first use, dropped when its fd is replaced).
    Result<const std::uint8_t*> mapDmabuf(int index, const DmabufBlock& block);
    void unmapDmabuf(int index);
    std::string m_last_status;
    std::function<void(const std::string&)> m_on_status;
};

}  // namespace navmap::ipc
