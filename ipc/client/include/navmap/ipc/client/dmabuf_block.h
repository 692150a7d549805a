// SPDX-License-Identifier: Apache-2.0
#pragma once
// The 48-byte block of a dma-buf frame (docs/frame-protocol.md "dma-buf frames", version 1): it
// follows the frame header (encoding Dmabuf) and its metadata block, and says how to import the
// buffer whose fd came with it or earlier (SCM_RIGHTS). Encoding and strict decoding; no I/O.

#include <array>
#include <cstddef>
#include <cstdint>

#include "navmap/ipc/net/client_api.h"
#include "navmap/ipc/net/result.h"

namespace navmap::ipc {

inline constexpr std::size_t kDmabufBlockBytes = 48;
inline constexpr std::uint16_t kDmabufBlockVersion = 1;
/// Buffer indices a server may use: the header's `slot`, 0..kDmabufMaxBuffers-1.
inline constexpr int kDmabufMaxBuffers = 16;

/// Block flags (bytes 6..7).
enum DmabufBlockFlag : std::uint16_t {
    kDmabufBufferFd = 1U << 0,  ///< the buffer's fd is attached: new, or made anew (replaces the old one)
    kDmabufFenceFd = 1U << 1,   ///< a sync fence fd is attached (after the buffer's fd, if any)
};

struct DmabufBlock {
    std::uint16_t flags = 0;
    std::uint32_t fourcc = 0;    ///< DRM fourcc ('AB24': DRM_FORMAT_ABGR8888, RGBA8 bytes)
    std::uint32_t planes = 1;    ///< version 1: one plane
    std::uint64_t modifier = 0;  ///< DRM format modifier (0: linear)
    std::uint32_t stride = 0;    ///< bytes per row of plane 0
    std::uint32_t offset = 0;    ///< plane 0's offset in the buffer
    std::uint32_t width = 0;
    std::uint32_t height = 0;
};

/// The 48-byte wire form.
NAVMAP_CLIENT_API std::array<std::uint8_t, kDmabufBlockBytes> encodeDmabufBlock(const DmabufBlock& block) noexcept;

/// Parses and checks a block: the magic, version 1, only known flags, one plane, a size within
/// kMaxFrameDimension and a stride of at least width x 4, reserved bytes 0. The error names the
/// field ("dma-buf block: 2 planes (version 1 has one)").
NAVMAP_CLIENT_API Result<DmabufBlock> decodeDmabufBlock(const std::uint8_t* data, std::size_t size);

}  // namespace navmap::ipc
