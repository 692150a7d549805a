// SPDX-License-Identifier: Apache-2.0
#pragma once
// ShmBufferSource: wl_shm buffers for navmap-wayland (docs/wayland.md "Buffers"). Each buffer is
// a memfd of its own, mapped once; a frame is written into a buffer the compositor does not hold
// (blitFrame(): the one copy between the ring and the screen), in the wl_shm format that needs
// no conversion where the compositor offers it (XBGR8888 for RGBA8 frames, RGB565 for RGB565),
// else XRGB8888. At most kMaxBuffers per size; buffers of an old size go when the compositor
// releases them.

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "buffer_source.h"

struct wl_shm;
struct wl_buffer;

namespace navmap::ipc::wayland {

class ShmBufferSource final : public BufferSource {
public:
    static constexpr int kMaxBuffers = 3;

    /// `formats`: the wl_shm formats the compositor announced (wl_shm.format values).
    ShmBufferSource(wl_shm* shm, std::vector<std::uint32_t> formats);
    ~ShmBufferSource() override;
    ShmBufferSource(const ShmBufferSource&) = delete;
    ShmBufferSource& operator=(const ShmBufferSource&) = delete;

    const char* name() const noexcept override { return "wl_shm"; }
    bool attach(wl_surface* surface, const DisplayFrame& frame, int width, int height) override;
    bool attachBlank(wl_surface* surface, int width, int height) override;
    Placement lastPlacement() const noexcept override { return m_placement; }
    const std::string& lastError() const noexcept override { return m_last_error; }

    /// The format frames of `stream` are written in.
    ShmFormat formatFor(PixelFormat stream) const noexcept;

    struct Buffer;  // one wl_buffer with its mapping (shm_buffer_source.cpp)

private:
    Buffer* freeBuffer(int width, int height, ShmFormat format);
    void dropStale(int width, int height, ShmFormat format);
    void attachBuffer(wl_surface* surface, Buffer& b);

    wl_shm* m_shm;
    bool m_has_xbgr8888 = false;
    bool m_has_rgb565 = false;
    std::vector<std::unique_ptr<Buffer>> m_buffers;
    Placement m_placement;
    std::string m_last_error;
};

}  // namespace navmap::ipc::wayland
