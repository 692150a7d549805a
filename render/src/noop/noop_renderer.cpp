#include "noop_renderer.h"

#include <algorithm>

namespace navmap::render::noop {

NoopRenderer::NoopRenderer(const RendererOptions& options)
    : m_width(options.width), m_height(options.height), m_ring(std::max(1, options.readback_ring)) {
    m_device.backend = "noop";
    m_device.platform = "none";
    m_device.renderer = "no-op";
}

void NoopRenderer::resize(int width, int height) {
    m_pending.clear();
    m_width = width;
    m_height = height;
}

void NoopRenderer::render(const Camera&) { ++m_frames; }

void NoopRenderer::renderMap(const MapFrame& frame) {
    ++m_frames;
    m_stats = {};
    m_stats.tiles_drawn = frame.tiles.size();
}

Image NoopRenderer::blank() const {
    Image image(m_width, m_height);
    const auto to8 = [](float v) { return static_cast<std::uint8_t>(std::clamp(v, 0.0f, 1.0f) * 255.0f + 0.5f); };
    for (std::size_t i = 0; i < image.rgba.size(); i += 4) {
        image.rgba[i] = to8(m_style.sky_color.r);
        image.rgba[i + 1] = to8(m_style.sky_color.g);
        image.rgba[i + 2] = to8(m_style.sky_color.b);
        image.rgba[i + 3] = 255;
    }
    return image;
}

Image NoopRenderer::readSync() { return blank(); }

std::optional<Frame> NoopRenderer::readAsync(std::uint64_t sequence) {
    std::optional<Frame> oldest;
    if (m_pending.size() == static_cast<std::size_t>(m_ring)) {
        oldest = Frame{m_pending.front(), blank()};
        m_pending.pop_front();
    }
    m_pending.push_back(sequence);
    return oldest;
}

std::vector<Frame> NoopRenderer::drainReadbacks() {
    std::vector<Frame> frames;
    for (auto seq : m_pending) frames.push_back(Frame{seq, blank()});
    m_pending.clear();
    return frames;
}

}  // namespace navmap::render::noop
