// SPDX-License-Identifier: Apache-2.0
#include "occlusion_effects.h"

#include "gl_state_scope.h"
#include "vertex_layout.h"

#include <algorithm>
#include <cstddef>
#include <cstdio>
#include <string>

#include <glm/gtc/type_ptr.hpp>

#include "gl/gl_work.h"
#include "navmap/render/renderer.h"

namespace navmap::render::gl {

namespace {

// Stencil bit of the frame that the direct glow uses so overlapping road segments blend once.
constexpr GLuint kGlowStencilBit = 0x80;
// Stencil bit of the frame that marks the pixels where a building is the visible surface: inside
// the label auras the only pixels the aura changes. The composite clears it as it blends (each
// pixel blends once).
constexpr GLuint kAuraStencilBit = 0x20;

// Buffers kept for this many target sizes (one renderer may serve several displays).
constexpr std::size_t kMaxBufferSets = 3;

GLuint makeTexture(GLenum format, int w, int h, GLint filter) {
    GLuint t = 0;
    glGenTextures(1, &t);
    glBindTexture(GL_TEXTURE_2D, t);
    glTexStorage2D(GL_TEXTURE_2D, 1, format, w, h);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, filter);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, filter);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    glBindTexture(GL_TEXTURE_2D, 0);
    return t;
}

// An RGBA8 colour layer: drawn at the target's sample count, read as a single-sampled texture.
struct Layer {
    GLuint texture = 0;
    GLuint ms_color = 0;     // multisampled colour (targets with MSAA), else 0
    GLuint fbo = 0;          // drawing framebuffer: ms_color or texture, plus a depth attachment
    GLuint resolve_fbo = 0;  // texture (MSAA only)
    int width = 0, height = 0;

    void create(int w, int h, int samples, GLint filter) {
        width = w;
        height = h;
        texture = makeTexture(GL_RGBA8, w, h, filter);
        glGenFramebuffers(1, &fbo);
        glBindFramebuffer(GL_FRAMEBUFFER, fbo);
        if (samples > 0) {
            ms_color = makeRenderbuffer(GL_RGBA8, samples, w, h);
            glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, ms_color);
            glGenFramebuffers(1, &resolve_fbo);
            glBindFramebuffer(GL_FRAMEBUFFER, resolve_fbo);
            glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, texture, 0);
            checkFramebufferComplete("occlusion effects: resolve");
        } else {
            glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, texture, 0);
        }
    }
    void attachDepth(GLuint depth_rb) const {
        glBindFramebuffer(GL_FRAMEBUFFER, fbo);
        glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_STENCIL_ATTACHMENT, GL_RENDERBUFFER, depth_rb);
    }
    // Binds for drawing and clears the colour to transparent.
    void begin() const {
        glBindFramebuffer(GL_FRAMEBUFFER, fbo);
        const GLenum c0 = GL_COLOR_ATTACHMENT0;
        glDrawBuffers(1, &c0);
        glViewport(0, 0, width, height);
        const GLfloat zero[] = {0, 0, 0, 0};
        glClearBufferfv(GL_COLOR, 0, zero);
    }
    void resolve() const {
        if (!ms_color) return;
        glBindFramebuffer(GL_READ_FRAMEBUFFER, fbo);
        glBindFramebuffer(GL_DRAW_FRAMEBUFFER, resolve_fbo);
        glBlitFramebuffer(0, 0, width, height, 0, 0, width, height, GL_COLOR_BUFFER_BIT, GL_NEAREST);
    }
    void destroy() {
        glDeleteTextures(1, &texture);
        glDeleteRenderbuffers(1, &ms_color);
        const GLuint fbos[] = {fbo, resolve_fbo};
        glDeleteFramebuffers(2, fbos);
        *this = {};
    }
};

void bindFullscreen(GLuint vao) {
    glBindVertexArray(vao);
    countedDrawArrays(GL_TRIANGLES, 0, 3);
}

