#pragma once
// The no-op backend: the Renderer API without any GL, for tests of code outside render/.

#include <deque>

#include "navmap/render/renderer.h"

namespace navmap::render::noop {

class NoopRenderer final : public Renderer {
public:
    explicit NoopRenderer(const RendererOptions& options);

    [[nodiscard]] const DeviceInfo& device() const override { return m_device; }
    [[nodiscard]] int width() const override { return m_width; }
    [[nodiscard]] int height() const override { return m_height; }
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
    Image blank() const;

    DeviceInfo m_device;
    int m_width;
    int m_height;
    int m_ring;
    std::size_t m_terrain_vertices = 0;
    std::size_t m_frames = 0;
    TerrainStyle m_style;
    MapFrameStats m_stats;
    std::deque<std::uint64_t> m_pending;
};

}  // namespace navmap::render::noop
