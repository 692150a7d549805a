#include "gl_renderer.h"

#include <GLES3/gl3.h>

#include <string>

namespace navmap::render::gl {

namespace {

std::string glString(GLenum name) {
    const auto* s = reinterpret_cast<const char*>(glGetString(name));
    return s ? s : "";
}

}  // namespace

GlRenderer::GlRenderer(const RendererOptions& options) : m_options(options), m_egl(options.platform) {
    if (options.width <= 0 || options.height <= 0) {
        throw RenderError("renderer: invalid size " + std::to_string(options.width) + "x" +
                          std::to_string(options.height));
    }
    m_device.backend = "gles";
    m_device.platform = m_egl.platformUsed();
    m_device.vendor = glString(GL_VENDOR);
    m_device.renderer = glString(GL_RENDERER);
    m_device.version = glString(GL_VERSION);
    m_device.gles_major = m_egl.glesMajor();
    m_device.gles_minor = m_egl.glesMinor();
    m_device.software = m_device.renderer.find("llvmpipe") != std::string::npos ||
                        m_device.renderer.find("softpipe") != std::string::npos ||
                        m_device.renderer.find("swrast") != std::string::npos;
    if (m_options.msaa_samples < 0) m_options.msaa_samples = m_device.software ? 0 : 4;
    m_terrain = std::make_unique<TerrainLayer>();
    m_map = std::make_unique<MapRenderer>(m_options);
    resize(options.width, options.height);
}

GlRenderer::~GlRenderer() {
    m_egl.makeCurrent();
    // GL objects go before the context (m_egl is destroyed after the members declared below it).
    m_ring.reset();
    m_target.reset();
    m_terrain.reset();
    m_map.reset();
}

void GlRenderer::resize(int width, int height) {
    m_egl.makeCurrent();
    if (m_ring) m_ring->drain();
    m_target = std::make_unique<RenderTarget>(width, height, m_options.msaa_samples);
    m_ring = std::make_unique<ReadbackRing>(width, height, m_options.readback_ring);
    m_device.msaa_samples = m_target->samples();
}

void GlRenderer::setTerrain(const HeightfieldMesh& mesh) {
    m_egl.makeCurrent();
    m_terrain->upload(mesh);
}

void GlRenderer::render(const Camera& camera) {
    m_egl.makeCurrent();
    m_target->clear(m_style.sky_color.r, m_style.sky_color.g, m_style.sky_color.b);
    m_target->bindForDrawing(false);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    glEnable(GL_CULL_FACE);
    glCullFace(GL_BACK);
    const double aspect = static_cast<double>(m_target->width()) / m_target->height();
    m_terrain->draw(camera, aspect, m_style);
    m_target->resolve();
}

void GlRenderer::renderMap(const MapFrame& frame) {
    m_egl.makeCurrent();
    m_map->render(frame, *m_target);
}

void GlRenderer::setMapStyle(const MapStyle& style) { m_map->setStyle(style); }

void GlRenderer::finish() {
    m_egl.makeCurrent();
    glFinish();
}

Image GlRenderer::readSync() {
    m_egl.makeCurrent();
    m_target->resolve();
    return readPixelsSync(m_target->width(), m_target->height());
}

std::optional<Frame> GlRenderer::readAsync(std::uint64_t sequence) {
    m_egl.makeCurrent();
    m_target->resolve();
    return m_ring->submit(sequence);
}

std::vector<Frame> GlRenderer::collectReadbacks() {
    m_egl.makeCurrent();
    return m_ring->collectReady();
}

std::vector<Frame> GlRenderer::drainReadbacks() {
    m_egl.makeCurrent();
    return m_ring->drain();
}

}  // namespace navmap::render::gl
