// SPDX-License-Identifier: Apache-2.0
#pragma once
// BufferSource: where navmap-wayland gets the wl_buffer that shows a frame (docs/wayland.md).
// ShmBufferSource (wl_shm, one copy from the ring, or from the mapped dma-buf, into the buffer) is
// the one there is; a zwp_linux_dmabuf source handing dma-buf frames to the compositor would be
// another implementation of this interface, chosen in navmap_wayland_main.cpp. Called on the thread that owns the
// Wayland connection; a source never commits the surface (the window does, after its configure).

#include <cstdint>
#include <string>

#include "frame_blit.h"

struct wl_surface;

namespace navmap::ipc::wayland {

/// A frame to show, as the stream client hands it out (in the mapped ring, or its own copy).
struct DisplayFrame {
    SourcePixels pixels;
    std::uint64_t sequence = 0;
};

class BufferSource {
public:
    virtual ~BufferSource() = default;
    /// "wl_shm", ...: for the log.
    virtual const char* name() const noexcept = 0;
    /// Attaches to `surface` a buffer of width x height showing `frame` (scaled to fit and
    /// centred when the sizes differ) and damages all of it; the caller commits. false: no buffer
    /// could be had (every one still held by the compositor: the frame is skipped; or an error,
    /// then lastError() says which).
    virtual bool attach(wl_surface* surface, const DisplayFrame& frame, int width, int height) = 0;
    /// The same with a black buffer: the surface before its first frame.
    virtual bool attachBlank(wl_surface* surface, int width, int height) = 0;
    /// Where the last frame attached landed in its buffer.
    virtual Placement lastPlacement() const noexcept = 0;
    /// Empty, or why the last attach failed for another reason than busy buffers.
    virtual const std::string& lastError() const noexcept = 0;
};

}  // namespace navmap::ipc::wayland