// Blits the depth of the target's drawing framebuffer into `fbo` (same size).
void blitDepth(const RenderTarget& target, GLuint fbo) {
    glBindFramebuffer(GL_READ_FRAMEBUFFER, target.drawFramebuffer());
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, fbo);
    glBlitFramebuffer(0, 0, target.width(), target.height(), 0, 0, target.width(), target.height(), GL_DEPTH_BUFFER_BIT,
                      GL_NEAREST);
}

// One enlarged label OOBB for aura_mask.vert.
struct MaskInstance {
    glm::vec4 box;     // center, axis
    glm::vec4 extent;  // half extents (enlarged), margin, alpha
    float depth;       // NDC z
};

}  // namespace

struct OcclusionEffects::Buffers {
    int width = 0, height = 0, samples = 0;
    // Terrain-only depth, single-sampled (glow_roads.frag tests against it, the aura writes it
    // inside the auras). Captured each frame a glow or aura is drawn.
    GLuint terrain_depth = 0, terrain_fbo = 0;
    // Glowing roads with blur: the glow layer (the scene's depth attached per frame) and the
    // half-resolution blur pair.
    Layer glow;
    Layer blur[2];
    // Label aura: the layer behind the labels (step 2), drawn with the frame's depth/stencil
    // attached, and the label OOBB depth + gradient mask (steps 2 and 3). The layer starts as the
    // terrain colour before the buildings; multisampled it starts transparent, as ES 3.0 cannot
    // blit into a multisampled buffer, and the terrain colour is kept beside it (terrain_color).
    Layer behind;
    Layer terrain_color;
    GLuint label_mask = 0, label_depth = 0, label_fbo = 0;
    int maskWidth() const { return std::max((width + 1) / 2, 1); }
    int maskHeight() const { return std::max((height + 1) / 2, 1); }
    // Single-sampled targets: the depth/stencil step 2 draws with, a copy of the frame's taken
    // when the depth inside the auras has become the far plane's; the frame's own then keeps that
    // depth, and the composite need not write any (attached to `behind` for good).
    GLuint step2_depth = 0;

    void makeTerrainDepth() {
        if (terrain_fbo) return;
        terrain_depth = makeTexture(GL_DEPTH24_STENCIL8, width, height, GL_NEAREST);
        glGenFramebuffers(1, &terrain_fbo);
        glBindFramebuffer(GL_FRAMEBUFFER, terrain_fbo);
        glFramebufferTexture2D(GL_FRAMEBUFFER, GL_DEPTH_STENCIL_ATTACHMENT, GL_TEXTURE_2D, terrain_depth, 0);
        const GLenum none = GL_NONE;
        glDrawBuffers(1, &none);
        glReadBuffer(GL_NONE);
        checkFramebufferComplete("occlusion effects: terrain depth");
    }

    void makeGlowLayers() {  // blur only
        if (glow.fbo) return;
        glow.create(width, height, samples, GL_LINEAR);  // linear: the blur halves it
        const int hw = std::max(width / 2, 1), hh = std::max(height / 2, 1);
        for (Layer& l : blur) {
            l.create(hw, hh, 0, GL_LINEAR);
            checkFramebufferComplete("occlusion effects: glow blur");
        }
    }

    void makeAura() {
        makeTerrainDepth();
        if (behind.fbo) return;
        behind.create(width, height, samples, GL_NEAREST);
        checkFramebufferComplete("occlusion effects: aura scene behind labels");
        if (samples > 0) {
            terrain_color.create(width, height, 0, GL_NEAREST);  // a resolve target only
            checkFramebufferComplete("occlusion effects: aura terrain colour");
        }
        if (samples == 0) {
            step2_depth = makeRenderbuffer(GL_DEPTH24_STENCIL8, 0, width, height);
            behind.attachDepth(step2_depth);
            checkFramebufferComplete("occlusion effects: aura step 2 depth");
        }
        // Half resolution (seed 5.5.1 steps 2 and 3): the gradient is smooth and read with linear
        // filtering; the label depth decides only where the gradient has faded in.
        label_mask = makeTexture(GL_R8, maskWidth(), maskHeight(), GL_LINEAR);
        label_depth = makeTexture(GL_DEPTH_COMPONENT24, maskWidth(), maskHeight(), GL_NEAREST);
        glGenFramebuffers(1, &label_fbo);
        glBindFramebuffer(GL_FRAMEBUFFER, label_fbo);
        glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, label_mask, 0);
        glFramebufferTexture2D(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_TEXTURE_2D, label_depth, 0);
        checkFramebufferComplete("occlusion effects: aura label OOBBs");
    }

    ~Buffers() {
        glow.destroy();
        for (Layer& l : blur) l.destroy();
        behind.destroy();
        terrain_color.destroy();
        const GLuint textures[] = {terrain_depth, label_mask, label_depth};
        glDeleteTextures(3, textures);
        const GLuint fbos[] = {terrain_fbo, label_fbo};
        glDeleteFramebuffers(2, fbos);
        glDeleteRenderbuffers(1, &step2_depth);
    }
};

