// SPDX-License-Identifier: Apache-2.0
#pragma once
// FrameHeader: the per-frame header shared by every transport (shm notification, shm slot, TCP).
// Fixed 80 bytes, little-endian; the layout is in docs/frame-protocol.md.

#include <array>
#include <cstddef>
#include <cstdint>

#include "navmap/ipc/client/frame_format.h"
#include "navmap/ipc/client/frame_meta.h"
#include "navmap/ipc/net/client_api.h"
#include "navmap/ipc/net/result.h"

namespace navmap::ipc {

inline constexpr std::uint32_t kFrameMagic = 0x52464D4EU;  ///< "NMFR" as little-endian bytes
inline constexpr std::uint16_t kFrameProtocolVersion = 1;
inline constexpr std::size_t kFrameHeaderBytes = 80;
inline constexpr std::uint32_t kMaxFrameDimension = 8192;
inline constexpr std::uint32_t kMaxErrorPayloadBytes = 64 * 1024;
inline constexpr std::uint32_t kMaxStatusPayloadBytes = 64 * 1024;

/// What follows a header.
enum class FrameKind : std::uint16_t {
    Frame = 0,   ///< a frame (payload per `encoding`)
    Error = 1,   ///< the server's last word: payload is a UTF-8 message, then the connection closes
    Status = 2,  ///< before the first frame: payload is a UTF-8 JSON object; the connection stays open
};

/// Where a frame's pixels are.
enum class FrameEncoding : std::uint16_t {
    Shm = 0,   ///< in slot `slot` of the shared-memory ring (payload_bytes = 0)
    Raw = 1,   ///< payload_bytes = stride * height bytes follow the header
    Zlib = 2,  ///< payload_bytes of a zlib stream follow; it inflates to stride * height bytes
    /// In exported buffer `slot`: the 48-byte dma-buf block follows (payload_bytes = 48;
    /// dmabuf_block.h), the buffer's and fence's fds with it (SCM_RIGHTS) where its flags say so
    Dmabuf = 3,
};

struct FrameHeader {
    FrameKind kind = FrameKind::Frame;
    FrameEncoding encoding = FrameEncoding::Raw;
    PixelFormat format = PixelFormat::Rgba8;
    std::uint64_t sequence = 0;       ///< per profile ring, starts at 1, +1 per published frame
    std::int64_t render_time_ns = 0;  ///< CLOCK_REALTIME ns when the frame was rendered (published)
    std::int64_t source_time_ns = 0;  ///< CLOCK_REALTIME ns the CAN data behind the pose was received (0 = none)
    std::uint32_t width = 0;
    std::uint32_t height = 0;
    std::uint32_t stride = 0;         ///< bytes per row
    std::uint32_t payload_bytes = 0;  ///< bytes following the header on the socket
    std::uint64_t dropped = 0;        ///< frames this client has missed so far (server side)
    std::uint32_t slot = 0;           ///< ring slot (encoding Shm), buffer index (encoding Dmabuf)
    /// Whether the frame can be trusted (bytes 68..75; version 0 from servers before it existed).
    FrameValidity validity;
    /// Bytes of the metadata block that follows this header on the socket, before any payload
    /// (bytes 76..77): only for clients that asked for it, 0 in ring slots and for other kinds.
    std::uint16_t meta_bytes = 0;

    std::size_t pixelBytes() const noexcept { return static_cast<std::size_t>(stride) * height; }
};

/// Writes the 80-byte wire form.
NAVMAP_CLIENT_API std::array<std::uint8_t, kFrameHeaderBytes> encodeFrameHeader(const FrameHeader& header) noexcept;

/// Parses and validates a wire header: magic, version, size, known enums, dimensions within
/// kMaxFrameDimension, stride >= width * bytesPerPixel, payload size consistent with the encoding.
/// The validity bytes must follow validateFrameValidity(), meta_bytes be at most
/// kMaxFrameMetaBytes (0 for Error and Status), bytes 78..79 be 0.
/// For kinds Error and Status only the payload size is checked (at most 64 KiB); the payload
/// itself is checked with validateTextPayload once it has been read.
NAVMAP_CLIENT_API Result<FrameHeader> decodeFrameHeader(const std::uint8_t* data, std::size_t size);

/// Checks the payload of an Error or Status header: at most 64 KiB of well-formed UTF-8 (no
/// overlong forms, no surrogates, nothing above U+10FFFF). The error names the first bad byte.
Status validateTextPayload(FrameKind kind, const std::uint8_t* data, std::size_t size);

}  // namespace navmap::ipc
