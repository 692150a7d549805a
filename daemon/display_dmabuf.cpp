// SPDX-License-Identifier: Apache-2.0
// Display's dma-buf frames (docs/frame-protocol.md "dma-buf frames"): the frame just drawn goes to
// the profile's dma-buf clients in a buffer the renderer exported, copied there on the GPU with the
// attribution blended in; the CPU copies no pixel.
#include "display.h"

namespace navmap::daemon {

void Display::exportDmabuf(render::Renderer& renderer, ipc::FrameServer& frames, std::uint64_t seq, bool counted) {
    if (seq < m_first_complete) {  // start-up: the map under the camera is not drawn yet
        if (counted) ++m_stats.held_back;
        return;
    }
    render::FrameOverlay overlay;
    if (m_attribution) {
        if (m_attribution_pixels.rgba.empty()) {
            m_attribution_pixels = m_attribution->premultiplied();
            ++m_attribution_id;
        }
        overlay = {&m_attribution_pixels, m_attribution->x(), m_attribution->y(), m_attribution_id};
    }
    // Buffers a client still holds, and the newest one (not yet sent to every client), stay as they are.
    const auto exported =
        renderer.exportFrame(m_target, frames.dmabufBusy(m_profile.name), m_attribution ? &overlay : nullptr);
    if (!exported) {
        ++m_stats.dmabuf_busy;
        return;
    }
    ipc::FrameView info;
    info.width = exported->width;
    info.height = exported->height;
    const auto it = m_source_times.find(seq);
    const ipc::CanTime source = it != m_source_times.end() ? it->second.source : ipc::CanTime{};
    info.source_time_ns = realtimeNs(source);
    if (it != m_source_times.end()) {
        info.validity = it->second.annotation.validity;
        info.meta = it->second.annotation.meta;
    }
    ipc::DmabufBuffer buffer;
    buffer.index = exported->buffer;
    buffer.generation = exported->generation;
    buffer.fd = exported->fd;
    buffer.layout.fourcc = exported->fourcc;
    buffer.layout.modifier = exported->modifier;
    buffer.layout.stride = exported->stride;
    buffer.layout.offset = exported->offset;
    buffer.layout.width = static_cast<std::uint32_t>(exported->width);
    buffer.layout.height = static_cast<std::uint32_t>(exported->height);
    buffer.fence_fd = exported->fence_fd;  // the frame server's from here on
    if (frames.publishDmabuf(m_profile.name, info, buffer) == 0) return;
    ++m_stats.dmabuf_published;
    if (counted) countPublished(source);
}

}  // namespace navmap::daemon