OcclusionEffects::OcclusionEffects()
    : m_glow_roads(ShaderProgram::fromEmbedded("roads_geo.vert", "glow_roads.frag")),
      m_glow_blur(ShaderProgram::fromEmbedded("screen_outline.vert", "glow_blur.frag")),
      m_glow_composite(ShaderProgram::fromEmbedded("screen_outline.vert", "glow_composite.frag")),
      m_glow_stencil(ShaderProgram::fromEmbedded("screen_outline.vert", "glow_stencil.frag")),
      m_aura_buildings(ShaderProgram::fromEmbedded("buildings.vert", "aura_buildings.frag")),
      m_aura_mask(ShaderProgram::fromEmbedded("aura_mask.vert", "aura_mask.frag")),
      m_aura_depth(ShaderProgram::fromEmbedded("aura_mask.vert", "aura_depth.frag", "#define NAVMAP_FAR_DEPTH 1\n")),
      m_aura_composite(ShaderProgram::fromEmbedded("aura_mask.vert", "aura_composite.frag")),
      m_aura_composite_colour(
          ShaderProgram::fromEmbedded("aura_mask.vert", "aura_composite.frag", "#define NAVMAP_DEPTH_KEPT 1\n")) {
    glGenVertexArrays(1, &m_empty_vao);
    glGenVertexArrays(1, &m_mask_vao);
    glGenBuffers(1, &m_mask_vbo);
    glBindVertexArray(m_mask_vao);
    glBindBuffer(GL_ARRAY_BUFFER, m_mask_vbo);
    setVertexAttributes(sizeof(MaskInstance),
                        {{0, 4, GL_FLOAT, offsetof(MaskInstance, box)},
                         {1, 4, GL_FLOAT, offsetof(MaskInstance, extent)},
                         {2, 1, GL_FLOAT, offsetof(MaskInstance, depth)}},
                        1);
    glBindVertexArray(0);
    glBindBuffer(GL_ARRAY_BUFFER, 0);
}

OcclusionEffects::~OcclusionEffects() {
    m_buffers.clear();
    const GLuint vaos[] = {m_empty_vao, m_mask_vao};
    glDeleteVertexArrays(2, vaos);
    glDeleteBuffers(1, &m_mask_vbo);
}

OcclusionEffects::Buffers& OcclusionEffects::buffersFor(const RenderTarget& target) {
    const int samples = target.samples();
    auto it = std::find_if(m_buffers.begin(), m_buffers.end(), [&](const auto& b) {
        return b->width == target.width() && b->height == target.height() && b->samples == samples;
    });
    if (it == m_buffers.end()) {
        auto b = std::make_unique<Buffers>();
        b->width = target.width();
        b->height = target.height();
        b->samples = samples;
        if (m_buffers.size() >= kMaxBufferSets) m_buffers.pop_back();
        m_buffers.insert(m_buffers.begin(), std::move(b));
    } else if (it != m_buffers.begin()) {
        std::rotate(m_buffers.begin(), it, it + 1);
    }
    return *m_buffers.front();
}

