// SPDX-License-Identifier: Apache-2.0
#pragma once
// Frame readback: synchronous glReadPixels, or a ring of pixel-pack buffers with fences so the
// next frame renders while the last one is copied out. Private to render/.

#include <GLES3/gl3.h>

#include <cstdint>
#include <deque>
#include <optional>
#include <vector>

#include "navmap/render/renderer.h"
#include "readback_queue.h"

namespace navmap::render::gl {

/// Reads the currently bound GL_READ_FRAMEBUFFER into a top-down RGBA image.
Image readPixelsSync(int width, int height);

/// Readback of one target's frames from the bound GL_READ_FRAMEBUFFER. With two or more slots
/// each frame is copied into a pixel-pack buffer of its own with a fence (asynchronous where the
/// driver copies on the GPU). With one slot there is no pixel-pack buffer: submit() reads the
/// frame straight into an image once its rendering is done and collectReady() (or drain()) hands
/// it out. On software rasterizers that is what the pixel-pack path amounts to anyway (Mesa's
/// llvmpipe waits for the frame's rasterization in glReadPixels either way), minus a buffer of
/// width x height x 4 bytes and one copy.
class ReadbackRing {
public:
    ReadbackRing(int width, int height, int slots);
    ~ReadbackRing();
    ReadbackRing(const ReadbackRing&) = delete;
    ReadbackRing& operator=(const ReadbackRing&) = delete;

    /// Queues a copy of the bound read framebuffer; returns the oldest frame if the ring was full.
    /// One slot: reads the frame now; it is returned by the next collectReady() or drain().
    std::optional<Frame> submit(std::uint64_t sequence);
    /// Completes every pending copy, oldest first.
    std::vector<Frame> drain();
    /// Completes the pending copies whose fence has signalled, oldest first, without waiting.
    std::vector<Frame> collectReady();

private:
    struct Slot {
        GLuint pbo = 0;
        GLsync fence = nullptr;
        std::uint64_t sequence = 0;
    };
    /// Queues the copy of the bound read framebuffer into the next slot; returns its index.
    std::size_t startCopy(std::uint64_t sequence);
    Frame complete(Slot& slot);

    int m_width;
    int m_height;
    bool m_direct = false;  // one slot: no pixel-pack buffer, submit() reads the frame
    std::vector<Slot> m_slots;
    ReadbackQueue<std::size_t> m_pending;  // indices into m_slots
    std::size_t m_next = 0;
    std::deque<Frame> m_read;  // one slot: read by submit(), not handed out yet
};

}  // namespace navmap::render::gl
