#include "label_pass.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <string>
#include <utility>

#include "navmap/render/text/label_text_style.h"
#include "text_layer.h"

namespace navmap::render::gl {

namespace {

using Clock = std::chrono::steady_clock;
namespace nl = navmap::render::labels;

nl::LabelKind layoutKind(map::LabelKind kind) {
    switch (kind) {
        case map::LabelKind::Road: return nl::LabelKind::Line;
        case map::LabelKind::Area: return nl::LabelKind::Area;
        case map::LabelKind::Place:
        case map::LabelKind::Poi: break;
    }
    return nl::LabelKind::Point;
}

std::uint64_t fnv1a(std::uint64_t h, const void* data, std::size_t n) {
    const auto* p = static_cast<const unsigned char*>(data);
    for (std::size_t i = 0; i < n; ++i) {
        h ^= p[i];
        h *= 1099511628211ULL;
    }
    return h;
}

// Camera height above the ground it looks at: the rigs look at the vehicle on the terrain.
double cameraHeight(const Camera& c) { return c.eye.z - c.target.z; }

}  // namespace

std::vector<glm::vec3> labelPoints(const map::Tile& tile, const HeightGrid& grid) {
    std::vector<glm::vec3> out;
    out.reserve(tile.labels.size() * 3);
    auto at = [&](const map::LocalPoint& p) {
        const double z = grid.size >= 2 && grid.heights ? grid.heightAt(p.x, p.y) : 0.0;
        return glm::vec3(p.x, p.y, static_cast<float>(z));
    };
    for (const map::Label& l : tile.labels) {
        out.push_back(at(l.anchor));
        out.push_back(at(l.segment_start));
        out.push_back(at(l.segment_end));
    }
    return out;
}

std::uint64_t labelId(const map::Label& label, const glm::dvec3& anchor_store) {
    const auto kind = static_cast<std::uint64_t>(label.kind);
    if (label.osm_id != 0) {
        // OSM ids are unique per element type; the kind keeps a road name and a place of the
        // same id apart. Bit 63 marks OSM-based ids.
        return (static_cast<std::uint64_t>(label.osm_id) << 3 | kind) | (1ULL << 63);
    }
    std::uint64_t h = 14695981039346656037ULL;
    h = fnv1a(h, label.name.data(), label.name.size());
    const std::int64_t q[2] = {std::llround(anchor_store.x), std::llround(anchor_store.y)};
    h = fnv1a(h, q, sizeof q);
    return ((h << 3) | kind) & ~(1ULL << 63);
}

LabelText::LabelText() : layer(std::make_unique<TextLayer>(engine.atlas())) {}

LabelText::~LabelText() = default;

LabelPass::LabelPass(std::shared_ptr<LabelText> text)
    : m_shared(std::move(text)), m_engine(m_shared->engine), m_text(*m_shared->layer) {}

LabelPass::~LabelPass() = default;

glm::vec2 LabelPass::labelSize(std::uint64_t id, const map::Label& label) {
    if (auto it = m_sizes.find(id); it != m_sizes.end()) return it->second;
    if (m_sizes.size() > 50000) m_sizes.clear();  // bounded; sizes are recomputed on demand
    const text::LabelTextStyle s = text::labelTextStyle(label.kind, label.subclass);
    const text::RunId run = m_engine.run(label.name, s.font);
    glm::vec2 size;
    if (s.icon.empty()) {
        const text::TextMetrics m = m_engine.measure(run, s.size_px);
        size = {m.width, m.height};
    } else {
        const text::LaidOutText t = m_engine.layoutWithIcon(m_engine.run(s.icon, s.font), run, s.size_px);
        size = {t.metrics.width, t.metrics.height};
    }
    m_sizes.emplace(id, size);
    return size;
}

void LabelPass::collect(const MapFrame& frame, std::span<const TileLabels> tiles, glm::ivec2 viewport) {
    m_candidates.clear();
    const glm::vec2 vp(viewport);
    const auto near = static_cast<float>(frame.camera.near_m);
    auto toScreen = [&](const glm::vec4& clip) {
        const glm::vec2 ndc = glm::vec2(clip) / clip.w;
        return glm::vec2((ndc.x * 0.5f + 0.5f) * vp.x, (0.5f - ndc.y * 0.5f) * vp.y);
    };
    for (const TileLabels& t : tiles) {
        if (!t.tile || t.points.size() != t.tile->labels.size() * 3) continue;
        const glm::mat4 vp_tile = m_projection * frame.camera.viewRelativeTo(t.origin);
        for (std::size_t i = 0; i < t.tile->labels.size(); ++i) {
            const map::Label& l = t.tile->labels[i];
            if (l.name.empty()) continue;
            const glm::vec4 clip = vp_tile * glm::vec4(t.points[3 * i], 1.0f);
            if (clip.w < near) continue;
            const glm::vec2 px = toScreen(clip);
            if (!(px.x >= 0.0f && px.y >= 0.0f && px.x <= vp.x && px.y <= vp.y)) continue;
            const glm::dvec3 anchor = t.origin + glm::dvec3(t.points[3 * i]);
            const std::uint64_t id = labelId(l, anchor);
            auto [it, inserted] = m_features.try_emplace(id);
            if (!inserted && it->second.frame == m_frame) continue;  // same feature in two tiles
            Feature& f = it->second;
            if (inserted) {
                f.name = l.name;
                f.kind = l.kind;
                f.subclass = l.subclass;
            }
            f.anchor = anchor;
            f.frame = m_frame;
            nl::LabelCandidate c;
            c.id = id;
            c.priority = std::clamp(l.importance, 0.0f, 1.0f);
            c.kind = layoutKind(l.kind);
            c.anchor = px;
            c.depth = clip.w;
            c.size = labelSize(id, l);
            if (c.kind == nl::LabelKind::Line) {
                const glm::vec4 a = vp_tile * glm::vec4(t.points[3 * i + 1], 1.0f);
                const glm::vec4 b = vp_tile * glm::vec4(t.points[3 * i + 2], 1.0f);
                if (a.w >= near && b.w >= near) {
                    c.line_p0 = toScreen(a);
                    c.line_p1 = toScreen(b);
                }
                // A segment shorter than a pixel on screen has no direction: label it as a point.
                if (!(glm::length(c.line_p1 - c.line_p0) >= 1.0f)) c.kind = nl::LabelKind::Point;
            }
            m_candidates.push_back(c);
        }
    }
}

void LabelPass::layout(const MapFrame& frame, std::span<const TileLabels> tiles, glm::ivec2 viewport,
                       MapFrameStats& stats) {
    const auto t0 = Clock::now();
    ++m_frame;
    const double aspect = static_cast<double>(viewport.x) / std::max(viewport.y, 1);
    m_projection = frame.camera.projection(aspect);
    m_engine.beginFrame();
    collect(frame, tiles, viewport);

    const glm::dvec3 look = frame.camera.target - frame.camera.eye;
    const float tilt = nl::LabelSpaceSwitch::tiltDeg(glm::vec3(look), glm::vec3(0.0f, 0.0f, 1.0f));
    m_layout.setFrame(m_candidates, nl::CameraState{tilt, glm::vec2(viewport)});
    const double dt = std::isfinite(frame.frame_dt_s) && frame.frame_dt_s > 0.0 ? frame.frame_dt_s : 0.0;
    m_layout.advance(dt);
    m_switch.update(tilt, static_cast<float>(cameraHeight(frame.camera)), dt);
    const float world = m_switch.worldWeight();

    // Text of the placed labels (quads must live until the draw calls).
    const auto out = m_layout.output();
    m_texts.clear();
    m_screen.clear();
    m_world.clear();
    m_occluders.clear();
    m_texts.reserve(out.size());
    // View space with the camera at the origin: world-space labels are positioned there.
    const glm::mat4 view = frame.camera.viewRelativeTo(frame.camera.eye);
    const glm::vec2 vp(viewport);
    std::size_t visible = 0;
    for (const nl::PlacedLabel& p : out) {
        if (p.state == nl::LabelState::FadingIn || p.state == nl::LabelState::Visible) ++visible;
        auto it = m_features.find(p.id);
        if (it == m_features.end()) continue;
        const Feature& f = it->second;
        const text::LabelTextStyle s = text::labelTextStyle(f.kind, f.subclass);
        const text::RunId run = m_engine.run(f.name, s.font);
        m_texts.push_back(s.icon.empty() ? m_engine.layout(run, s.size_px)
                                         : m_engine.layoutWithIcon(m_engine.run(s.icon, s.font), run, s.size_px));
        const text::LaidOutText& t = m_texts.back();
        const float angle = p.box.angle();
        // seed 5.5.1: the occluded label's depth for the aura; screen-space labels stand at their anchor.
        const glm::vec3 anchor_view = glm::vec3(view * glm::vec4(glm::vec3(f.anchor - frame.camera.eye), 1.0f));
        float occluder_depth = -anchor_view.z;
        if (world < 1.0f) {
            m_screen.push_back({t.quads, t.size_px, p.box.center, angle, p.scale, p.alpha * (1.0f - world), s.style});
        }
        if (world > 0.0f) {
            // Seed 5.2.1 / 5.5: the label lies in the scene at its anchor's depth, so buildings
            // and terrain in front hide it. It is pulled a little towards the camera so the
            // ground it stands on does not cut its lower half.
            glm::vec3 a = glm::vec3(view * glm::vec4(glm::vec3(f.anchor - frame.camera.eye), 1.0f));
            const float dist = -a.z;
            if (!(dist > static_cast<float>(frame.camera.near_m))) continue;
            const float pull = std::min(30.0f, 0.1f * dist);
            a *= (dist - pull) / dist;
            const float w = -a.z;
            // Same screen position and size as the layout box: offset from the anchor in view
            // space at depth w, em size fixed to the layout's scale.
            const glm::vec2 d = p.box.center - p.anchor;
            a.x += d.x * 2.0f / vp.x * w / m_projection[0][0];
            a.y -= d.y * 2.0f / vp.y * w / m_projection[1][1];
            text::WorldTextDraw wd;
            wd.quads = t.quads;
            wd.size_px = t.size_px;
            wd.position = a;
            wd.world_em_m = 1.0f;
            wd.min_px = wd.max_px = t.size_px * p.scale;
            wd.angle_rad = angle;
            wd.alpha = p.alpha * world;
            wd.style = s.style;
            m_world.push_back(wd);
            occluder_depth = w;
        }
        if (occluder_depth > static_cast<float>(frame.camera.near_m)) {
            m_occluders.push_back({p.box, occluder_depth, p.alpha});
        }
    }
    // Forget features neither in this frame's input nor in the output any more.
    for (auto it = m_features.begin(); it != m_features.end();) {
        const bool shown = std::ranges::binary_search(out, it->first, {}, &nl::PlacedLabel::id);
        if (it->second.frame != m_frame && !shown) {
            it = m_features.erase(it);
        } else {
            ++it;
        }
    }

    stats.label_candidates = m_candidates.size();
    stats.labels_visible = visible;
    stats.label_world_weight = world;
    stats.placed_labels.assign(out.begin(), out.end());
    stats.labels_ms = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

void LabelPass::draw(glm::ivec2 viewport, MapFrameStats& stats) {
    const auto t0 = Clock::now();
    std::size_t glyphs = 0;
    if (!m_world.empty()) {
        m_text.drawWorld(m_world, glm::mat4(1.0f), m_projection, viewport);
        glyphs += m_text.stats().glyphs;
    }
    if (!m_screen.empty()) {
        m_text.drawScreen(m_screen, viewport);
        glyphs += m_text.stats().glyphs;
    }
    stats.label_glyphs = glyphs;
    stats.labels_ms += std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

}  // namespace navmap::render::gl
