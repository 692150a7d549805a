// SPDX-License-Identifier: Apache-2.0
#include "label_pass.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <numbers>
#include <string>
#include <unordered_map>
#include <utility>

#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include "navmap/render/maneuver_arrow.h"
#include "render_target.h"
#include "text/label_text_style.h"
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

// Samples along a line of sight when testing world-space text against the terrain.
constexpr int kTerrainSightSteps = 32;

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

// Clip coordinates to screen pixels (origin top left, y down).
glm::vec2 toScreen(const glm::vec4& clip, glm::vec2 viewport) {
    const glm::vec2 ndc = glm::vec2(clip) / clip.w;
    return {(ndc.x * 0.5f + 0.5f) * viewport.x, (0.5f - ndc.y * 0.5f) * viewport.y};
}

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

const LabelPass::TextSize& LabelPass::textSize(std::uint64_t id, const map::Label& label) {
    if (auto it = m_sizes.find(id); it != m_sizes.end()) return it->second;
    if (m_sizes.size() > 50000) m_sizes.clear();  // bounded; sizes are recomputed on demand
    const text::LabelTextStyle s = text::labelTextStyle(label.kind, label.subclass);
    const text::RunId run = m_engine.run(label.name, s.font);
    text::TextMetrics m;
    if (s.icon.empty()) {
        m = m_engine.measure(run, s.size_px);
    } else {
        m = m_engine.layoutWithIcon(m_engine.run(s.icon, s.font), run, s.size_px).metrics;
    }
    // The box the layout keeps free holds the drawn outline and halo too (text_sdf.vert draws
    // them out to the atlas spread less a pixel), plus a pixel of antialiasing.
    const text::AtlasParams& atlas = m_engine.atlas().params();
    const float spread = static_cast<float>(atlas.spread_px) / static_cast<float>(atlas.base_em_px) * s.size_px;
    TextSize t;
    t.margin = std::min(s.style.outline_px + s.style.halo_px, std::max(spread - 1.0f, 0.0f)) + 1.0f;
    t.size = glm::vec2(m.width, m.height) + 2.0f * t.margin;
    t.cap_height = m.cap_height;
    t.size_px = s.size_px;
    t.world_reach = s.world_reach;
    return m_sizes.emplace(id, t).first->second;
}

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
    // Eye-relative float coordinates: precise near the camera, wherever the store's origin is.
    const glm::vec3 a(anchor - m_eye);
    const float near = static_cast<float>(frame.camera.near_m);
    auto project = [&](glm::vec3 p, glm::vec2& out) {
        const glm::vec4 clip = view_projection * glm::vec4(p, 1.0f);
        if (clip.w < near) return false;
        out = toScreen(clip, viewport);
        return true;
    };
    const glm::vec3 to_eye = glm::normalize(-a);
    const glm::vec3 z(0.0f, 0.0f, 1.0f);
    // seed 5.2.1: a road name lies along the road in 3D, a place name stands across the view.
    bool along_road = c.kind == nl::LabelKind::Line;
    glm::vec3 right;
    if (along_road) {
        const glm::dvec3 d = seg_b - seg_a;
        if (glm::length(d) < 1.0) {
            along_road = false;
        } else {
            right = glm::normalize(glm::vec3(d));
        }
    }
    if (!along_road) {
        right = glm::cross(z, to_eye);
        if (glm::length(right) < 1e-3f) return WorldFit::Screen;  // right above it: no upright plane faces the camera
        right = glm::normalize(right);
    }
    // The plane turns about its baseline to face the camera (an axial billboard): the glyphs
    // keep their height on screen, the baseline keeps the road's direction.
    glm::vec3 up = glm::cross(to_eye - glm::dot(to_eye, right) * right, right);
    if (glm::length(up) < 1e-3f) return WorldFit::Screen;  // the baseline points at the camera
    up = glm::normalize(up);
    if (up.z < 0.0f) up = -up;
    // Reads left to right on screen.
    glm::vec2 pa, pb;
    if (!project(a, pa) || !project(a + right, pb)) return WorldFit::Screen;
    if (pb.x < pa.x) right = -right;
    const glm::vec3 normal = glm::normalize(glm::cross(right, up));

    // World size: the style's pixel size at world_reach times the camera's look-at distance
    // (seed 4.3.3's depth reference), in true perspective: farther text is smaller. Only near
    // text is capped, at world_max_cap_ratio times the style's cap height (it would fill the
    // screen); far text whose cap height, where perspective makes it smallest, falls under
    // world_min_cap_px is not drawn unreadable (seed 5.1): it fades out (WorldFit::TooSmall).
    const float focal_px = m_projection[1][1] * 0.5f * viewport.y;
    const auto reference_m = t.world_reach * static_cast<float>(glm::length(frame.camera.target - frame.camera.eye));
    const float lift = static_cast<float>(m_params.world_lift_m);
    auto measure_cap = [&](float em, float& cap) {
        const float mpp = em / t.size_px;
        const glm::vec2 hm = 0.5f * t.size * mpp;
        const glm::vec3 mid = a + up * (lift + hm.y);
        cap = std::numeric_limits<float>::max();
        for (const float side : {-1.0f, 1.0f}) {
            const glm::vec3 foot = mid + right * (side * hm.x);
            glm::vec2 p0, p1;
            if (!project(foot, p0) || !project(foot + up * (t.cap_height * mpp), p1)) return false;
            cap = std::min(cap, glm::length(p1 - p0));
        }
        return cap > 0.0f;
    };
    float em_m = t.size_px * reference_m / focal_px;
    float cap_px = 0.0f;
    if (!measure_cap(em_m, cap_px)) return WorldFit::Screen;
    const float max_cap = std::max(m_params.world_min_cap_px, m_params.world_max_cap_ratio * t.cap_height);
    if (cap_px > max_cap) {
        em_m *= max_cap / cap_px;
        if (!measure_cap(em_m, cap_px)) return WorldFit::Screen;
    }
    const float metres_per_px = em_m / t.size_px;
    const glm::vec2 half_m = 0.5f * t.size * metres_per_px;
    const glm::vec3 center = a + up * (lift + half_m.y);  // standing on the ground at the anchor
    glm::vec2 corners[4];
    const glm::vec2 signs[4] = {{-1, -1}, {1, -1}, {1, 1}, {-1, 1}};
    for (int k = 0; k < 4; ++k) {
        if (!project(center + right * (signs[k].x * half_m.x) + up * (signs[k].y * half_m.y), corners[k]))
            return WorldFit::Screen;
    }
    const glm::vec2 baseline = 0.5f * ((corners[1] + corners[2]) - (corners[0] + corners[3]));
    if (!(glm::length(baseline) > 1.0f)) return WorldFit::Screen;
    const glm::vec2 axis = glm::normalize(baseline);
    if (along_road) {
        const float angle = std::abs(std::atan2(axis.y, axis.x)) * 180.0f / std::numbers::pi_v<float>;
        const float facing = 2.0f * half_m.x * focal_px / glm::length(center);
        // Text shown in the world stays until the limits; text coming in needs a margin (no
        // flicker between world and screen space on a winding road).
        const float enter = f.shown_world ? 1.0f : 1.1f;
        if (angle * enter > m_params.world_max_screen_angle_deg ||
            glm::length(baseline) < enter * m_params.world_min_foreshortening * facing) {
            return WorldFit::Screen;
        }
    }
    // Too small to read: fades out; shown text stays down to world_min_cap_px, text coming in
    // needs world_enter_cap_px (no flicker at the edge of legibility).
    const bool staying = f.shown_world && !f.too_small;
    if (cap_px < (staying ? m_params.world_min_cap_px : m_params.world_enter_cap_px)) return WorldFit::TooSmall;
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
                hidden || behindTerrain(tiles, center + right * (reach * sx * half_m.x) + up * (reach * sy * half_m.y),
                                        clearance);
        }
    }
    if (hidden) return WorldFit::Hidden;

    f.world = true;
    f.plane.origin = anchor;
    f.plane.right = right;
    f.plane.up = up;
    f.plane.normal = normal;
    f.plane.em_m = em_m;
    const nl::OrientedBox box = boxAround(corners, axis);
    c.size = 2.0f * box.half_extents;
    c.axis = axis;
    c.depth = 0.0f;  // perspective already sized it
    c.cap_height = cap_px;
    c.upright = true;
    if (!project(a, c.anchor)) return WorldFit::Screen;
    if (along_road) {
        c.line_p0 = pa;
        c.line_p1 = pa + axis * 10.0f;
    }
    return WorldFit::World;
}

