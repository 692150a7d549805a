// SPDX-License-Identifier: Apache-2.0
#pragma once
// The OpenGL ES 3 backend of Renderer. Private to render/.

#include <map>
#include <memory>
#include <optional>

#include "dmabuf_export.h"
#include "egl_context.h"
#include "gl_features.h"
#include "map_renderer.h"
#include "program_binary_cache.h"
#include "readback.h"
#include "render_target.h"
#include "terrain_layer.h"

namespace navmap::render::gl {

class GlRenderer final : public Renderer {
public:
    explicit GlRenderer(const RendererOptions& options);
    ~GlRenderer() override;

    [[nodiscard]] const DeviceInfo& device() const override { return m_device; }

    TargetHandle addTarget(int width, int height) override;
    bool removeTarget(TargetHandle target) override;
    [[nodiscard]] std::size_t targetCount() const override { return m_targets.size(); }
    [[nodiscard]] int width(TargetHandle target) const override { return view(target).target->width(); }
    [[nodiscard]] int height(TargetHandle target) const override { return view(target).target->height(); }

    void resize(TargetHandle target, int width, int height) override;
    void setTerrain(const HeightfieldMesh& mesh) override;
    void setTerrainStyle(const TerrainStyle& style) override { m_style = style; }
    void render(TargetHandle target, const Camera& camera) override;
    void setMapStyle(const MapStyle& style) override;
    void renderMap(TargetHandle target, const MapFrame& frame) override;
    [[nodiscard]] const MapFrameStats& mapStats() const override { return m_map->stats(); }
    [[nodiscard]] ProgramCacheStats programCache() const override {
        return m_programs ? m_programs->stats() : ProgramCacheStats{};
    }
    /// The route's work in the last map frame (tests and benchmarks, beside mapStats()).
    [[nodiscard]] const RouteWork& routeWork() const { return m_map->routeWork(); }
    void finish() override;
    Image readSync(TargetHandle target) override;
    std::optional<Frame> readAsync(TargetHandle target, std::uint64_t sequence) override;
    std::vector<Frame> drainReadbacks(TargetHandle target) override;
    std::vector<Frame> collectReadbacks(TargetHandle target) override;
    std::optional<DmabufFrame> exportFrame(TargetHandle target, std::uint32_t busy,
                                           const FrameOverlay* overlay = nullptr) override;
    using Renderer::collectReadbacks;
    using Renderer::drainReadbacks;
    using Renderer::height;
    using Renderer::readAsync;
    using Renderer::readSync;
    using Renderer::render;
    using Renderer::renderMap;
    using Renderer::resize;
    using Renderer::width;

private:
    // One display's offscreen state; everything else (context, shaders, tile resources) is shared.
    struct View {
        std::unique_ptr<RenderTarget> target;
        std::unique_ptr<ReadbackRing> ring;
        std::unique_ptr<DmabufExporter::Pool> dmabuf;  // exportFrame()'s buffers, made on its first call
    };
    /// `target`'s state; throws RenderError for a handle that names no target.
    [[nodiscard]] View& view(TargetHandle target);
    [[nodiscard]] const View& view(TargetHandle target) const;
    static void checkSize(int width, int height);
    /// device().dmabuf, and the exporter when the device can export (dmabuf_probe.h).
    void probeDmabuf();
    /// The depth/stencil buffer every target shares, grown to cover width x height (the targets
    /// get the new one attached when it grows).
    GLuint sharedDepthStencil(int width, int height);
    /// At the start of each frame: when the context was lost or reset (or the test hook
    /// NAVMAP_TEST_LOSE_CONTEXT_AFTER_FRAMES drops it), recreateContext().
    void checkContext();
    /// A new context with everything the old one held: targets of the same sizes and handles,
    /// programs, terrain, the map style; tiles and atlases re-upload as frames ask for them.
    /// Frames in flight on the old context are gone.
    void recreateContext();

    RendererOptions m_options;
    EglContext m_egl;  // first member with GL state: constructed first, destroyed last
    DeviceInfo m_device;
    GlFeatures m_features;  // what the context offers beyond ES 3.0 core (docs/gles-profile.md)
    std::unique_ptr<ProgramBinaryCache> m_programs;  // RendererOptions::program_cache_dir; null: none
    /// The dma-buf export (null without GBM); declared before the targets, whose pools it
    /// allocated, so that it outlives them.
    std::unique_ptr<DmabufExporter> m_dmabuf;
    std::map<int, View> m_targets;
    GLuint m_depth_stencil = 0;  // shared by the targets: the largest width x largest height
    ScratchSize m_depth_size;
    int m_next_id = 0;
    std::unique_ptr<TerrainLayer> m_terrain;
    std::unique_ptr<MapRenderer> m_map;
    std::shared_ptr<const HeightfieldMesh> m_terrain_mesh;  // setTerrain's, uploaded again on a new context
    std::optional<MapStyle> m_map_style;                    // setMapStyle's, set again on a new context
    int m_frames = 0;                                       // render() and renderMap() calls
    int m_lose_after_frames = 0;                            // test hook: drop the context after this many (0: never)
    TerrainStyle m_style;
};

}  // namespace navmap::render::gl