void OcclusionEffects::captureTerrainDepth(const RenderTarget& target, bool glow, bool aura) {
    if (!glow && !aura) return;
    Buffers& b = buffersFor(target);
    b.makeTerrainDepth();
    if (aura) b.makeAura();
    blitDepth(target, b.terrain_fbo);
    if (aura) {  // the layer behind the labels starts as the terrain
        glBindFramebuffer(GL_READ_FRAMEBUFFER, target.drawFramebuffer());
        glReadBuffer(GL_COLOR_ATTACHMENT0);
        glBindFramebuffer(GL_DRAW_FRAMEBUFFER, b.samples > 0 ? b.terrain_color.fbo : b.behind.fbo);
        glBlitFramebuffer(0, 0, b.width, b.height, 0, 0, b.width, b.height, GL_COLOR_BUFFER_BIT, GL_NEAREST);
    }
    target.bindForDrawing(false);
}

GLuint OcclusionEffects::terrainDepth(const RenderTarget& target) { return buffersFor(target).terrain_depth; }

void OcclusionEffects::markBuildings(bool on) {
    if (!on) {
        glDisable(GL_STENCIL_TEST);
        glStencilMask(0xFF);
        return;
    }
    glEnable(GL_STENCIL_TEST);
    glStencilMask(kAuraStencilBit);
    glStencilFunc(GL_ALWAYS, kAuraStencilBit, kAuraStencilBit);
    glStencilOp(GL_KEEP, GL_KEEP, GL_REPLACE);
}

void OcclusionEffects::glowFromStencil(const RenderTarget& target, const MapLayers& layers, const MapStyle& style) {
    Buffers& b = buffersFor(target);
    const bool blur = layers.glow_blur;
    if (blur) b.makeGlowLayers();
    const GlStateScope saved;
    const float strength = std::clamp(style.glow_strength, 0.0f, 1.0f);
    // seed 5.5.2: "if z_building < z_road the road is occluded". The road pixels a building hides
    // are marked; where a road is seen there all the same (another road over the hidden one, road
    // mask of seed 3.6.3, resolved when the outlines were drawn) nothing glows.
    if (!(layers.outlines && (layers.roads || layers.route))) target.resolveMask();
    if (blur) {
        b.glow.attachDepth(target.depthStencilRenderbuffer());
        b.glow.begin();
        glDisable(GL_BLEND);
    } else {
        target.bindForDrawing(false);
        glEnable(GL_BLEND);
        glBlendFuncSeparate(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA, GL_ZERO, GL_ONE);  // the frame stays opaque
    }
    glDisable(GL_DEPTH_TEST);
    glDisable(GL_CULL_FACE);
    glEnable(GL_STENCIL_TEST);
    glStencilMask(0);
    glStencilFunc(GL_EQUAL, kRoadFillStencilBit, kRoadFillStencilBit);
    glStencilOp(GL_KEEP, GL_KEEP, GL_KEEP);
    glUseProgram(m_glow_stencil.id());
    glUniform3fv(m_glow_stencil.uniform("u_glow_color"), 1, glm::value_ptr(style.glow_color));
    glUniform1f(m_glow_stencil.uniform("u_alpha"), blur ? 1.0f : strength);
    glActiveTexture(GL_TEXTURE0);
    glBindTexture(GL_TEXTURE_2D, target.maskTexture());
    glUniform1i(m_glow_stencil.uniform("u_road_mask"), 0);
    bindFullscreen(m_empty_vao);
    glBindTexture(GL_TEXTURE_2D, 0);
    glDisable(GL_STENCIL_TEST);
    glStencilMask(0xFF);
    if (blur) blurAndComposite(target, b, strength);
    target.bindForDrawing(false);
    glBindVertexArray(0);
}