void LabelPass::collect(const MapFrame& frame, std::span<const TileLabels> tiles, glm::ivec2 viewport, bool world) {
    m_candidates.clear();
    m_too_small = 0;
    const glm::vec2 vp(viewport);
    const auto near = static_cast<float>(frame.camera.near_m);
    // Finest tiles first: a feature in several tiles (a long road, a tile and its coarser
    // neighbour) takes its anchor and segment from the most detailed one.
    m_tile_order.resize(tiles.size());
    for (std::size_t k = 0; k < tiles.size(); ++k) m_tile_order[k] = k;
    std::ranges::stable_sort(m_tile_order,
                             [&](std::size_t x, std::size_t y) { return tiles[x].size_m < tiles[y].size_m; });
    for (const std::size_t k : m_tile_order) {
        const TileLabels& t = tiles[k];
        if (!t.tile || t.points.size() != t.tile->labels.size() * 3) continue;
        const glm::mat4 vp_tile = m_projection * frame.camera.viewRelativeTo(t.origin);
        for (std::size_t i = 0; i < t.tile->labels.size(); ++i) {
            const map::Label& l = t.tile->labels[i];
            if (l.name.empty()) continue;
            const glm::vec4 clip = vp_tile * glm::vec4(t.points[3 * i], 1.0f);
            if (clip.w < near) continue;
            const glm::vec2 px = toScreen(clip, vp);
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
            const bool shown = std::ranges::binary_search(m_shown, id);
            f.shown_world = f.world && shown;
            f.shown_screen = !f.world && shown;
            f.world = false;
            const TextSize& size = textSize(id, l);
            nl::LabelCandidate c;
            c.id = id;
            c.priority = std::clamp(l.importance, 0.0f, 1.0f);
            c.kind = layoutKind(l.kind);
            c.anchor = px;
            c.depth = clip.w;
            c.size = size.size;
            c.cap_height = size.cap_height;
            if (world) {
                // Road names stand on the middle of their longest straight piece, along it.
                // On the finest drawn terrain: the tile that carried the label may be a coarser one.
                auto on_ground = [&](glm::dvec3 p) {
                    const double z = groundHeight(tiles, p.x, p.y);
                    if (!std::isnan(z)) p.z = z;
                    return p;
                };
                const glm::dvec3 a = on_ground(t.origin + glm::dvec3(t.points[3 * i + 1]));
                const glm::dvec3 b = on_ground(t.origin + glm::dvec3(t.points[3 * i + 2]));
                const glm::dvec3 at = c.kind == nl::LabelKind::Line && glm::length(b - a) >= 1.0
                                          ? on_ground(0.5 * (a + b))
                                          : on_ground(anchor);
                const WorldFit fit = worldCandidate(frame, tiles, m_view_projection, vp, at, a, b, size, f, c);
                if (fit == WorldFit::Hidden || fit == WorldFit::TooSmall) {
                    // Not a candidate: the layout fades it out, in the world where it was shown.
                    f.world = f.shown_world;
                    f.too_small = fit == WorldFit::TooSmall;
                    m_too_small += f.too_small;
                    f.out_frame = m_frame;
                    f.out_cause = f.too_small ? nl::InputCause::TooSmall : nl::InputCause::Hidden;
                    continue;
                }
                f.too_small = false;
                if (fit == WorldFit::Screen) {
                    // Text that cannot be read in the world (far away, end-on) is shown as in the
                    // bird's-eye view, unless a hill stands in front of its anchor (with hysteresis:
                    // it comes in when a point 1 m above the anchor is in sight, stays while 4 m is).
                    const float lift = f.shown_screen ? 4.0f : 1.0f;
                    if (behindTerrain(tiles, glm::vec3(anchor - m_eye) + glm::vec3(0.0f, 0.0f, lift), -0.5f)) {
                        f.out_frame = m_frame;
                        f.out_cause = nl::InputCause::Hidden;
                        continue;
                    }
                }
            }
            if (!f.world && c.kind == nl::LabelKind::Line) {
                const glm::vec4 a = vp_tile * glm::vec4(t.points[3 * i + 1], 1.0f);
                const glm::vec4 b = vp_tile * glm::vec4(t.points[3 * i + 2], 1.0f);
                if (a.w >= near && b.w >= near) {
                    c.line_p0 = toScreen(a, vp);
                    c.line_p1 = toScreen(b, vp);
                }
                // A segment shorter than a pixel on screen has no direction: label it as a point.
                if (!(glm::length(c.line_p1 - c.line_p0) >= 1.0f)) c.kind = nl::LabelKind::Point;
            }
            m_candidates.push_back(c);
        }
    }
}

