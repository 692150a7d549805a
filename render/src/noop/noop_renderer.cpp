// SPDX-License-Identifier: Apache-2.0
#include "noop_renderer.h"

#include <algorithm>
#include <string>

namespace navmap::render::noop {

NoopRenderer::NoopRenderer(const RendererOptions& options) : m_ring(std::max(1, options.readback_ring)) {
    m_device.backend = "noop";
    m_device.platform = "none";
    m_device.renderer = "no-op";
    m_current = addTarget(options.width, options.height);
}

int NoopRenderer::addTarget(int width, int height) {
    if (width <= 0 || height <= 0) {
        throw RenderError("renderer: invalid size " + std::to_string(width) + "x" + std::to_string(height));
    }
    const int id = m_next_id++;
    m_targets.emplace(id, View{width, height, {}});
    return id;
}

void NoopRenderer::useTarget(int id) {
    if (!m_targets.contains(id)) throw RenderError("renderer: no target " + std::to_string(id));
    m_current = id;
}

bool NoopRenderer::removeTarget(int id) {
    if (id == 0 || m_targets.erase(id) == 0) return false;
    if (m_current == id) m_current = 0;
    return true;
}

void NoopRenderer::resize(int width, int height) {
    if (width <= 0 || height <= 0) {
        throw RenderError("renderer: invalid size " + std::to_string(width) + "x" + std::to_string(height));
    }
    View& v = current();
    v.pending.clear();
    v.width = width;
    v.height = height;
}

void NoopRenderer::render(const Camera&) { ++m_frames; }

void NoopRenderer::renderMap(const MapFrame& frame) {
    ++m_frames;
    m_stats = {};
    m_stats.tiles_drawn = frame.tiles.size();
}

Image NoopRenderer::blank() const {
    Image image(current().width, current().height);
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
    View& v = current();
    std::optional<Frame> oldest;
    if (v.pending.size() == static_cast<std::size_t>(m_ring)) {
        oldest = Frame{v.pending.front(), blank()};
        v.pending.pop_front();
    }
    v.pending.push_back(sequence);
    return oldest;
}

std::vector<Frame> NoopRenderer::drainReadbacks() {
    std::vector<Frame> frames;
    View& v = current();
    for (auto seq : v.pending) frames.push_back(Frame{seq, blank()});
    v.pending.clear();
    return frames;
}

}  // namespace navmap::render::noop
