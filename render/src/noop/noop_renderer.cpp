// SPDX-License-Identifier: Apache-2.0
#include "noop_renderer.h"

#include <algorithm>
#include <cmath>
#include <string>

namespace navmap::render::noop {

NoopRenderer::NoopRenderer(const RendererOptions& options) : m_ring(std::max(1, options.readback_ring)) {
    m_device.backend = "noop";
    m_device.platform = "none";
    m_device.renderer = "no-op";
    m_device.dmabuf.reason = "the no-op renderer draws into no GPU buffers";
    addTarget(options.width, options.height);  // the primary target, id 0
}

TargetHandle NoopRenderer::addTarget(int width, int height) {
    if (width <= 0 || height <= 0) {
        throw RenderError("renderer: invalid size " + std::to_string(width) + "x" + std::to_string(height));
    }
    const int id = m_next_id++;
    m_targets.emplace(id, View{width, height, ReadbackQueue<std::uint64_t>(static_cast<std::size_t>(m_ring))});
    return handle(id);
}

bool NoopRenderer::removeTarget(TargetHandle target) {
    return target != primaryTarget() && m_targets.erase(target.id()) > 0;
}

NoopRenderer::View& NoopRenderer::view(TargetHandle target) {
    const auto it = m_targets.find(target.id());
    if (it == m_targets.end()) throw RenderError("renderer: no target " + std::to_string(target.id()));
    return it->second;
}

const NoopRenderer::View& NoopRenderer::view(TargetHandle target) const {
    return const_cast<NoopRenderer*>(this)->view(target);
}

void NoopRenderer::resize(TargetHandle target, int width, int height) {
    if (width <= 0 || height <= 0) {
        throw RenderError("renderer: invalid size " + std::to_string(width) + "x" + std::to_string(height));
    }
    View& v = view(target);
    v.pending.clear();
    v.width = width;
    v.height = height;
}

void NoopRenderer::render(TargetHandle target, const Camera&) {
    (void)view(target);
    ++m_frames;
}

void NoopRenderer::renderMap(TargetHandle target, const MapFrame& frame) {
    (void)view(target);
    ++m_frames;
    m_stats = {};
    m_stats.tiles_drawn = frame.tiles.size();
}

Image NoopRenderer::blank(const View& v) const {
    Image image(v.width, v.height);
    const auto to8 = [](float c) { return static_cast<std::uint8_t>(std::lround(std::clamp(c, 0.0f, 1.0f) * 255.0f)); };
    for (std::size_t i = 0; i < image.rgba.size(); i += 4) {
        image.rgba[i] = to8(m_style.sky_color.r);
        image.rgba[i + 1] = to8(m_style.sky_color.g);
        image.rgba[i + 2] = to8(m_style.sky_color.b);
        image.rgba[i + 3] = 255;
    }
    return image;
}

Image NoopRenderer::readSync(TargetHandle target) { return blank(view(target)); }

std::optional<Frame> NoopRenderer::readAsync(TargetHandle target, std::uint64_t sequence) {
    View& v = view(target);
    return v.pending.submit([&](std::uint64_t seq) { return Frame{seq, blank(v)}; }, [sequence] { return sequence; });
}

std::vector<Frame> NoopRenderer::drainReadbacks(TargetHandle target) {
    View& v = view(target);
    return v.pending.drain([&](std::uint64_t seq) { return Frame{seq, blank(v)}; });
}

}  // namespace navmap::render::noop
