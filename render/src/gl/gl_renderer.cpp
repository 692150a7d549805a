// SPDX-License-Identifier: Apache-2.0
#include "gl_renderer.h"

#include <GLES3/gl3.h>

#include <cstdio>
#include <cstdlib>
#include <string>
#include <utility>
#include <vector>

namespace navmap::render::gl {

namespace {

std::string glString(GLenum name) {
    const auto* s = reinterpret_cast<const char*>(glGetString(name));
    return s ? s : "";
}

std::string glExtensions() {
    GLint n = 0;
    glGetIntegerv(GL_NUM_EXTENSIONS, &n);
    std::string all;
    for (GLint i = 0; i < n; ++i) {
        const auto* e = reinterpret_cast<const char*>(glGetStringi(GL_EXTENSIONS, static_cast<GLuint>(i)));
        if (e) all += std::string(all.empty() ? "" : " ") + e;
    }
    return all;
}

}  // namespace

GlRenderer::GlRenderer(const RendererOptions& options) : m_options(options), m_egl(options.platform) {
    checkSize(options.width, options.height);
    m_device.backend = "gles";
    m_device.platform = m_egl.platformUsed();
    m_device.vendor = glString(GL_VENDOR);
    m_device.renderer = glString(GL_RENDERER);
    m_device.version = glString(GL_VERSION);
    m_device.gles_major = m_egl.glesMajor();
    m_device.gles_minor = m_egl.glesMinor();
    m_device.software = isSoftwareRasterizer(m_device.renderer);
    m_device.robust_context = m_egl.robust();
    probeDmabuf();
    m_features = GlFeatures::current(m_device.gles_major, m_device.gles_minor);
    m_device.features_off = m_features.featuresOff(options.msaa_samples, m_device.software);
    if (!m_egl.detectsResets()) {
        m_device.features_off.emplace_back(
            "GPU reset detection (no EGL_EXT_create_context_robustness, or no glGetGraphicsResetStatus): a lost "
            "context is not made anew");
    }
    if (m_options.msaa_samples < 0) m_options.msaa_samples = m_device.software ? 0 : 4;
    // readback_ring 0 = auto: llvmpipe copies a frame into a pixel-pack buffer on the CPU once
    // its rasterization is done, so a buffer ring buys no overlap there and costs width x height
    // x 4 bytes per slot: one slot (direct read, ReadbackRing). GPUs copy asynchronously: two.
    if (m_options.readback_ring <= 0) m_options.readback_ring = m_device.software ? 1 : 2;
    if (!m_options.program_cache_dir.empty())
        m_programs = std::make_unique<ProgramBinaryCache>(m_options.program_cache_dir);
    const ProgramBinaryCache::Use programs(m_programs.get());  // the passes compile theirs below
    m_terrain = std::make_unique<TerrainLayer>();
    m_map = std::make_unique<MapRenderer>(m_options, m_device.software, m_features);
    addTarget(options.width, options.height);  // the primary target, id 0
    // Test hook (docs/gles-profile.md "Lost contexts"): the context is dropped as a GPU reset
    // would lose it, once, at the start of frame N + 1.
    if (const char* lose = std::getenv("NAVMAP_TEST_LOSE_CONTEXT_AFTER_FRAMES")) m_lose_after_frames = std::atoi(lose);
}

void GlRenderer::probeDmabuf() {
    DmabufProbeInput in{m_egl.displayExtensions(), glExtensions(), m_device.platform, m_device.renderer,
                        findDrmNodes()};
    m_device.dmabuf = decideDmabuf(in);
    m_dmabuf = std::make_unique<DmabufExporter>(m_egl.display(), in.drm_nodes, m_device.dmabuf, m_device.renderer,
                                                m_device.platform);
}

GlRenderer::~GlRenderer() {
    m_egl.makeCurrent();
    // GL objects go before the context (m_egl is destroyed after the members declared below it).
    m_targets.clear();
    m_dmabuf.reset();
    glDeleteRenderbuffers(1, &m_depth_stencil);
    m_terrain.reset();
    m_map.reset();
}

void GlRenderer::checkSize(int width, int height) {
    if (width <= 0 || height <= 0) {
        throw RenderError("renderer: invalid size " + std::to_string(width) + "x" + std::to_string(height));
    }
}

GLuint GlRenderer::sharedDepthStencil(int width, int height) {
    // The targets render one after another on this context and a frame's depth/stencil is
    // scratch (cleared at its start, read only within it), so one buffer serves them all:
    // 3.5 MiB less per extra 1280x720 target.
    if (!m_depth_size.grow(width, height)) return m_depth_stencil;
    const GLuint grown = makeRenderbuffer(GL_DEPTH24_STENCIL8, RenderTarget::effectiveSamples(m_options.msaa_samples),
                                          m_depth_size.width, m_depth_size.height);
    for (auto& [id, view] : m_targets) {
        if (view.target) view.target->attachDepthStencil(grown);
    }
    glDeleteRenderbuffers(1, &m_depth_stencil);
    m_depth_stencil = grown;
    return m_depth_stencil;
}

TargetHandle GlRenderer::addTarget(int width, int height) {
    checkSize(width, height);
    m_egl.makeCurrent();
    View view;
    view.target =
        std::make_unique<RenderTarget>(width, height, m_options.msaa_samples, sharedDepthStencil(width, height));
    view.ring = std::make_unique<ReadbackRing>(width, height, m_options.readback_ring);
    m_device.msaa_samples = view.target->samples();
    const int id = m_next_id++;
    m_targets.emplace(id, std::move(view));
    return handle(id);
}

GlRenderer::View& GlRenderer::view(TargetHandle target) {
    const auto it = m_targets.find(target.id());
    if (it == m_targets.end()) throw RenderError("renderer: no target " + std::to_string(target.id()));
    return it->second;
}

const GlRenderer::View& GlRenderer::view(TargetHandle target) const {
    return const_cast<GlRenderer*>(this)->view(target);
}

bool GlRenderer::removeTarget(TargetHandle target) {
    if (target == primaryTarget() || !m_targets.contains(target.id())) return false;
    m_egl.makeCurrent();
    m_targets.erase(target.id());  // pending readbacks: their fences and buffers go with the ring
    m_map->dropTarget(target.id());
    return true;
}

void GlRenderer::resize(TargetHandle target, int width, int height) {
    checkSize(width, height);
    m_egl.makeCurrent();
    View& v = view(target);
    if (v.ring) v.ring->drain();
    v.ring.reset();
    v.dmabuf.reset();  // buffers of the old size; the next export makes new ones
    v.target.reset();  // before the shared depth/stencil may grow: it re-attaches to every target
    v.target = std::make_unique<RenderTarget>(width, height, m_options.msaa_samples, sharedDepthStencil(width, height));
    v.ring = std::make_unique<ReadbackRing>(width, height, m_options.readback_ring);
    m_device.msaa_samples = v.target->samples();
}

void GlRenderer::setTerrain(const HeightfieldMesh& mesh) {
    m_egl.makeCurrent();
    const ProgramBinaryCache::Use programs(m_programs.get());
    m_terrain->upload(mesh);
    m_terrain_mesh = std::make_shared<const HeightfieldMesh>(mesh);
}

void GlRenderer::checkContext() {
    if (m_lose_after_frames > 0 && m_frames == m_lose_after_frames) {
        m_lose_after_frames = 0;
        m_egl.loseForTest();
    }
    const unsigned status = m_egl.resetStatus();
    if (status == GL_NO_ERROR) return;
    std::fprintf(stderr, "<4>navmap: GL context lost (reset status 0x%04x); making a new one\n", status);
    recreateContext();
}

void GlRenderer::recreateContext() {
    // The objects go first (their GL calls are ignored on a lost context, or with none current),
    // then the new context gets them again.
    std::vector<std::pair<int, std::pair<int, int>>> sizes;
    for (auto& [id, v] : m_targets) {
        sizes.push_back({id, {v.target->width(), v.target->height()}});
        v.ring.reset();
        v.dmabuf.reset();
        v.target.reset();
    }
    m_map.reset();
    m_terrain.reset();
    m_depth_stencil = 0;  // went with the context
    m_depth_size = {};
    m_egl.recreate();
    const ProgramBinaryCache::Use programs(m_programs.get());  // the new context's programs
    m_features = GlFeatures::current(m_device.gles_major, m_device.gles_minor);
    m_terrain = std::make_unique<TerrainLayer>();
    if (m_terrain_mesh) m_terrain->upload(*m_terrain_mesh);
    m_map = std::make_unique<MapRenderer>(m_options, m_device.software, m_features);
    if (m_map_style) m_map->setStyle(*m_map_style);
    for (const auto& [id, size] : sizes) {
        View& v = m_targets.at(id);
        v.target = std::make_unique<RenderTarget>(size.first, size.second, m_options.msaa_samples,
                                                  sharedDepthStencil(size.first, size.second));
        v.ring = std::make_unique<ReadbackRing>(size.first, size.second, m_options.readback_ring);
    }
    ++m_device.context_resets;
}

void GlRenderer::render(TargetHandle handle, const Camera& camera) {
    (void)view(handle);  // throws for a handle that names no target
    m_egl.makeCurrent();
    checkContext();
    ++m_frames;
    const RenderTarget& target = *view(handle).target;
    target.clear(m_style.sky_color.r, m_style.sky_color.g, m_style.sky_color.b);
    target.bindForDrawing(false);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    glEnable(GL_CULL_FACE);
    glCullFace(GL_BACK);
    const double aspect = static_cast<double>(target.width()) / target.height();
    m_terrain->draw(camera, aspect, m_style);
    target.resolve();
}

void GlRenderer::renderMap(TargetHandle target, const MapFrame& frame) {
    (void)view(target);  // throws for a handle that names no target
    m_egl.makeCurrent();
    checkContext();
    ++m_frames;
    const View& v = view(target);
    const ProgramBinaryCache::Use programs(m_programs.get());  // passes made on first use compile theirs here
    // Each target is a view of its own: its label layout continues from its own last frame.
    if (frame.hide_surface_labels && frame.layers.labels) {
        MapFrame without = frame;  // in a tunnel: drawn as with the labels off
        without.layers.labels = false;
        m_map->render(without, *v.target, target.id());
        return;
    }
    m_map->render(frame, *v.target, target.id());
}

void GlRenderer::setMapStyle(const MapStyle& style) {
    m_map_style = style;
    m_map->setStyle(style);
}

void GlRenderer::finish() {
    m_egl.makeCurrent();
    glFinish();
}

Image GlRenderer::readSync(TargetHandle handle) {
    const RenderTarget& target = *view(handle).target;
    m_egl.makeCurrent();
    target.resolve();
    return readPixelsSync(target.width(), target.height());
}

std::optional<Frame> GlRenderer::readAsync(TargetHandle target, std::uint64_t sequence) {
    View& v = view(target);
    m_egl.makeCurrent();
    v.target->resolve();
    return v.ring->submit(sequence);
}

std::vector<Frame> GlRenderer::collectReadbacks(TargetHandle target) {
    View& v = view(target);
    m_egl.makeCurrent();
    return v.ring->collectReady();
}

std::optional<DmabufFrame> GlRenderer::exportFrame(TargetHandle target, std::uint32_t busy,
                                                   const FrameOverlay* overlay) {
    View& v = view(target);
    if (!m_dmabuf || !m_dmabuf->ready()) return std::nullopt;
    m_egl.makeCurrent();
    v.target->resolve();  // leaves the frame's colour bound for reading
    if (!v.dmabuf) v.dmabuf = std::make_unique<DmabufExporter::Pool>();
    auto frame = m_dmabuf->exportFrame(*v.dmabuf, v.target->width(), v.target->height(), busy, overlay);
    v.target->bindForDrawing(false);
    return frame;
}

std::vector<Frame> GlRenderer::drainReadbacks(TargetHandle target) {
    View& v = view(target);
    m_egl.makeCurrent();
    return v.ring->drain();
}

}  // namespace navmap::render::gl
