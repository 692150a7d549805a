// SPDX-License-Identifier: Apache-2.0
#pragma once
// DmabufFrames: one ring entry's dma-buf frames (docs/frame-protocol.md "dma-buf frames"): the
// newest frame the render thread published into an exported buffer, a duplicate of each buffer's
// fd (per allocation), and which buffers clients still hold. The render thread publishes and asks
// which buffers it must not write (busy()); the server thread takes the newest frame for a client
// (marking its buffer held until the client's ack) and releases it. One mutex guards all of it and
// is never held across I/O. Private to ipc/stream.

#include <array>
#include <cstdint>
#include <memory>
#include <mutex>
#include <optional>
#include <vector>

#include "navmap/ipc/client/dmabuf_block.h"
#include "navmap/ipc/client/frame_header.h"
#include "navmap/ipc/net/unique_fd.h"
#include "navmap/ipc/stream/frame_server.h"

namespace navmap::ipc::stream_detail {

class DmabufFrames {
public:
    /// What a client gets for the newest frame: its header and block (flags and fds set for this
    /// client), with the fds to attach (duplicates the caller sends and closes).
    struct Taken {
        std::uint64_t sequence = 0;
        FrameHeader header;
        DmabufBlock block;
        std::shared_ptr<const std::vector<std::uint8_t>> meta;
        int buffer = -1;
        net::UniqueFd buffer_fd;  ///< set when the client does not have this allocation yet
        net::UniqueFd fence_fd;
    };
    /// The allocations of each buffer a client has received (0: none).
    using Known = std::array<std::uint64_t, kDmabufMaxBuffers>;

    ~DmabufFrames();

    /// Render thread: `buffer`'s frame is the newest. Duplicates the buffer's fd when its
    /// allocation is new, takes `buffer.fence_fd`. False (nothing kept, the fence closed) for a
    /// buffer index out of range or an fd that cannot be duplicated.
    bool publish(const FrameView& info, const DmabufBuffer& buffer);
    /// Render thread: the buffers it must not write: held by a client, or the newest (a client
    /// may still be sent it).
    std::uint32_t busy() const;
    /// Server thread: the newest frame when newer than `after`; its buffer is held (once per
    /// take) until release(). `known` is updated with the allocation sent.
    std::optional<Taken> take(std::uint64_t after, Known& known);
    /// Server thread: a client is done with `buffer` (its ack, or it is gone).
    void release(int buffer);
    std::uint64_t latestSequence() const;

private:
    struct Buffer {
        net::UniqueFd fd;  // our duplicate of the renderer's fd
        std::uint64_t generation = 0;
        int held = 0;  // clients holding it
    };
    mutable std::mutex m_mutex;
    std::array<Buffer, kDmabufMaxBuffers> m_buffers;
    std::uint64_t m_sequence = 0;  // the newest frame's; 0: none yet
    FrameHeader m_header;
    DmabufBlock m_block;
    int m_buffer = -1;
    net::UniqueFd m_fence;
    std::shared_ptr<const std::vector<std::uint8_t>> m_meta;
};

}  // namespace navmap::ipc::stream_detail