void OcclusionEffects::aura(const RenderTarget& target, std::span<const LabelOccluder> labels,
                            const glm::mat4& projection, const MapStyle& style, const DrawWith& draw_buildings,
                            const std::function<void()>& draw_roads) {
    // Step 1 of seed 5.5.1 (the occluding buildings in a buffer of their own) is the scene itself
    // here: its buildings are already drawn, and the terrain colour under them was kept by
    // captureTerrainDepth(). Outside the auras the frame stays exactly the baseline.
    std::vector<MaskInstance> instances;
    instances.reserve(labels.size());
    std::vector<LabelOccluder> sorted(labels.begin(), labels.end());
    std::sort(sorted.begin(), sorted.end(), [](const auto& a, const auto& c) { return a.depth_m > c.depth_m; });
    for (const LabelOccluder& l : sorted) {
        if (l.alpha <= 0.0f) continue;
        const glm::vec4 clip = projection * glm::vec4(0.0f, 0.0f, -l.depth_m, 1.0f);
        if (clip.w <= 0.0f) continue;
        // seed 5.5.1: "we slightly enlarge the bounding-box of each label" so the referenced
        // road stays visible around it; the margin grows a little with the text size.
        const float margin = style.aura_margin_px + 0.5f * std::min(l.box.half_extents.x, l.box.half_extents.y);
        instances.push_back({glm::vec4(l.box.center, l.box.axis),
                             glm::vec4(l.box.half_extents + margin, margin, l.alpha),
                             std::clamp(clip.z / clip.w, -1.0f, 1.0f)});
    }
    if (instances.empty()) return;  // no aura anywhere: the baseline frame
    Buffers& b = buffersFor(target);
    b.makeAura();
    const GlStateScope saved;

    // Steps 2 (label depth) and 3 (gradient mask) in one pass: every enlarged label OOBB at the
    // depth of its label, farthest first, so the depth test keeps the nearest label and the
    // MAX blend the strongest mask.
    glBindFramebuffer(GL_FRAMEBUFFER, b.label_fbo);
    const GLenum c0 = GL_COLOR_ATTACHMENT0;
    glDrawBuffers(1, &c0);
    glViewport(0, 0, b.maskWidth(), b.maskHeight());
    const GLfloat zero[] = {0, 0, 0, 0};
    glClearBufferfv(GL_COLOR, 0, zero);
    const GLfloat far_depth = 1.0f;
    glClearBufferfv(GL_DEPTH, 0, &far_depth);
    glBindBuffer(GL_ARRAY_BUFFER, m_mask_vbo);
    if (instances.size() > m_mask_capacity) {
        m_mask_capacity = std::max(instances.size(), std::size_t{64});
        countedBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(m_mask_capacity * sizeof(MaskInstance)), nullptr,
                          GL_DYNAMIC_DRAW);
    }
    countedBufferSubData(GL_ARRAY_BUFFER, 0, static_cast<GLsizeiptr>(instances.size() * sizeof(MaskInstance)),
                         instances.data());
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LEQUAL);
    glDepthMask(GL_TRUE);
    glDisable(GL_CULL_FACE);
    glEnable(GL_BLEND);
    glBlendEquation(GL_MAX);
    glUseProgram(m_aura_mask.id());
    glUniform2f(m_aura_mask.uniform("u_viewport"), static_cast<float>(b.width), static_cast<float>(b.height));
    glBindVertexArray(m_mask_vao);
    countedDrawArraysInstanced(GL_TRIANGLE_STRIP, 0, 4, static_cast<GLsizei>(instances.size()));
    glDisable(GL_BLEND);
    glBlendEquation(GL_FUNC_ADD);

    // Inside the auras, on the pixels that markBuildings() marked, the depth becomes the far
    // plane's: the layer behind the labels is drawn there with the terrain as its only limit (the
    // terrain-only depth, tested in its shaders), and the labels drawn next are not hidden by the
    // buildings that the aura fades. (World-space labels stand where their lines of sight clear
    // the terrain; the manoeuvre arrows lie on the road ahead.) The depth comes from the vertices
    // and the pass writes no colour: llvmpipe tests the stencil first and shades the marked
    // pixels only.
    glBindFramebuffer(GL_FRAMEBUFFER, target.drawFramebuffer());
    glDrawBuffers(1, &c0);
    glViewport(0, 0, b.width, b.height);
    glColorMask(GL_FALSE, GL_FALSE, GL_FALSE, GL_FALSE);
    glDepthFunc(GL_ALWAYS);
    glDepthMask(GL_TRUE);
    glEnable(GL_STENCIL_TEST);
    glStencilMask(0);
    glStencilFunc(GL_EQUAL, kAuraStencilBit, kAuraStencilBit);
    glStencilOp(GL_KEEP, GL_KEEP, GL_KEEP);
    glUseProgram(m_aura_depth.id());
    glUniform2f(m_aura_depth.uniform("u_viewport"), static_cast<float>(b.width), static_cast<float>(b.height));
    countedDrawArraysInstanced(GL_TRIANGLE_STRIP, 0, 4, static_cast<GLsizei>(instances.size()));  // mask VAO
    glActiveTexture(GL_TEXTURE1);

    // Step 2, on the marked pixels: the buildings again with the inverse depth test against the
    // label OOBB depth (over the terrain depth, so hills still hide them), then the roads and the
    // route over them, into the layer behind the labels, which holds the terrain colour: the
    // scene as it looks without the buildings in front of the labels. Single-sampled, with a copy
    // of the frame's depth and stencil, so the frame keeps the far depth inside the auras
    // (a blit costs llvmpipe less than the composite writing the depth per fragment, which also
    // makes it test the stencil after the shader); multisampled (ES 3.0 cannot blit into a
    // multisampled buffer) with the frame's own, and the composite writes the terrain's depth.
    const bool depth_kept = b.step2_depth != 0;
    if (depth_kept) {
        glBindFramebuffer(GL_READ_FRAMEBUFFER, target.drawFramebuffer());
        glBindFramebuffer(GL_DRAW_FRAMEBUFFER, b.behind.fbo);
        glBlitFramebuffer(0, 0, b.width, b.height, 0, 0, b.width, b.height, GL_DEPTH_BUFFER_BIT | GL_STENCIL_BUFFER_BIT,
                          GL_NEAREST);
    } else {
        b.behind.attachDepth(target.depthStencilRenderbuffer());
    }
    glBindFramebuffer(GL_FRAMEBUFFER, b.behind.fbo);
    glDrawBuffers(1, &c0);
    glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    if (b.samples > 0) glClearBufferfv(GL_COLOR, 0, zero);
    glEnable(GL_STENCIL_TEST);
    glStencilMask(0);
    glStencilFunc(GL_EQUAL, kAuraStencilBit, kAuraStencilBit);
    glStencilOp(GL_KEEP, GL_KEEP, GL_KEEP);
    glDepthFunc(GL_LESS);
    glEnable(GL_CULL_FACE);
    glCullFace(GL_BACK);
    glUseProgram(m_aura_buildings.id());
    glBindTexture(GL_TEXTURE_2D, b.label_depth);  // unit 1
    glUniform1i(m_aura_buildings.uniform("u_label_depth"), 1);
    glActiveTexture(GL_TEXTURE3);  // for the buildings and for draw_roads
    glBindTexture(GL_TEXTURE_2D, b.terrain_depth);
    glUniform1i(m_aura_buildings.uniform("u_terrain_depth"), 3);
    glUniform2f(m_aura_buildings.uniform("u_frame_size"), static_cast<float>(b.width), static_cast<float>(b.height));
    glActiveTexture(GL_TEXTURE0);
    draw_buildings(m_aura_buildings);
    glActiveTexture(GL_TEXTURE1);
    glBindTexture(GL_TEXTURE_2D, 0);
    glActiveTexture(GL_TEXTURE0);
    glDisable(GL_CULL_FACE);
    glDepthMask(GL_FALSE);
    glDepthFunc(GL_LEQUAL);
    draw_roads();
    glDepthMask(GL_TRUE);
    glActiveTexture(GL_TEXTURE3);
    glBindTexture(GL_TEXTURE_2D, 0);
    glActiveTexture(GL_TEXTURE0);
    b.behind.resolve();

    compositeAura(target, b, style, static_cast<GLsizei>(instances.size()), depth_kept);
}