void LabelPass::dropRepeatedStreets() {
    // Road candidates in keeping order: on screen now first (the way that carries the name keeps
    // it), then by importance, then by id.
    std::vector<std::size_t> roads;
    for (std::size_t i = 0; i < m_candidates.size(); ++i) {
        if (m_features.at(m_candidates[i].id).kind == map::LabelKind::Road) roads.push_back(i);
    }
    if (roads.size() < 2) return;
    const auto shown = [&](std::size_t i) { return std::ranges::binary_search(m_shown, m_candidates[i].id); };
    std::sort(roads.begin(), roads.end(), [&](std::size_t a, std::size_t b) {
        const bool sa = shown(a), sb = shown(b);
        if (sa != sb) return sa;
        const auto& x = m_candidates[a];
        const auto& y = m_candidates[b];
        return x.priority != y.priority ? x.priority > y.priority : x.id < y.id;
    });
    std::unordered_map<std::string_view, std::vector<glm::dvec3>> kept;
    std::vector<std::uint8_t> drop(m_candidates.size(), 0);
    const double r2 = m_params.street_repeat_m * m_params.street_repeat_m;
    for (const std::size_t i : roads) {
        const Feature& f = m_features.at(m_candidates[i].id);
        auto& anchors = kept[f.name];
        const bool near_one = std::any_of(anchors.begin(), anchors.end(), [&](const glm::dvec3& a) {
            const glm::dvec2 d = glm::dvec2(a - f.anchor);
            return glm::dot(d, d) < r2;
        });
        if (near_one) {
            drop[i] = 1;
            m_features.at(m_candidates[i].id).out_frame = m_frame;
            m_features.at(m_candidates[i].id).out_cause = nl::InputCause::StreetRepeat;
        } else {
            anchors.push_back(f.anchor);
        }
    }
    std::size_t out = 0;
    for (std::size_t i = 0; i < m_candidates.size(); ++i) {
        if (!drop[i]) m_candidates[out++] = m_candidates[i];
    }
    m_candidates.resize(out);
}

