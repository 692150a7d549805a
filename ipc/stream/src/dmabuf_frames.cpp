// SPDX-License-Identifier: Apache-2.0
#include "dmabuf_frames.h"

#include <fcntl.h>
#include <unistd.h>

#include <chrono>

namespace navmap::ipc::stream_detail {

namespace {

std::int64_t realtimeNowNs() {
    return std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::system_clock::now().time_since_epoch())
        .count();
}

int dupCloexec(int fd) { return fd >= 0 ? ::fcntl(fd, F_DUPFD_CLOEXEC, 0) : -1; }

}  // namespace

DmabufFrames::~DmabufFrames() = default;

bool DmabufFrames::publish(const FrameView& info, const DmabufBuffer& buffer) {
    net::UniqueFd fence(buffer.fence_fd);  // ours from here on, whatever happens
    if (buffer.index < 0 || buffer.index >= kDmabufMaxBuffers || buffer.fd < 0) {
        return false;
    }
    FrameHeader h;
    h.kind = FrameKind::Frame;
    h.encoding = FrameEncoding::Dmabuf;
    h.format = PixelFormat::Rgba8;
    h.render_time_ns = info.render_time_ns != 0 ? info.render_time_ns : realtimeNowNs();
    h.source_time_ns = info.source_time_ns;
    h.width = buffer.layout.width;
    h.height = buffer.layout.height;
    h.stride = buffer.layout.width * 4;  // the pixels' row as a copy would have it; the block has the buffer's
    h.payload_bytes = static_cast<std::uint32_t>(kDmabufBlockBytes);
    h.slot = static_cast<std::uint32_t>(buffer.index);
    h.validity = info.validity;
    DmabufBlock block = buffer.layout;
    block.flags = 0;
    block.planes = 1;

    std::lock_guard lock(m_mutex);
    Buffer& b = m_buffers[static_cast<std::size_t>(buffer.index)];
    if (b.generation != buffer.generation || !b.fd.valid()) {
        net::UniqueFd copy(dupCloexec(buffer.fd));
        if (!copy.valid()) {
            return false;
        }
        b.fd = std::move(copy);
        b.generation = buffer.generation;
    }
    h.sequence = ++m_sequence;
    m_header = h;
    m_block = block;
    m_buffer = buffer.index;
    m_fence = std::move(fence);
    m_meta = info.meta;
    return true;
}

std::uint32_t DmabufFrames::busy() const {
    std::lock_guard lock(m_mutex);
    std::uint32_t mask = 0;
    for (int i = 0; i < kDmabufMaxBuffers; ++i) {
        if (m_buffers[static_cast<std::size_t>(i)].held > 0) mask |= 1U << i;
    }
    if (m_buffer >= 0) mask |= 1U << m_buffer;
    return mask;
}

std::optional<DmabufFrames::Taken> DmabufFrames::take(std::uint64_t after, Known& known) {
    std::lock_guard lock(m_mutex);
    if (m_sequence == 0 || m_sequence <= after || m_buffer < 0) {
        return std::nullopt;
    }
    Buffer& b = m_buffers[static_cast<std::size_t>(m_buffer)];
    Taken t;
    t.sequence = m_sequence;
    t.header = m_header;
    t.block = m_block;
    t.meta = m_meta;
    t.buffer = m_buffer;
    if (known[static_cast<std::size_t>(m_buffer)] != b.generation) {
        t.buffer_fd.reset(dupCloexec(b.fd.get()));
        if (!t.buffer_fd.valid()) {
            return std::nullopt;
        }
        t.block.flags |= kDmabufBufferFd;
        known[static_cast<std::size_t>(m_buffer)] = b.generation;
    }
    if (m_fence.valid()) {
        t.fence_fd.reset(dupCloexec(m_fence.get()));
        if (t.fence_fd.valid()) t.block.flags |= kDmabufFenceFd;
    }
    ++b.held;
    return t;
}

void DmabufFrames::release(int buffer) {
    if (buffer < 0 || buffer >= kDmabufMaxBuffers) return;
    std::lock_guard lock(m_mutex);
    Buffer& b = m_buffers[static_cast<std::size_t>(buffer)];
    if (b.held > 0) --b.held;
}

std::uint64_t DmabufFrames::latestSequence() const {
    std::lock_guard lock(m_mutex);
    return m_sequence;
}

}  // namespace navmap::ipc::stream_detail