void OcclusionEffects::compositeAura(const RenderTarget& target, Buffers& b, const MapStyle& style, GLsizei instances,
                                     bool depth_kept) {
    // Step 4: composite by the mask on the marked pixels, each once (the stencil bit is cleared
    // as it blends); where step 2 drew into the frame's depth (multisampled), the depth there
    // becomes the terrain's.
    target.bindForDrawing(false);
    // Also the glow's mark: inside the auras the road is shown, not glowing (glowFromStencil()).
    glStencilMask(kAuraStencilBit | OcclusionEffects::kRoadFillStencilBit);
    glStencilFunc(GL_EQUAL, kAuraStencilBit, kAuraStencilBit);
    glStencilOp(GL_KEEP, GL_KEEP, GL_ZERO);
    if (depth_kept) {
        glDisable(GL_DEPTH_TEST);
    } else {
        glEnable(GL_DEPTH_TEST);
        glDepthFunc(GL_ALWAYS);
        glDepthMask(GL_TRUE);
    }
    glEnable(GL_BLEND);
    glBlendFuncSeparate(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA, GL_ZERO, GL_ONE);  // the frame stays opaque
    ShaderProgram& composite = depth_kept ? m_aura_composite_colour : m_aura_composite;
    glUseProgram(composite.id());
    glActiveTexture(GL_TEXTURE0);
    glBindTexture(GL_TEXTURE_2D, b.behind.texture);
    glActiveTexture(GL_TEXTURE1);
    glBindTexture(GL_TEXTURE_2D, b.samples > 0 ? b.terrain_color.texture : b.behind.texture);
    glActiveTexture(GL_TEXTURE2);
    glBindTexture(GL_TEXTURE_2D, b.label_mask);
    glActiveTexture(GL_TEXTURE3);
    glBindTexture(GL_TEXTURE_2D, b.terrain_depth);
    glUniform1i(composite.uniform("u_behind"), 0);
    glUniform1i(composite.uniform("u_terrain"), 1);
    glUniform1i(composite.uniform("u_over_terrain"), b.samples > 0 ? 1 : 0);
    glUniform1i(composite.uniform("u_mask"), 2);
    glUniform1i(composite.uniform("u_terrain_depth"), 3);
    glUniform1f(composite.uniform("u_min_alpha"), std::clamp(style.aura_min_alpha, 0.0f, 1.0f));
    glUniform2f(composite.uniform("u_frame_size"), static_cast<float>(b.width), static_cast<float>(b.height));
    glUniform2f(composite.uniform("u_viewport"), static_cast<float>(b.width), static_cast<float>(b.height));
    glBindVertexArray(m_mask_vao);
    countedDrawArraysInstanced(GL_TRIANGLE_STRIP, 0, 4, instances);
    glDisable(GL_STENCIL_TEST);
    glStencilMask(0xFF);
    for (GLenum unit : {GL_TEXTURE3, GL_TEXTURE2, GL_TEXTURE1, GL_TEXTURE0}) {
        glActiveTexture(unit);
        glBindTexture(GL_TEXTURE_2D, 0);
    }
    glBindVertexArray(0);
}

