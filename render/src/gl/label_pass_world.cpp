// SPDX-License-Identifier: Apache-2.0
// World-space labels of the label pass (seed 5.2.1): the plane each label stands in, its size
// and box on screen, its legibility and visibility over the terrain, and its text drawn there.
#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <span>

#include <glm/geometric.hpp>

#include "label_pass.h"
#include "label_pass_screen.h"

namespace navmap::render::gl {

namespace {

namespace nl = navmap::render::labels;

// Samples along a line of sight when testing world-space text against the terrain.
constexpr int kTerrainSightSteps = 32;

// The smallest oriented box with axis `axis` around `points` (screen pixels).
nl::OrientedBox boxAround(std::span<const glm::vec2> points, glm::vec2 axis) {
    const glm::vec2 normal(-axis.y, axis.x);
    glm::vec2 lo(std::numeric_limits<float>::max());
    glm::vec2 hi(std::numeric_limits<float>::lowest());
    for (const glm::vec2 p : points) {
        const glm::vec2 q(glm::dot(p, axis), glm::dot(p, normal));
        lo = glm::min(lo, q);
        hi = glm::max(hi, q);
    }
    const glm::vec2 mid = 0.5f * (lo + hi);
    return nl::OrientedBox{axis * mid.x + normal * mid.y, 0.5f * (hi - lo), axis};
}

}  // namespace

/// A label being fitted into the world by worldCandidate(): the projection, then the plane,
/// size and screen box found step by step. Eye-relative float coordinates: precise near the
/// camera, wherever the store's origin is.
struct LabelPass::WorldShape {
    glm::mat4 view_projection{1.0f};
    glm::vec2 viewport{0.0f};
    float near = 0.0f;
    glm::vec3 a{0.0f};  ///< the anchor
    // The plane (facePlane).
    bool along_road = false;
    glm::vec3 right{1.0f, 0.0f, 0.0f};
    glm::vec3 up{0.0f, 0.0f, 1.0f};
    glm::vec3 normal{0.0f, -1.0f, 0.0f};
    glm::vec2 pa{0.0f};  ///< the anchor on screen
    // The size (sizeInWorld).
    float focal_px = 0.0f;
    float lift = 0.0f;
    float em_m = 0.0f;
    float cap_px = 0.0f;
    // The text box (boxOnScreen).
    glm::vec2 half_m{0.0f};
    glm::vec3 center{0.0f};
    glm::vec2 corners[4];
    glm::vec2 axis{1.0f, 0.0f};

