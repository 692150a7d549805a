// SPDX-License-Identifier: Apache-2.0
#pragma once
// The no-op backend: the Renderer API without any GL, for tests of code outside render/.

#include <deque>
#include <map>

#include "navmap/render/renderer.h"

namespace navmap::render::noop {

class NoopRenderer final : public Renderer {
public:
    explicit NoopRenderer(const RendererOptions& options);

    [[nodiscard]] const DeviceInfo& device() const override { return m_device; }
    [[nodiscard]] int width() const override { return current().width; }
    [[nodiscard]] int height() const override { return current().height; }
    int addTarget(int width, int height) override;
    void useTarget(int id) override;
    bool removeTarget(int id) override;
    [[nodiscard]] int currentTarget() const override { return m_current; }
    [[nodiscard]] std::size_t targetCount() const override { return m_targets.size(); }
    void resize(int width, int height) override;
    void setTerrain(const HeightfieldMesh& mesh) override { m_terrain_vertices = mesh.vertices.size(); }
    void setTerrainStyle(const TerrainStyle& style) override { m_style = style; }
    void render(const Camera& camera) override;
    void setMapStyle(const MapStyle& style) override { m_style.sky_color = style.sky_color; }
    void renderMap(const MapFrame& frame) override;
    [[nodiscard]] const MapFrameStats& mapStats() const override { return m_stats; }
    void finish() override {}
    Image readSync() override;
    std::optional<Frame> readAsync(std::uint64_t sequence) override;
    std::vector<Frame> drainReadbacks() override;
    std::vector<Frame> collectReadbacks() override { return drainReadbacks(); }

    [[nodiscard]] std::size_t framesRendered() const { return m_frames; }

private:
    struct View {
        int width = 0;
        int height = 0;
        std::deque<std::uint64_t> pending;
    };
    View& current() { return m_targets.at(m_current); }
    const View& current() const { return m_targets.at(m_current); }
    Image blank() const;

    DeviceInfo m_device;
    std::map<int, View> m_targets;
    int m_current = 0;
    int m_next_id = 0;
    int m_ring;
    std::size_t m_terrain_vertices = 0;
    std::size_t m_frames = 0;
    TerrainStyle m_style;
    MapFrameStats m_stats;
};

}  // namespace navmap::render::noop
