// SPDX-License-Identifier: Apache-2.0
#pragma once
// StreamProfile and the client handshake: one JSON line the client sends first on the Unix or
// TCP socket (docs/frame-protocol.md). Parsing never throws; every problem is an Error.

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

#include "navmap/ipc/client/frame_format.h"
#include "navmap/ipc/net/client_api.h"
#include "navmap/ipc/net/result.h"

namespace navmap::ipc {

/// What a display client wants: size, frame rate, view and pixel format.
struct StreamProfile {
    std::string name = "custom";  ///< "cluster", "hud", "center" or a free name
    int width = 1280;
    int height = 480;
    int fps = 30;                ///< most frames per second the client wants; 0 = every frame (recorders)
    std::string view = "snail";  ///< "bird", "snail" or "hud"
    PixelFormat format = PixelFormat::Rgba8;
};

/// The defaults of docs/architecture.md "Display profiles": cluster 1280x480 snail, hud 800x240 hud, center 1280x720
/// bird (30 fps, RGBA8). nullopt for other names.
NAVMAP_CLIENT_API std::optional<StreamProfile> defaultStreamProfile(std::string_view name);

/// How the pixels travel.
enum class StreamPayload {
    Shm,   ///< shared-memory ring (Unix socket only)
    Raw,   ///< on the socket, uncompressed
    Zlib,  ///< on the socket, zlib-compressed
    /// dma-bufs the GPU rendered into (Unix socket only; docs/frame-protocol.md "dma-buf
    /// frames"). No server exports them yet: navmapd refuses the request naming why, and a
    /// client with StreamRequest::dmabuf_fallback_shm asks for shm instead.
    Dmabuf,
};
NAVMAP_CLIENT_API const char* streamPayloadName(StreamPayload payload) noexcept;

struct StreamRequest {
    StreamProfile profile;
    StreamPayload payload = StreamPayload::Shm;
    /// Payload shm: the client holds frames in place until its ack (StreamClient::nextHeld), so
    /// the server keeps the notified slot from the writer while another slot is free.
    bool hold = false;
    /// The metadata block (frame_meta.h) after every frame header: "meta":true in the handshake.
    /// Off by default, so a client that does not know the block never gets one.
    bool meta = false;
    /// Client side only, never sent: a request for payload dmabuf that the server refuses (or
    /// accepts in a form this library cannot import) is made again as payload shm on a new
    /// connection (StreamClient::connectUnix; StreamClient::fallbackReason() says why).
    bool dmabuf_fallback_shm = false;
};

inline constexpr std::size_t kMaxHandshakeBytes = 4096;
inline constexpr int kMinStreamDimension = 16;
inline constexpr int kMaxStreamDimension = 4096;
inline constexpr int kMaxStreamFps = 1000;  ///< displays need <= 240; recorders and benchmarks more

/// Parses one handshake line (without or with the trailing '\n'):
///   {"version":1,"profile":"cluster","width":1280,"height":480,"fps":30,"view":"snail",
///    "format":"rgba8","payload":"shm","hold":true,"meta":true}
/// "version" and either "profile" (a default name) or all of width/height/view are required;
/// given fields override the named profile's. Unknown keys, wrong types and out-of-range values
/// are errors naming the key.
NAVMAP_CLIENT_API Result<StreamRequest> parseStreamRequest(std::string_view line);

/// The handshake line for `request`, ending in '\n'. parseStreamRequest() reads it back equal.
NAVMAP_CLIENT_API std::string formatStreamRequest(const StreamRequest& request);

/// The server's answer to a StreamRequest, as the client reads it.
struct StreamReply {
    bool accepted = false;
    std::string refusal;               ///< !accepted: the server's "error" text ("?" when it gave none)
    StreamProfile profile;             ///< accepted: the granted profile (its size and format are the request's)
    std::uint32_t ring_slots = 0;      ///< payload shm: slots of the ring
    std::size_t ring_total_bytes = 0;  ///< payload shm: the ring memfd's size, as the layout gives it
};

/// Parses the server's reply line to `request` (docs/frame-protocol.md "Handshake"):
///   {"ok":true,"version":1,"profile":{"name":..,"width":..,"height":..,"fps":..,"view":..,"format":..},
///    "payload":"shm","stride":..,"header_bytes":80,"ring":{"slots":..,"slot_bytes":..,"total_bytes":..,
///    "header_offset":64,"pixel_offset":256}}   or   {"ok":false,"error":"why"}
/// The server is not trusted: every field present must have its type and range (the ones a
/// request may have), the granted size and format must be the requested ones, payload shm needs
/// "ring" with sizes that match the profile's layout. Absent optional fields keep the request's
/// values. Never throws; an Error names the field ("reply: \"profile.width\" must be an integer").
NAVMAP_CLIENT_API Result<StreamReply> parseStreamReply(std::string_view line, const StreamRequest& request);

}  // namespace navmap::ipc