void LabelPass::inputChanges(const MapFrame& frame, glm::vec2 viewport, MapFrameStats& stats) {
    stats.label_input_changes.clear();
    m_input_ids.clear();
    for (const nl::LabelCandidate& c : m_candidates) m_input_ids.push_back(c.id);
    std::ranges::sort(m_input_ids);
    // Whether a store-frame point is in the view of a frame (eye-relative view-projection).
    const auto in_view = [](const glm::mat4& vp_eye, const glm::dvec3& eye, glm::vec2 size, float near,
                            const glm::dvec3& p) {
        const glm::vec4 clip = vp_eye * glm::vec4(glm::vec3(p - eye), 1.0f);
        if (clip.w < near) return false;
        const glm::vec2 px = toScreen(clip, size);
        return px.x >= 0.0f && px.y >= 0.0f && px.x <= size.x && px.y <= size.y;
    };
    const auto near = static_cast<float>(frame.camera.near_m);
    // Arrivals: why was it no candidate in the last frame?
    for (const std::uint64_t id : m_input_ids) {
        if (std::ranges::binary_search(m_prev_input_ids, id)) continue;
        const Feature& f = m_features.at(id);
        nl::InputCause cause = nl::InputCause::Tiles;
        if (f.out_frame + 1 == m_frame) {
            cause = f.out_cause;
        } else if (m_prev_viewport.x <= 0.0f ||
                   !in_view(m_prev_view_projection, m_prev_eye, m_prev_viewport, m_prev_near, f.anchor)) {
            cause = nl::InputCause::View;
        }
        stats.label_input_changes.push_back({id, true, cause});
    }
    // Departures of the labels the layout showed: why is it no candidate now?
    for (const std::uint64_t id : m_prev_input_ids) {
        if (std::ranges::binary_search(m_input_ids, id) || !std::ranges::binary_search(m_shown, id)) continue;
        const auto it = m_features.find(id);
        if (it == m_features.end()) continue;
        const Feature& f = it->second;
        nl::InputCause cause = nl::InputCause::Tiles;
        if (f.out_frame == m_frame) {
            cause = f.out_cause;
        } else if (!in_view(m_view_projection, m_eye, viewport, near, f.anchor)) {
            cause = nl::InputCause::View;
        }
        stats.label_input_changes.push_back({id, false, cause});
    }
    m_prev_input_ids.swap(m_input_ids);
    m_prev_view_projection = m_view_projection;
    m_prev_eye = m_eye;
    m_prev_viewport = viewport;
    m_prev_near = near;
}