void OcclusionEffects::blurAndComposite(const RenderTarget& target, Buffers& b, float strength) {
    b.glow.resolve();
    glDisable(GL_DEPTH_TEST);

    // seed 5.5.2 (optional): blur, horizontal while halving the resolution, then vertical.
    {
        glUseProgram(m_glow_blur.id());
        glUniform1i(m_glow_blur.uniform("u_source"), 0);
        glActiveTexture(GL_TEXTURE0);
        b.blur[0].begin();
        glBindTexture(GL_TEXTURE_2D, b.glow.texture);
        glUniform2f(m_glow_blur.uniform("u_step"), 1.0f / static_cast<float>(b.blur[0].width), 0.0f);
        bindFullscreen(m_empty_vao);
        b.blur[1].begin();
        glBindTexture(GL_TEXTURE_2D, b.blur[0].texture);
        glUniform2f(m_glow_blur.uniform("u_step"), 0.0f, 1.0f / static_cast<float>(b.blur[1].height));
        bindFullscreen(m_empty_vao);
    }

    // Composite over the scene, before the labels, except where a road is visible.
    target.bindForDrawing(false);
    glEnable(GL_BLEND);
    glBlendFuncSeparate(GL_ONE, GL_ONE_MINUS_SRC_ALPHA, GL_ZERO, GL_ONE);  // the frame stays opaque
    glUseProgram(m_glow_composite.id());
    glActiveTexture(GL_TEXTURE0);
    glBindTexture(GL_TEXTURE_2D, b.glow.texture);
    glActiveTexture(GL_TEXTURE1);
    glBindTexture(GL_TEXTURE_2D, b.blur[1].texture);
    glUniform1i(m_glow_composite.uniform("u_glow"), 0);
    glUniform1i(m_glow_composite.uniform("u_blurred"), 1);
    glActiveTexture(GL_TEXTURE2);
    glBindTexture(GL_TEXTURE_2D, target.maskTexture());
    glUniform1i(m_glow_composite.uniform("u_road_mask"), 2);
    glUniform1f(m_glow_composite.uniform("u_strength"), strength);
    bindFullscreen(m_empty_vao);
    for (GLenum unit : {GL_TEXTURE2, GL_TEXTURE1, GL_TEXTURE0}) {
        glActiveTexture(unit);
        glBindTexture(GL_TEXTURE_2D, 0);
    }
}

