// SPDX-License-Identifier: Apache-2.0
#include "navmap/ipc/client/frame_header.h"

#include <cstdio>
#include <string>

namespace navmap::ipc {
namespace {

template <typename T>
void put(std::uint8_t* out, std::size_t off, T v) noexcept {
    for (std::size_t i = 0; i < sizeof(T); ++i) {
        out[off + i] = static_cast<std::uint8_t>(static_cast<std::uint64_t>(v) >> (8 * i));
    }
}

template <typename T>
T get(const std::uint8_t* in, std::size_t off) noexcept {
    std::uint64_t v = 0;
    for (std::size_t i = 0; i < sizeof(T); ++i) {
        v |= static_cast<std::uint64_t>(in[off + i]) << (8 * i);
    }
    return static_cast<T>(v);
}

}  // namespace

// Layout (little-endian), docs/frame-protocol.md:
//  0 magic u32 | 4 version u16 | 6 header bytes u16 | 8 kind u16 | 10 encoding u16 | 12 format u32
// 16 sequence u64 | 24 render ns i64 | 32 source ns i64 | 40 width u32 | 44 height u32
// 48 stride u32 | 52 payload bytes u32 | 56 dropped u64 | 64 slot u32 | 68 validity version u8
// 69 validity flags u8 | 70 degraded reasons u16 | 72 pose age ms u32 | 76 meta bytes u16 | 78 reserved u16 (0)
std::array<std::uint8_t, kFrameHeaderBytes> encodeFrameHeader(const FrameHeader& h) noexcept {
    std::array<std::uint8_t, kFrameHeaderBytes> out{};
    std::uint8_t* o = out.data();
    put<std::uint32_t>(o, 0, kFrameMagic);
    put<std::uint16_t>(o, 4, kFrameProtocolVersion);
    put<std::uint16_t>(o, 6, static_cast<std::uint16_t>(kFrameHeaderBytes));
    put<std::uint16_t>(o, 8, static_cast<std::uint16_t>(h.kind));
    put<std::uint16_t>(o, 10, static_cast<std::uint16_t>(h.encoding));
    put<std::uint32_t>(o, 12, static_cast<std::uint32_t>(h.format));
    put<std::uint64_t>(o, 16, h.sequence);
    put<std::int64_t>(o, 24, h.render_time_ns);
    put<std::int64_t>(o, 32, h.source_time_ns);
    put<std::uint32_t>(o, 40, h.width);
    put<std::uint32_t>(o, 44, h.height);
    put<std::uint32_t>(o, 48, h.stride);
    put<std::uint32_t>(o, 52, h.payload_bytes);
    put<std::uint64_t>(o, 56, h.dropped);
    put<std::uint32_t>(o, 64, h.slot);
    put<std::uint8_t>(o, 68, h.validity.version);
    put<std::uint8_t>(o, 69, h.validity.flags);
    put<std::uint16_t>(o, 70, h.validity.degraded);
    put<std::uint32_t>(o, 72, h.validity.pose_age_ms);
    put<std::uint16_t>(o, 76, h.meta_bytes);
    return out;
}

Result<FrameHeader> decodeFrameHeader(const std::uint8_t* d, std::size_t size) {
    if (size < kFrameHeaderBytes) {
        return Error{"frame header: " + std::to_string(size) + " bytes, need " + std::to_string(kFrameHeaderBytes)};
    }
    if (get<std::uint32_t>(d, 0) != kFrameMagic) {
        return Error{"frame header: bad magic (not a navmap frame stream)"};
    }
    const auto version = get<std::uint16_t>(d, 4);
    if (version != kFrameProtocolVersion) {
        return Error{"frame header: unsupported version " + std::to_string(version)};
    }
    if (get<std::uint16_t>(d, 6) != kFrameHeaderBytes) {
        return Error{"frame header: header size " + std::to_string(get<std::uint16_t>(d, 6)) + ", expected 80"};
    }
    FrameHeader h;
    const auto kind = get<std::uint16_t>(d, 8);
    const auto encoding = get<std::uint16_t>(d, 10);
    const auto format = get<std::uint32_t>(d, 12);
    if (kind > 2) {
        return Error{"frame header: unknown kind " + std::to_string(kind)};
    }
    h.kind = static_cast<FrameKind>(kind);
    h.sequence = get<std::uint64_t>(d, 16);
    h.render_time_ns = get<std::int64_t>(d, 24);
    h.source_time_ns = get<std::int64_t>(d, 32);
    h.width = get<std::uint32_t>(d, 40);
    h.height = get<std::uint32_t>(d, 44);
    h.stride = get<std::uint32_t>(d, 48);
    h.payload_bytes = get<std::uint32_t>(d, 52);
    h.dropped = get<std::uint64_t>(d, 56);
    h.slot = get<std::uint32_t>(d, 64);
    h.validity.version = get<std::uint8_t>(d, 68);
    h.validity.flags = get<std::uint8_t>(d, 69);
    h.validity.degraded = get<std::uint16_t>(d, 70);
    h.validity.pose_age_ms = get<std::uint32_t>(d, 72);
    h.meta_bytes = get<std::uint16_t>(d, 76);
    if (get<std::uint16_t>(d, 78) != 0) {
        return Error{"frame header: reserved bytes 78..79 are not 0"};
    }
    if (auto s = validateFrameValidity(h.validity); !s) {
        return Error{s.message()};
    }
    if (h.meta_bytes != 0 &&
        (h.kind != FrameKind::Frame || h.meta_bytes < kFrameMetaFixedBytes || h.meta_bytes > kMaxFrameMetaBytes)) {
        return Error{"frame header: metadata of " + std::to_string(h.meta_bytes) + " bytes" +
                     (h.kind != FrameKind::Frame ? " on an error or status" : "")};
    }
    if (h.kind == FrameKind::Error) {
        if (h.payload_bytes > kMaxErrorPayloadBytes) {
            return Error{"frame header: error message of " + std::to_string(h.payload_bytes) + " bytes"};
        }
        return h;
    }
    if (h.kind == FrameKind::Status) {
        if (h.payload_bytes > kMaxStatusPayloadBytes) {
            return Error{"frame header: status of " + std::to_string(h.payload_bytes) + " bytes (limit " +
                         std::to_string(kMaxStatusPayloadBytes) + ")"};
        }
        return h;
    }
    if (encoding > 3) {
        return Error{"frame header: unknown encoding " + std::to_string(encoding)};
    }
    h.encoding = static_cast<FrameEncoding>(encoding);
    if (!isKnownPixelFormat(format)) {
        return Error{"frame header: unknown pixel format " + std::to_string(format)};
    }
    h.format = static_cast<PixelFormat>(format);
    if (h.width == 0 || h.height == 0 || h.width > kMaxFrameDimension || h.height > kMaxFrameDimension) {
        return Error{"frame header: bad size " + std::to_string(h.width) + "x" + std::to_string(h.height)};
    }
    if (static_cast<std::uint64_t>(h.stride) < static_cast<std::uint64_t>(h.width) * bytesPerPixel(h.format) ||
        h.stride > 4 * kMaxFrameDimension) {
        return Error{"frame header: stride " + std::to_string(h.stride) + " too small or too large for width " +
                     std::to_string(h.width)};
    }
    switch (h.encoding) {
        case FrameEncoding::Shm:
            if (h.payload_bytes != 0) {
                return Error{"frame header: shm frame with a socket payload"};
            }
            break;
        case FrameEncoding::Raw:
            if (h.payload_bytes != h.pixelBytes()) {
                return Error{"frame header: raw payload " + std::to_string(h.payload_bytes) + " bytes, expected " +
                             std::to_string(h.pixelBytes())};
            }
            break;
        case FrameEncoding::Dmabuf:
            if (h.payload_bytes != 48 || h.slot >= 16) {
                return Error{"frame header: dma-buf frame with a payload of " + std::to_string(h.payload_bytes) +
                             " bytes (expected 48) or buffer " + std::to_string(h.slot) + " (0..15)"};
            }
            break;
        case FrameEncoding::Zlib:
            // zlib's worst case expansion is tiny; anything beyond that is not a zlib of this frame.
            if (h.payload_bytes == 0 || h.payload_bytes > h.pixelBytes() + h.pixelBytes() / 1000 + 64) {
                return Error{"frame header: zlib payload of " + std::to_string(h.payload_bytes) + " bytes"};
            }
            break;
    }
    return h;
}

// Hand-written (RFC 3629, table 3-7 of the Unicode standard): the build's libraries offer UTF-8
// checks only as exceptions (nlohmann's strict dump) or as whole text engines (ICU, glib).
Status validateTextPayload(FrameKind kind, const std::uint8_t* d, std::size_t size) {
    const char* what = kind == FrameKind::Status ? "status" : "error message";
    const std::uint32_t limit = kind == FrameKind::Status ? kMaxStatusPayloadBytes : kMaxErrorPayloadBytes;
    if (size > limit) {
        return Error{std::string(what) + ": " + std::to_string(size) + " bytes (limit " + std::to_string(limit) + ")"};
    }
    std::size_t i = 0;
    while (i < size) {
        const std::uint8_t b = d[i];
        std::size_t len = 0;
        std::uint8_t lo = 0x80;  // allowed range of the second byte
        std::uint8_t hi = 0xBF;
        if (b < 0x80) {
            ++i;
            continue;
        } else if (b >= 0xC2 && b <= 0xDF) {
            len = 2;
        } else if (b >= 0xE0 && b <= 0xEF) {
            len = 3;
            lo = b == 0xE0 ? 0xA0 : 0x80;  // no overlong forms
            hi = b == 0xED ? 0x9F : 0xBF;  // no UTF-16 surrogates
        } else if (b >= 0xF0 && b <= 0xF4) {
            len = 4;
            lo = b == 0xF0 ? 0x90 : 0x80;  // no overlong forms
            hi = b == 0xF4 ? 0x8F : 0xBF;  // nothing above U+10FFFF
        }
        bool ok = len != 0 && i + len <= size && d[i + 1] >= lo && d[i + 1] <= hi;
        for (std::size_t k = 2; ok && k < len; ++k) {
            ok = d[i + k] >= 0x80 && d[i + k] <= 0xBF;
        }
        if (!ok) {
            char byte[8];
            std::snprintf(byte, sizeof(byte), "0x%02x", static_cast<unsigned>(b));
            return Error{std::string(what) + ": not UTF-8 (byte " + byte + " at offset " + std::to_string(i) + ")"};
        }
        i += len;
    }
    return {};
}

}  // namespace navmap::ipc