void LabelPass::keepOut(const MapFrame& frame, std::span<const TileLabels> tiles, glm::vec2 viewport,
                        std::span<const glm::vec2> marker, const MapStyle& style) {
    m_keep_out.clear();
    const float margin = m_params.keep_out_margin_px;
    if (marker.size() >= 2) {
        glm::vec2 lo(std::numeric_limits<float>::max()), hi(std::numeric_limits<float>::lowest());
        for (const glm::vec2 p : marker) {
            lo = glm::min(lo, p);
            hi = glm::max(hi, p);
        }
        m_keep_out.push_back({0.5f * (lo + hi), 0.5f * (hi - lo) + margin, {1.0f, 0.0f}});
    }
    auto ground_at = [&](double x, double y) {
        const double z = groundHeight(tiles, x, y);
        return std::isnan(z) ? frame.camera.target.z : z;
    };
    const float focal_px = m_projection[1][1] * 0.5f * viewport.y;
    const auto near = static_cast<float>(frame.camera.near_m);
    // A draped polyline on screen: one box per piece, as wide as the piece (`half_width_m(i)`,
    // piece i from point i - 1 to i) at its nearer end, plus the margin.
    auto strip = [&](const std::vector<glm::dvec3>& points, auto&& half_width_m) {
        for (std::size_t i = 1; i < points.size(); ++i) {
            const glm::vec4 ca = m_view_projection * glm::vec4(glm::vec3(points[i - 1] - m_eye), 1.0f);
            const glm::vec4 cb = m_view_projection * glm::vec4(glm::vec3(points[i] - m_eye), 1.0f);
            if (ca.w < near || cb.w < near) continue;
            const glm::vec2 a = toScreen(ca, viewport), b = toScreen(cb, viewport);
            const float len = glm::length(b - a);
            const glm::vec2 axis = len > 1e-3f ? (b - a) / len : glm::vec2(1.0f, 0.0f);
            const float half_width = half_width_m(i) * focal_px / std::min(ca.w, cb.w) + margin;
            m_keep_out.push_back({0.5f * (a + b), {0.5f * len + half_width, half_width}, axis});
        }
    };
    // Points every `step_m` along a polyline with measures, from `from` to `to`, draped on the
    // finest drawn tile under each.
    auto sample = [&](const std::vector<glm::dvec3>& points, const std::vector<double>& measure_m, double from,
                      double to, double step_m) {
        std::vector<glm::dvec3> out;
        std::vector<double> at;
        // From the first point at or beyond `from` (the measures grow along the line).
        std::size_t k = std::max<std::size_t>(
            1,
            static_cast<std::size_t>(std::lower_bound(measure_m.begin(), measure_m.end(), from) - measure_m.begin()));
        for (double m = from;; m = std::min(m + step_m, to)) {
            while (k + 1 < measure_m.size() && measure_m[k] < m) ++k;
            const double m0 = measure_m[k - 1], m1 = measure_m[k];
            const double u = m1 > m0 ? std::clamp((m - m0) / (m1 - m0), 0.0, 1.0) : 0.0;
            const glm::dvec3 p = glm::mix(points[k - 1], points[k], u);
            out.emplace_back(p.x, p.y, ground_at(p.x, p.y));
            at.push_back(m);
            if (m >= to) break;
        }
        return std::pair(std::move(out), std::move(at));
    };
    // The route just ahead of the car.
    if (frame.route && frame.layers.route && frame.route->points.size() >= 2 &&
        frame.route->measure_m.size() == frame.route->points.size()) {
        const RouteGeometry& r = *frame.route;
        const double from = std::clamp(frame.route_progress_m, r.measure_m.front(), r.measure_m.back());
        const double to = std::min(from + m_params.route_keep_out_m, r.measure_m.back());
        const auto [points, at] = sample(r.points, r.measure_m, from, to, 10.0);
        strip(points, [&](std::size_t) { return 0.5f * style.route_width_m; });
    }
    // The manoeuvre arrows, as wide as they are drawn (casing included; the head at its base).
    for (const ManeuverArrow& arrow : frame.arrows) {
        if (arrow.emphasis <= 0.0f) continue;
        const float grow = arrowScale(arrow, style, frame.camera.eye, frame.camera.target.z, focal_px);
        const ArrowShape shape = arrowShape(arrow, style, grow);
        const RouteGeometry& line = shape.line;
        if (line.points.size() < 2 || line.measure_m.size() != line.points.size()) continue;
        const auto sampled = sample(line.points, line.measure_m, line.measure_m.front(), line.measure_m.back(), 5.0);
        const auto& points = sampled.first;
        const auto& at = sampled.second;
        strip(points, [&](std::size_t i) {
            return std::max(arrowHalfWidth(shape, at[i - 1], true, true), arrowHalfWidth(shape, at[i], true, false));
        });
    }
}