void OcclusionEffects::glow(const RenderTarget& target, const MapLayers& layers, const MapStyle& style,
                            const DrawWith& draw_roads) {
    Buffers& b = buffersFor(target);
    b.makeTerrainDepth();
    const bool direct = !layers.glow_blur;
    if (!direct) b.makeGlowLayers();
    const GlStateScope saved;

    // seed 5.5.2 step 1: the road fragments behind what the scene depth holds (buildings, and
    // the terrain, which the shader excludes with the terrain-only depth). Without blur they go
    // straight into the frame: no glow buffer, no full-screen composite (the passes that cost
    // most on software rasterizers). Where a road is visible nothing glows (road mask, already
    // resolved when the outlines were drawn).
    if (!(layers.outlines && (layers.roads || layers.route))) target.resolveMask();
    if (direct) {
        target.bindForDrawing(false);
    } else {
        b.glow.attachDepth(target.depthStencilRenderbuffer());
        b.glow.begin();
    }
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_GREATER);
    glDepthMask(GL_FALSE);
    glDisable(GL_CULL_FACE);
    const float strength = std::clamp(style.glow_strength, 0.0f, 1.0f);
    const bool blend_once = direct && strength < 1.0f;
    if (blend_once) {
        glEnable(GL_BLEND);
        glBlendFuncSeparate(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA, GL_ZERO, GL_ONE);  // the frame stays opaque
        // Overlapping segments (joints, junctions) blend once: stencil bit 7, which no pass
        // before sets in a frame (RenderTarget::clear zeroes it; a masked clear here cost 3 % of
        // the frame on llvmpipe).
        glStencilMask(kGlowStencilBit);
        glEnable(GL_STENCIL_TEST);
        glStencilFunc(GL_NOTEQUAL, kGlowStencilBit, kGlowStencilBit);
        glStencilOp(GL_KEEP, GL_KEEP, GL_REPLACE);
    } else {
        glDisable(GL_BLEND);
    }
    glUseProgram(m_glow_roads.id());
    glUniform1i(m_glow_roads.uniform("u_direct"), direct ? 1 : 0);
    glUniform1f(m_glow_roads.uniform("u_alpha"), strength);
    glActiveTexture(GL_TEXTURE2);
    glBindTexture(GL_TEXTURE_2D, target.maskTexture());
    glUniform1i(m_glow_roads.uniform("u_road_mask"), 2);
    glActiveTexture(GL_TEXTURE1);
    glBindTexture(GL_TEXTURE_2D, b.terrain_depth);
    glUniform1i(m_glow_roads.uniform("u_terrain_depth"), 1);
    glActiveTexture(GL_TEXTURE0);
    glUniform1i(m_glow_roads.uniform("u_road_color"), layers.glow_mode == MapLayers::GlowMode::RoadColor ? 1 : 0);
    glUniform3fv(m_glow_roads.uniform("u_glow_color"), 1, glm::value_ptr(style.glow_color));
    draw_roads(m_glow_roads);
    for (GLenum unit : {GL_TEXTURE2, GL_TEXTURE1, GL_TEXTURE0}) {
        glActiveTexture(unit);
        glBindTexture(GL_TEXTURE_2D, 0);
    }
    if (blend_once) {
        glDisable(GL_STENCIL_TEST);
        glStencilMask(0xFF);
    }
    if (direct) {
        glBindVertexArray(0);
        return;
    }
    blurAndComposite(target, b, strength);
    glBindVertexArray(0);
}

}  // namespace navmap::render::gl
