// SPDX-License-Identifier: Apache-2.0
#include "navmap/ipc/client/dmabuf_block.h"

#include <cstring>
#include <string>

#include "navmap/ipc/client/frame_header.h"

namespace navmap::ipc {

namespace {

constexpr std::uint8_t kMagic[4] = {'N', 'M', 'D', 'B'};

// Little-endian, as the frame header (docs/frame-protocol.md "Frame header").
template <typename T>
void put(std::uint8_t* o, std::size_t at, T v) {
    for (std::size_t i = 0; i < sizeof(T); ++i) o[at + i] = static_cast<std::uint8_t>(v >> (8 * i));
}

template <typename T>
T get(const std::uint8_t* d, std::size_t at) {
    T v = 0;
    for (std::size_t i = 0; i < sizeof(T); ++i) v |= static_cast<T>(static_cast<T>(d[at + i]) << (8 * i));
    return v;
}

}  // namespace

std::array<std::uint8_t, kDmabufBlockBytes> encodeDmabufBlock(const DmabufBlock& b) noexcept {
    std::array<std::uint8_t, kDmabufBlockBytes> o{};
    std::memcpy(o.data(), kMagic, 4);
    put<std::uint16_t>(o.data(), 4, kDmabufBlockVersion);
    put<std::uint16_t>(o.data(), 6, b.flags);
    put<std::uint32_t>(o.data(), 8, b.fourcc);
    put<std::uint32_t>(o.data(), 12, b.planes);
    put<std::uint32_t>(o.data(), 16, static_cast<std::uint32_t>(b.modifier >> 32));
    put<std::uint32_t>(o.data(), 20, static_cast<std::uint32_t>(b.modifier));
    put<std::uint32_t>(o.data(), 24, b.stride);
    put<std::uint32_t>(o.data(), 28, b.offset);
    put<std::uint32_t>(o.data(), 32, b.width);
    put<std::uint32_t>(o.data(), 36, b.height);
    return o;
}

Result<DmabufBlock> decodeDmabufBlock(const std::uint8_t* d, std::size_t size) {
    if (size != kDmabufBlockBytes) {
        return Error{"dma-buf block: " + std::to_string(size) + " bytes, expected " +
                     std::to_string(kDmabufBlockBytes)};
    }
    if (std::memcmp(d, kMagic, 4) != 0) {
        return Error{"dma-buf block: bad magic (expected \"NMDB\")"};
    }
    if (const auto v = get<std::uint16_t>(d, 4); v != kDmabufBlockVersion) {
        return Error{"dma-buf block: version " + std::to_string(v) + " (this client reads version 1)"};
    }
    DmabufBlock b;
    b.flags = get<std::uint16_t>(d, 6);
    if ((b.flags & ~(kDmabufBufferFd | kDmabufFenceFd)) != 0) {
        return Error{"dma-buf block: unknown flags 0x" + std::to_string(b.flags)};
    }
    b.fourcc = get<std::uint32_t>(d, 8);
    b.planes = get<std::uint32_t>(d, 12);
    if (b.planes != 1) {
        return Error{"dma-buf block: " + std::to_string(b.planes) + " planes (version 1 has one)"};
    }
    b.modifier = (std::uint64_t{get<std::uint32_t>(d, 16)} << 32) | get<std::uint32_t>(d, 20);
    b.stride = get<std::uint32_t>(d, 24);
    b.offset = get<std::uint32_t>(d, 28);
    b.width = get<std::uint32_t>(d, 32);
    b.height = get<std::uint32_t>(d, 36);
    if (b.width == 0 || b.height == 0 || b.width > kMaxFrameDimension || b.height > kMaxFrameDimension) {
        return Error{"dma-buf block: bad size " + std::to_string(b.width) + "x" + std::to_string(b.height)};
    }
    if (b.stride < b.width * 4U || b.stride > 4 * kMaxFrameDimension + 4096) {
        return Error{"dma-buf block: stride " + std::to_string(b.stride) + " for width " + std::to_string(b.width)};
    }
    if (get<std::uint64_t>(d, 40) != 0) {
        return Error{"dma-buf block: reserved bytes 40..47 not 0"};
    }
    return b;
}

}  // namespace navmap::ipc