    bool project(glm::vec3 p, glm::vec2& out) const {
        const glm::vec4 clip = view_projection * glm::vec4(p, 1.0f);
        if (clip.w < near) return false;
        out = toScreen(clip, viewport);
        return true;
    }
};

double LabelPass::groundHeight(std::span<const TileLabels> tiles, double x, double y) {
    // The finest drawn tile under the point: what the terrain pass draws there.
    const TileLabels* best = nullptr;
    for (const TileLabels& t : tiles) {
        if (t.grid.size < 2 || !t.grid.heights) continue;
        if (x < t.origin.x || y < t.origin.y || x > t.origin.x + t.size_m || y > t.origin.y + t.size_m) continue;
        if (!best || t.size_m < best->size_m) best = &t;
    }
    return best ? best->grid.heightAt(x - best->origin.x, y - best->origin.y) : std::nan("");
}

bool LabelPass::behindTerrain(std::span<const TileLabels> tiles, const glm::vec3& target, float clearance_m) const {
    for (int k = 1; k <= kTerrainSightSteps; ++k) {
        // Denser near the eye, where a slope beside the road covers much of the view; up to 95 %
        // of the way: the text stands on the ground it names.
        const float u = static_cast<float>(k) / static_cast<float>(kTerrainSightSteps);
        const glm::vec3 p = target * (0.95f * u * u);
        const double ground = groundHeight(tiles, m_eye.x + p.x, m_eye.y + p.y);
        if (!std::isnan(ground) && m_eye.z + p.z < ground + clearance_m) return true;
    }
    return false;
}

LabelPass::WorldFit LabelPass::worldCandidate(const MapFrame& frame, std::span<const TileLabels> tiles,
                                              const glm::mat4& view_projection, glm::vec2 viewport,
                                              const glm::dvec3& anchor, const glm::dvec3& seg_a,
                                              const glm::dvec3& seg_b, const TextSize& t, Feature& f,
                                              nl::LabelCandidate& c) const {
    WorldShape w;
    w.view_projection = view_projection;
    w.viewport = viewport;
    w.near = static_cast<float>(frame.camera.near_m);
    w.a = glm::vec3(anchor - m_eye);
    // seed 5.2.1: a road name lies along the road in 3D, a place name stands across the view.
    w.along_road = c.kind == nl::LabelKind::Line;
    if (!facePlane(w, seg_a, seg_b) || !sizeInWorld(frame, t, w) || !boxOnScreen(t, f, w)) return WorldFit::Screen;
    // Too small to read: fades out; shown text stays down to world_min_cap_px, text coming in
    // needs world_enter_cap_px (no flicker at the edge of legibility).
    const bool staying = f.shown_world && !f.too_small;
    if (w.cap_px < (staying ? m_params.world_min_cap_px : m_params.world_enter_cap_px)) return WorldFit::TooSmall;
    if (hiddenByTerrain(tiles, f, w)) return WorldFit::Hidden;

    f.world = true;
    f.plane.origin = anchor;
    f.plane.right = w.right;
    f.plane.up = w.up;
    f.plane.normal = w.normal;
    f.plane.em_m = w.em_m;
    const nl::OrientedBox box = boxAround(w.corners, w.axis);
    c.size = 2.0f * box.half_extents;
    c.axis = w.axis;
    c.depth = 0.0f;  // perspective already sized it
    c.cap_height = w.cap_px;
    c.upright = true;
    if (!w.project(w.a, c.anchor)) return WorldFit::Screen;
    if (w.along_road) {
        c.line_p0 = w.pa;
        c.line_p1 = w.pa + w.axis * 10.0f;
    }
    return WorldFit::World;
}

bool LabelPass::facePlane(WorldShape& w, const glm::dvec3& seg_a, const glm::dvec3& seg_b) {
    const glm::vec3 to_eye = glm::normalize(-w.a);
    const glm::vec3 z(0.0f, 0.0f, 1.0f);
    glm::vec3 right;
    if (w.along_road) {
        const glm::dvec3 d = seg_b - seg_a;
        if (glm::length(d) < 1.0) {
            w.along_road = false;
        } else {
            right = glm::normalize(glm::vec3(d));
        }
    }
    if (!w.along_road) {
        right = glm::cross(z, to_eye);
        if (glm::length(right) < 1e-3f) return false;  // right above it: no upright plane faces the camera
        right = glm::normalize(right);
    }
    // The plane turns about its baseline to face the camera (an axial billboard): the glyphs
    // keep their height on screen, the baseline keeps the road's direction.
    glm::vec3 up = glm::cross(to_eye - glm::dot(to_eye, right) * right, right);
    if (glm::length(up) < 1e-3f) return false;  // the baseline points at the camera
    up = glm::normalize(up);
    if (up.z < 0.0f) up = -up;
    // Reads left to right on screen.
    glm::vec2 pb;
    if (!w.project(w.a, w.pa) || !w.project(w.a + right, pb)) return false;
    if (pb.x < w.pa.x) right = -right;
    w.right = right;
    w.up = up;
    w.normal = glm::normalize(glm::cross(right, up));
    return true;
}

bool LabelPass::sizeInWorld(const MapFrame& frame, const TextSize& t, WorldShape& w) const {
    // World size: the style's pixel size at world_reach times the camera's look-at distance
    // (seed 4.3.3's depth reference), in true perspective: farther text is smaller. Only near
    // text is capped, at world_max_cap_ratio times the style's cap height (it would fill the
    // screen); far text whose cap height, where perspective makes it smallest, falls under
    // world_min_cap_px is not drawn unreadable (seed 5.1): it fades out (WorldFit::TooSmall).
    w.focal_px = m_projection[1][1] * 0.5f * w.viewport.y;
    const auto reference_m = t.world_reach * static_cast<float>(glm::length(frame.camera.target - frame.camera.eye));
    w.lift = static_cast<float>(m_params.world_lift_m);
    float em_m = t.size_px * reference_m / w.focal_px;
    float cap_px = 0.0f;
    if (!measureCap(t, w, em_m, cap_px)) return false;
    const float max_cap = std::max(m_params.world_min_cap_px, m_params.world_max_cap_ratio * t.cap_height);
    if (cap_px > max_cap) {
        em_m *= max_cap / cap_px;
        if (!measureCap(t, w, em_m, cap_px)) return false;
    }
    w.em_m = em_m;
    w.cap_px = cap_px;
    return true;
}

bool LabelPass::measureCap(const TextSize& t, const WorldShape& w, float em, float& cap) {
    const float mpp = em / t.size_px;
    const glm::vec2 hm = 0.5f * t.size * mpp;
    const glm::vec3 mid = w.a + w.up * (w.lift + hm.y);
    cap = std::numeric_limits<float>::max();
    for (const float side : {-1.0f, 1.0f}) {
        const glm::vec3 foot = mid + w.right * (side * hm.x);
        glm::vec2 p0, p1;
        if (!w.project(foot, p0) || !w.project(foot + w.up * (t.cap_height * mpp), p1)) return false;
        cap = std::min(cap, glm::length(p1 - p0));
    }
    return cap > 0.0f;
}

bool LabelPass::boxOnScreen(const TextSize& t, const Feature& f, WorldShape& w) const {
    const float metres_per_px = w.em_m / t.size_px;
    const glm::vec2 half_m = 0.5f * t.size * metres_per_px;
    const glm::vec3 center = w.a + w.up * (w.lift + half_m.y);  // standing on the ground at the anchor
    const glm::vec2 signs[4] = {{-1, -1}, {1, -1}, {1, 1}, {-1, 1}};
    for (int k = 0; k < 4; ++k) {
        if (!w.project(center + w.right * (signs[k].x * half_m.x) + w.up * (signs[k].y * half_m.y), w.corners[k]))
            return false;
    }
    const glm::vec2 baseline = 0.5f * ((w.corners[1] + w.corners[2]) - (w.corners[0] + w.corners[3]));
    if (!(glm::length(baseline) > 1.0f)) return false;
    const glm::vec2 axis = glm::normalize(baseline);
    if (w.along_road) {
        const float angle = std::abs(std::atan2(axis.y, axis.x)) * 180.0f / std::numbers::pi_v<float>;
        const float facing = 2.0f * half_m.x * w.focal_px / glm::length(center);
        // Text shown in the world stays until the limits; text coming in needs a margin (no
        // flicker between world and screen space on a winding road).
        const float enter = f.shown_world ? 1.0f : 1.1f;
        if (angle * enter > m_params.world_max_screen_angle_deg ||
            glm::length(baseline) < enter * m_params.world_min_foreshortening * facing) {
            return false;
        }
    }
    w.half_m = half_m;
    w.center = center;
    w.axis = axis;
    return true;
}

bool LabelPass::hiddenByTerrain(std::span<const TileLabels> tiles, const Feature& f, const WorldShape& w) const {
    // Text behind a hill cannot be read, and the aura fades only buildings (seed 5.5.1): lines
    // of sight to a grid of points over the text box must pass above the drawn terrain. A label
    // comes in only with a margin of clear sky around its text (hysteresis against flicker).
    // The lines of sight keep a clearance above the grid: the drawn surface is morphed towards
    // coarser levels with distance (terrain LOD), which can stand a few metres higher.
    const float reach = f.shown_world ? 1.0f : 1.25f;
    const float clearance = f.shown_world ? m_params.terrain_clearance_m : 2.0f * m_params.terrain_clearance_m;
    bool hidden = false;
    for (const float sx : {-0.9f, -0.3f, 0.3f, 0.9f}) {
        for (const float sy : {-0.6f, 0.6f}) {
            hidden =
                hidden ||
                behindTerrain(tiles, w.center + w.right * (reach * sx * w.half_m.x) + w.up * (reach * sy * w.half_m.y),
                              clearance);
        }
    }
    return hidden;
}

bool LabelPass::drawInWorld(const FrameDraw& d, const nl::PlacedLabel& p, const WorldPlane& pl,
                            const text::LaidOutText& t, const text::TextStyle& style, bool screen_drawn,
                            nl::DrawnLabel& drawn, float& occluder_depth) {
    // seed 5.2.1: the text lies in its plane where the layout box's center is seen.
    const glm::vec2 vp = d.viewport;
    const glm::vec2 ndc(p.box.center.x / vp.x * 2.0f - 1.0f, 1.0f - p.box.center.y / vp.y * 2.0f);
    const glm::vec3 ray =
        glm::vec3(d.inverse_view * glm::vec4(ndc.x / m_projection[0][0], ndc.y / m_projection[1][1], -1.0f, 0.0f));
    const glm::vec3 origin(pl.origin - m_eye);
    const float denom = glm::dot(pl.normal, ray);
    const float hit = std::abs(denom) > 1e-6f ? glm::dot(pl.normal, origin) / denom : -1.0f;
    if (!(hit > 0.0f)) return false;
    const glm::vec3 center = ray * hit;
    const float depth = -(m_view * glm::vec4(center, 1.0f)).z;
    if (!(depth > static_cast<float>(d.frame.camera.near_m))) return false;
    text::WorldTextDraw wd;
    wd.quads = t.quads;
    wd.size_px = t.size_px;
    // Pulled towards the eye like the roads and the route (seed 3.6.2: view-space
    // scale 1 - alpha), so the roads drawn over the ground do not cut the text
    // standing on it; position and size scale together, the picture is the same.
    const float pull = 1.0f - m_params.world_depth_pull;
    wd.position = center * pull;
    wd.right = pl.right;
    wd.up = pl.up;
    wd.em_m = pl.em_m * pull;
    wd.alpha = p.alpha * d.world;
    wd.style = style;
    m_world.push_back(wd);
    occluder_depth = depth;
    if (d.world >= 0.5f || !screen_drawn) {
        // What the frame shows of it is this world-space text.
        worldGlyphBoxes(d, center, depth, pl, t, style, drawn);
    }
    return true;
}

void LabelPass::worldGlyphBoxes(const FrameDraw& d, const glm::vec3& center, float depth, const WorldPlane& pl,
                                const text::LaidOutText& t, const text::TextStyle& style, nl::DrawnLabel& drawn) const {
    const glm::vec2 vp = d.viewport;
    drawn.world_space = true;
    drawn.glyph_boxes.clear();
    const float metres_per_px = pl.em_m / t.size_px;
    const float em_px = pl.em_m * d.focal_px / depth;
    const float inset =
        text::drawnGlyphInsetPx(em_px, d.spread_em, style.outline_px, style.halo_px, em_px / t.size_px) * t.size_px /
        em_px;  // screen px back to quad px
    auto project = [&](glm::vec2 local) {
        const glm::vec3 w = center + (pl.right * local.x - pl.up * local.y) * metres_per_px;
        return toScreen(m_view_projection * glm::vec4(w, 1.0f), vp);
    };
    for (const text::GlyphQuad& q : t.quads) {
        const glm::vec2 lo = q.p0 + inset, hi = q.p1 - inset;
        if (!(hi.x > lo.x && hi.y > lo.y)) continue;
        drawn.glyph_boxes.push_back({project(lo), project({hi.x, lo.y}), project(hi), project({lo.x, hi.y})});
    }
    const float cap_m = t.metrics.cap_height * metres_per_px;
    const float half_w = 0.5f * t.metrics.width * metres_per_px;
    const float baseline_down = (0.5f * (t.metrics.ascent - t.metrics.descent)) * metres_per_px;
    drawn.cap_height_px = std::numeric_limits<float>::max();
    for (const float side : {-1.0f, 1.0f}) {
        const glm::vec3 foot = center + pl.right * (side * half_w) - pl.up * baseline_down;
        const glm::vec2 a = toScreen(m_view_projection * glm::vec4(foot, 1.0f), vp);
        const glm::vec2 b = toScreen(m_view_projection * glm::vec4(foot + pl.up * cap_m, 1.0f), vp);
        drawn.cap_height_px = std::min(drawn.cap_height_px, glm::length(b - a));
    }
}

}  // namespace navmap::render::gl