void LabelPass::layout(const MapFrame& frame, std::span<const TileLabels> tiles, glm::ivec2 viewport,
                       MapFrameStats& stats, std::span<const glm::vec2> marker, const MapStyle& style) {
    const auto t0 = Clock::now();
    ++m_frame;
    const double aspect = static_cast<double>(viewport.x) / std::max(viewport.y, 1);
    m_projection = frame.camera.projection(aspect);
    m_eye = frame.camera.eye;
    // View space with the camera at the origin: world-space labels are positioned there.
    const glm::mat4 view = frame.camera.viewRelativeTo(m_eye);
    m_view = view;
    m_view_projection = m_projection * view;
    m_engine.beginFrame();

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

    // Text of the placed labels (quads must live until the draw calls).
    const auto out = m_layout.output();
    m_texts.clear();
    m_screen.clear();
    m_world.clear();
    m_world_drawn.clear();
    m_occluders.clear();
    m_texts.reserve(out.size());
    const text::AtlasParams& atlas = m_engine.atlas().params();
    const float spread_em = static_cast<float>(atlas.spread_px) / static_cast<float>(atlas.base_em_px);
    const float focal_px = m_projection[1][1] * 0.5f * vp.y;
    const glm::mat4 inverse_view = glm::inverse(view);
    stats.drawn_labels.clear();
    std::size_t visible = 0;
    for (const nl::PlacedLabel& p : out) {
        if (p.state == nl::LabelState::FadingIn || p.state == nl::LabelState::Visible) ++visible;
        auto it = m_features.find(p.id);
        if (it == m_features.end()) continue;
        Feature& f = it->second;
        const text::LabelTextStyle s = text::labelTextStyle(f.kind, f.subclass);
        const text::RunId run = m_engine.run(f.name, s.font);
        m_texts.push_back(s.icon.empty() ? m_engine.layout(run, s.size_px)
                                         : m_engine.layoutWithIcon(m_engine.run(s.icon, s.font), run, s.size_px));
        const text::LaidOutText& t = m_texts.back();
        const float angle = p.box.angle();
        // seed 5.5.1: the occluded label's depth for the aura; screen-space labels stand at their anchor.
        const glm::vec3 anchor_view = glm::vec3(view * glm::vec4(glm::vec3(f.anchor - m_eye), 1.0f));
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
        const bool screen_drawn = world < 1.0f || !f.world;
        if (screen_drawn) {
            const float screen_alpha = p.alpha * (f.world ? 1.0f - world : 1.0f);
            m_screen.push_back({t.quads, t.size_px, p.box.center, angle, p.scale, screen_alpha, s.style});
            drawn.cap_height_px = t.metrics.cap_height * p.scale;
            text::appendDrawnGlyphBoxes(t.quads, t.size_px, p.scale, angle, p.box.center, spread_em, s.style.outline_px,
                                        s.style.halo_px, drawn.glyph_boxes);
        }
        if (world > 0.0f && f.world) {
            // seed 5.2.1: the text lies in its plane where the layout box's center is seen.
            const WorldPlane& pl = f.plane;
            const glm::vec2 ndc(p.box.center.x / vp.x * 2.0f - 1.0f, 1.0f - p.box.center.y / vp.y * 2.0f);
            const glm::vec3 ray = glm::vec3(
                inverse_view * glm::vec4(ndc.x / m_projection[0][0], ndc.y / m_projection[1][1], -1.0f, 0.0f));
            const glm::vec3 origin(pl.origin - m_eye);
            const float denom = glm::dot(pl.normal, ray);
            const float hit = std::abs(denom) > 1e-6f ? glm::dot(pl.normal, origin) / denom : -1.0f;
            if (hit > 0.0f) {
                const glm::vec3 center = ray * hit;
                const float depth = -(view * glm::vec4(center, 1.0f)).z;
                if (depth > static_cast<float>(frame.camera.near_m)) {
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
                    wd.alpha = p.alpha * world;
                    wd.style = s.style;
                    m_world.push_back(wd);
                    occluder_depth = depth;
                    if (world >= 0.5f || !screen_drawn) {
                        // What the frame shows of it is this world-space text.
                        drawn.world_space = true;
                        drawn.glyph_boxes.clear();
                        const float metres_per_px = pl.em_m / t.size_px;
                        const float em_px = pl.em_m * focal_px / depth;
                        const float inset = text::drawnGlyphInsetPx(em_px, spread_em, s.style.outline_px,
                                                                    s.style.halo_px, em_px / t.size_px) *
                                            t.size_px / em_px;  // screen px back to quad px
                        auto project = [&](glm::vec2 local) {
                            const glm::vec3 w = center + (pl.right * local.x - pl.up * local.y) * metres_per_px;
                            return toScreen(m_view_projection * glm::vec4(w, 1.0f), vp);
                        };
                        for (const text::GlyphQuad& q : t.quads) {
                            const glm::vec2 lo = q.p0 + inset, hi = q.p1 - inset;
                            if (!(hi.x > lo.x && hi.y > lo.y)) continue;
                            drawn.glyph_boxes.push_back(
                                {project(lo), project({hi.x, lo.y}), project(hi), project({lo.x, hi.y})});
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
                    world_index = m_world.size() - 1;
                }
            }
        }
        if (occluder_depth > static_cast<float>(frame.camera.near_m)) {
            m_occluders.push_back({p.box, occluder_depth, p.alpha});
        }
        if (world_index < m_world.size()) {
            m_world_drawn.resize(m_world.size(), std::numeric_limits<std::size_t>::max());
            if (drawn.world_space && !drawn.glyph_boxes.empty()) m_world_drawn[world_index] = stats.drawn_labels.size();
        }
        if (!drawn.glyph_boxes.empty()) stats.drawn_labels.push_back(std::move(drawn));
    }
    m_world_drawn.resize(m_world.size(), std::numeric_limits<std::size_t>::max());
    // Forget features neither in this frame's input nor in the output any more.
    m_shown.clear();
    for (const nl::PlacedLabel& p : out) m_shown.push_back(p.id);  // output() is in id order
    for (auto it = m_features.begin(); it != m_features.end();) {
        const bool shown = std::ranges::binary_search(m_shown, it->first);
        if (it->second.frame != m_frame && !shown) {
            it = m_features.erase(it);
        } else {
            ++it;
        }
    }

    stats.label_candidates = m_candidates.size();
    stats.labels_too_small = m_too_small;
    stats.labels_visible = visible;
    stats.label_world_weight = world;
    stats.placed_labels.assign(out.begin(), out.end());
    stats.label_layout = m_layout.stats();
    stats.labels_ms = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
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
