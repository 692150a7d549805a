// SPDX-License-Identifier: Apache-2.0
// StreamClient's dma-buf frames (docs/frame-protocol.md "dma-buf frames"): the block after each
// header, the buffer and fence fds that come with it, and the ways a frame is handed out: the
// buffer itself (nextDmabuf), its read-only mapping (nextHeld) or a copy out of it (next).
#include <linux/dma-buf.h>
#include <poll.h>
#include <sys/ioctl.h>
#include <sys/mman.h>
#include <unistd.h>

#include <array>
#include <cerrno>
#include <cstring>

#include "navmap/ipc/client/stream_client.h"
#include "navmap/ipc/client/stream_socket.h"

namespace navmap::ipc {

namespace stream_detail {

void dmaBufSync(int fd, bool start) noexcept {
    dma_buf_sync sync{static_cast<__u64>((start ? DMA_BUF_SYNC_START : DMA_BUF_SYNC_END) | DMA_BUF_SYNC_READ)};
    while (::ioctl(fd, DMA_BUF_IOCTL_SYNC, &sync) != 0 && errno == EINTR) {}
}

}  // namespace stream_detail

using net::sysError;
using net::UniqueFd;
using Clock = std::chrono::steady_clock;

Result<bool> StreamClient::nextDmabuf(DmabufFrameRef& out, std::chrono::milliseconds timeout) {
    if (m_payload != StreamPayload::Dmabuf) {
        return Error{m_peer + ": nextDmabuf() needs a stream of payload dmabuf (this one is " +
                     streamPayloadName(m_payload) + ")"};
    }
    return receive({nullptr, nullptr, &out}, timeout);
}

Result<int> StreamClient::takeFd(const FrameHeader& h, const char* what) {
    if (m_fds.empty()) {
        return Error{m_peer + ": frame " + std::to_string(h.sequence) + ": the " + what +
                     " its dma-buf block announces did not come with it"};
    }
    const int f = m_fds.front();
    m_fds.erase(m_fds.begin());
    return f;
}

Status StreamClient::takeDmabuf(const FrameHeader& h, Out out, Clock::time_point deadline) {
    std::array<std::uint8_t, kDmabufBlockBytes> raw{};
    bool timed_out = false;
    if (auto s = readExact(raw.data(), raw.size(), deadline, &timed_out); !s) {
        return s;
    }
    const std::string frame = m_peer + ": frame " + std::to_string(h.sequence) + ": ";
    auto block = decodeDmabufBlock(raw.data(), raw.size());
    if (!block) {
        return Error{frame + block.error().message};
    }
    const DmabufBlock& b = block.value();
    if (b.width != h.width || b.height != h.height) {
        return Error{frame + "dma-buf block of " + std::to_string(b.width) + "x" + std::to_string(b.height) +
                     " for a frame of " + std::to_string(h.width) + "x" + std::to_string(h.height)};
    }
    int& buffer = m_dmabufs[h.slot];
    const bool new_buffer = (b.flags & kDmabufBufferFd) != 0;
    if (new_buffer) {
        auto f = takeFd(h, "buffer fd");
        if (!f) return Error{f.error().message};
        unmapDmabuf(static_cast<int>(h.slot));
        if (buffer >= 0) ::close(buffer);
        buffer = f.value();
        ++m_stats.dmabuf_fds;
    }
    if ((b.flags & kDmabufFenceFd) != 0) {
        auto f = takeFd(h, "fence fd");
        if (!f) return Error{f.error().message};
        const UniqueFd fence(f.value());
        // The frame is in the buffer once its fence signals (readable).
        pollfd p{fence.get(), POLLIN, 0};
        if (::poll(&p, 1, stream_detail::msLeft(deadline)) != 1) {
            return Error{frame + "its fence did not signal in time"};
        }
    }
    for (const int extra : m_fds) ::close(extra);  // descriptors no block announced: not ours to keep
    m_fds.clear();
    if (buffer < 0) {
        return Error{frame + "buffer " + std::to_string(h.slot) + " before its fd came"};
    }
    if (out.dmabuf != nullptr) {
        m_held = static_cast<int>(h.slot);
        out.dmabuf->block = b;
        out.dmabuf->fd = buffer;
        out.dmabuf->new_buffer = new_buffer;
        return {};
    }
    if (out.held != nullptr) {
        // In place: the pixels in a read-only mapping of the buffer, until release().
        auto at = mapDmabuf(static_cast<int>(h.slot), b);
        if (!at) return Error{at.error().message};
        stream_detail::dmaBufSync(buffer, true);
        m_held = static_cast<int>(h.slot);
        out.held->pixels = at.value();
        out.held->dmabuf_fd = buffer;
        out.held->dmabuf = b;
        return {};
    }
    // A copy: read the pixels through a mapping of the buffer, then give it back at once.
    const std::size_t bytes = std::size_t{b.stride} * b.height + b.offset;
    void* map = ::mmap(nullptr, bytes, PROT_READ, MAP_SHARED, buffer, 0);
    if (map == MAP_FAILED) {
        return Error{sysError("mmap", m_peer + " dma-buf " + std::to_string(h.slot))};
    }
    stream_detail::dmaBufSync(buffer, true);
    out.copy->pixels.resize(h.pixelBytes());
    for (std::uint32_t y = 0; y < h.height; ++y) {
        std::memcpy(out.copy->pixels.data() + std::size_t{y} * h.stride,
                    static_cast<const std::uint8_t*>(map) + b.offset + std::size_t{y} * b.stride, h.stride);
    }
    stream_detail::dmaBufSync(buffer, false);
    ::munmap(map, bytes);
    ++m_stats.cpu_copies;
    return sendAck();
}

Result<const std::uint8_t*> StreamClient::mapDmabuf(int index, const DmabufBlock& block) {
    Mapping& m = m_dmabuf_maps[static_cast<std::size_t>(index)];
    const std::size_t bytes = std::size_t{block.stride} * block.height + block.offset;
    if (m.at != nullptr && m.bytes != bytes) unmapDmabuf(index);
    if (m.at == nullptr) {
        void* at = ::mmap(nullptr, bytes, PROT_READ, MAP_SHARED, m_dmabufs[static_cast<std::size_t>(index)], 0);
        if (at == MAP_FAILED) {
            return Error{sysError("mmap", m_peer + " dma-buf " + std::to_string(index))};
        }
        m = {at, bytes};
    }
    return static_cast<const std::uint8_t*>(m.at) + block.offset;
}

void StreamClient::unmapDmabuf(int index) {
    Mapping& m = m_dmabuf_maps[static_cast<std::size_t>(index)];
    if (m.at != nullptr) ::munmap(m.at, m.bytes);
    m = {};
}

}  // namespace navmap::ipc
