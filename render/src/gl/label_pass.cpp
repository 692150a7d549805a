// SPDX-License-Identifier: Apache-2.0
// The label pass's frame: layout() runs the parts in label_pass_input.cpp (candidates),
// label_pass_keep_out.cpp (keep-out areas) and label_pass_world.cpp (world-space labels), then
// lays out the placed labels' text for draw().
#include "label_pass.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <utility>

#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include "render_target.h"
#include "text/label_text_style.h"
#include "text_layer.h"

namespace navmap::render::gl {

namespace {

using Clock = std::chrono::steady_clock;
namespace nl = navmap::render::labels;

// Camera height above the ground it looks at: the rigs look at the vehicle on the terrain.
double cameraHeight(const Camera& c) { return c.eye.z - c.target.z; }

}  // namespace

LabelText::LabelText() : layer(std::make_unique<TextLayer>(engine.atlas())) {}

LabelText::~LabelText() = default;

LabelPass::LabelPass(std::shared_ptr<LabelText> text)
    : m_shared(std::move(text)), m_engine(m_shared->engine), m_text(*m_shared->layer) {}

LabelPass::~LabelPass() = default;

void LabelPass::layout(const MapFrame& frame, std::span<const TileLabels> tiles, glm::ivec2 viewport,
                       MapFrameStats& stats, std::span<const glm::vec2> marker, const MapStyle& style) {
    const auto t0 = Clock::now();
    beginFrame(frame, viewport);

    // seed 5.5: the space first, so the layout works on the boxes the labels are drawn in.
    const glm::dvec3 look = frame.camera.target - frame.camera.eye;
    const float tilt = nl::LabelSpaceSwitch::tiltDeg(glm::vec3(look), glm::vec3(0.0f, 0.0f, 1.0f));
    const double dt = std::isfinite(frame.frame_dt_s) && frame.frame_dt_s > 0.0 ? frame.frame_dt_s : 0.0;
    m_switch.update(tilt, static_cast<float>(cameraHeight(frame.camera)), dt);
    const bool world_layout = m_switch.space() == nl::LabelSpace::World;
    const glm::vec2 vp(viewport);
    collect(frame, tiles, viewport, world_layout);
    dropRepeatedStreets();
    inputChanges(frame, vp, stats);
    keepOut(frame, tiles, vp, marker, style);
    m_layout.setKeepOut(m_keep_out);
    m_layout.setFrame(
        m_candidates,
        nl::CameraState{tilt, vp, static_cast<float>(glm::length(frame.camera.target - frame.camera.eye))});
    m_layout.advance(dt);
    const float world = m_switch.worldWeight();

    const std::size_t visible = prepareDraws(frame, vp, world, stats);
    forgetFeatures();

    const auto out = m_layout.output();
    stats.label_candidates = m_candidates.size();
    stats.labels_too_small = m_too_small;
    stats.labels_visible = visible;
    stats.label_world_weight = world;
    stats.placed_labels.assign(out.begin(), out.end());
    stats.label_layout = m_layout.stats();
    stats.labels_ms = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

void LabelPass::beginFrame(const MapFrame& frame, glm::ivec2 viewport) {
    ++m_frame;
    const double aspect = static_cast<double>(viewport.x) / std::max(viewport.y, 1);
    m_projection = frame.camera.projection(aspect);
    m_eye = frame.camera.eye;
    // View space with the camera at the origin: world-space labels are positioned there.
    m_view = frame.camera.viewRelativeTo(m_eye);
    m_view_projection = m_projection * m_view;
    m_engine.beginFrame();
}

std::size_t LabelPass::prepareDraws(const MapFrame& frame, glm::vec2 vp, float world, MapFrameStats& stats) {
    // Text of the placed labels (quads must live until the draw calls).
    const auto out = m_layout.output();
    m_texts.clear();
    m_screen.clear();
    m_world.clear();
    m_world_drawn.clear();
    m_occluders.clear();
    m_texts.reserve(out.size());
    const text::AtlasParams& atlas = m_engine.atlas().params();
    const FrameDraw d{
        .frame = frame,
        .viewport = vp,
        .world = world,
        .spread_em = static_cast<float>(atlas.spread_px) / static_cast<float>(atlas.base_em_px),
        .focal_px = m_projection[1][1] * 0.5f * vp.y,
        .inverse_view = glm::inverse(m_view),
    };
    stats.drawn_labels.clear();
    std::size_t visible = 0;
    for (const nl::PlacedLabel& p : out) {
        if (p.state == nl::LabelState::FadingIn || p.state == nl::LabelState::Visible) ++visible;
        auto it = m_features.find(p.id);
        if (it == m_features.end()) continue;
        prepareLabel(d, p, it->second, stats);
    }
    m_world_drawn.resize(m_world.size(), std::numeric_limits<std::size_t>::max());
    return visible;
}

void LabelPass::prepareLabel(const FrameDraw& d, const nl::PlacedLabel& p, const Feature& f, MapFrameStats& stats) {
    const text::LabelTextStyle s = text::labelTextStyle(f.kind, f.subclass);
    const text::RunId run = m_engine.run(f.name, s.font);
    m_texts.push_back(s.icon.empty() ? m_engine.layout(run, s.size_px)
                                     : m_engine.layoutWithIcon(m_engine.run(s.icon, s.font), run, s.size_px));
    const text::LaidOutText& t = m_texts.back();
    const float angle = p.box.angle();
    // seed 5.5.1: the occluded label's depth for the aura; screen-space labels stand at their anchor.
    const glm::vec3 anchor_view = glm::vec3(m_view * glm::vec4(glm::vec3(f.anchor - m_eye), 1.0f));
    float occluder_depth = -anchor_view.z;
    labels::DrawnLabel drawn;
    std::size_t world_index = std::numeric_limits<std::size_t>::max();  // its entry of m_world
    drawn.id = p.id;
    drawn.text = f.name;
    drawn.kind = p.kind;
    drawn.opacity = p.alpha;
    drawn.anchor = p.anchor;
    drawn.center = p.box.center;
    // Labels without a world placement stay in screen space in a world-space layout.
    const bool screen_drawn = d.world < 1.0f || !f.world;
    if (screen_drawn) {
        const float screen_alpha = p.alpha * (f.world ? 1.0f - d.world : 1.0f);
        m_screen.push_back({t.quads, t.size_px, p.box.center, angle, p.scale, screen_alpha, s.style});
        drawn.cap_height_px = t.metrics.cap_height * p.scale;
        text::appendDrawnGlyphBoxes(t.quads, t.size_px, p.scale, angle, p.box.center, d.spread_em, s.style.outline_px,
                                    s.style.halo_px, drawn.glyph_boxes);
    }
    if (d.world > 0.0f && f.world && drawInWorld(d, p, f.plane, t, s.style, screen_drawn, drawn, occluder_depth)) {
        world_index = m_world.size() - 1;
    }
    if (occluder_depth > static_cast<float>(d.frame.camera.near_m)) {
        m_occluders.push_back({p.box, occluder_depth, p.alpha});
    }
    if (world_index < m_world.size()) {
        m_world_drawn.resize(m_world.size(), std::numeric_limits<std::size_t>::max());
        if (drawn.world_space && !drawn.glyph_boxes.empty()) m_world_drawn[world_index] = stats.drawn_labels.size();
    }
    if (!drawn.glyph_boxes.empty()) stats.drawn_labels.push_back(std::move(drawn));
}

void LabelPass::forgetFeatures() {
    // Forget features neither in this frame's input nor in the output any more.
    m_shown.clear();
    for (const nl::PlacedLabel& p : m_layout.output()) m_shown.push_back(p.id);  // output() is in id order
    for (auto it = m_features.begin(); it != m_features.end();) {
        const bool shown = std::ranges::binary_search(m_shown, it->first);
        if (it->second.frame != m_frame && !shown) {
            it = m_features.erase(it);
        } else {
            ++it;
        }
    }
}

void LabelPass::draw(glm::ivec2 viewport, MapFrameStats& stats) {
    const auto t0 = Clock::now();
    std::size_t glyphs = 0;
    if (!m_world.empty()) {
        m_text.drawWorld(m_world, m_view, m_projection, viewport);
        glyphs += m_text.stats().glyphs;
    }
    if (!m_screen.empty()) {
        m_text.drawScreen(m_screen, viewport);
        glyphs += m_text.stats().glyphs;
    }
    stats.label_glyphs = glyphs;
    stats.labels_ms += std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

void LabelPass::measureOcclusion(GLuint depth_stencil_rb, int samples, glm::ivec2 viewport, MapFrameStats& stats) {
    for (labels::DrawnLabel& d : stats.drawn_labels) d.occluded_fraction = d.world_space ? -1.0f : 0.0f;
    std::vector<text::WorldTextDraw> draws;
    std::vector<std::size_t> which;
    for (std::size_t i = 0; i < m_world.size(); ++i) {
        if (m_world_drawn[i] >= stats.drawn_labels.size()) continue;
        draws.push_back(m_world[i]);
        which.push_back(m_world_drawn[i]);
    }
    if (draws.empty()) return;
    // Each label's text in a colour naming it, drawn once over everything and once tested
    // against the scene's depth as the labels were: the share of its pixels that fail the
    // test is the share the scene hides.
    const auto [pixels_all, pixels_seen] =
        m_text.countIdPixels(draws, m_view, m_projection, viewport, depth_stencil_rb, samples);
    for (std::size_t k = 0; k < which.size(); ++k) {
        const std::uint64_t all = pixels_all[k + 1];
        labels::DrawnLabel& d = stats.drawn_labels[which[k]];
        d.occluded_fraction = all > 0 ? 1.0f - static_cast<float>(pixels_seen[k + 1]) / static_cast<float>(all) : 0.0f;
    }
}

}  // namespace navmap::render::gl
