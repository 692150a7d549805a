// SPDX-License-Identifier: Apache-2.0
#pragma once
// The no-op backend: the Renderer API without any GL, for tests of code outside render/.

#include <map>

#include "navmap/render/renderer.h"
#include "readback_queue.h"

namespace navmap::render::noop {

class NoopRenderer final : public Renderer {
public:
    explicit NoopRenderer(const RendererOptions& options);

    [[nodiscard]] const DeviceInfo& device() const override { return m_device; }
    TargetHandle addTarget(int width, int height) override;
    bool removeTarget(TargetHandle target) override;
    [[nodiscard]] std::size_t targetCount() const override { return m_targets.size(); }
    [[nodiscard]] int width(TargetHandle target) const override { return view(target).width; }
    [[nodiscard]] int height(TargetHandle target) const override { return view(target).height; }
    void resize(TargetHandle target, int width, int height) override;
    void setTerrain(const HeightfieldMesh& mesh) override { m_terrain_vertices = mesh.vertices.size(); }
    void setTerrainStyle(const TerrainStyle& style) override { m_style = style; }
    void render(TargetHandle target, const Camera& camera) override;
    void setMapStyle(const MapStyle& style) override { m_style.sky_color = style.sky_color; }
    void renderMap(TargetHandle target, const MapFrame& frame) override;
    [[nodiscard]] const MapFrameStats& mapStats() const override { return m_stats; }
    void finish() override {}
    Image readSync(TargetHandle target) override;
    std::optional<Frame> readAsync(TargetHandle target, std::uint64_t sequence) override;
    std::vector<Frame> drainReadbacks(TargetHandle target) override;
    std::vector<Frame> collectReadbacks(TargetHandle target) override { return drainReadbacks(target); }
    using Renderer::collectReadbacks;
    using Renderer::drainReadbacks;
    using Renderer::height;
    using Renderer::readAsync;
    using Renderer::readSync;
    using Renderer::render;
    using Renderer::renderMap;
    using Renderer::resize;
    using Renderer::width;

    [[nodiscard]] std::size_t framesRendered() const { return m_frames; }

private:
    struct View {
        int width = 0;
        int height = 0;
        ReadbackQueue<std::uint64_t> pending;  // sequences of the readbacks in flight
    };
    /// `target`'s state; throws RenderError for a handle that names no target.
    View& view(TargetHandle target);
    const View& view(TargetHandle target) const;
    Image blank(const View& v) const;

    DeviceInfo m_device;
    std::map<int, View> m_targets;
    int m_next_id = 0;
    int m_ring;
    std::size_t m_terrain_vertices = 0;
    std::size_t m_frames = 0;
    TerrainStyle m_style;
    MapFrameStats m_stats;
};

}  // namespace navmap::render::noop
