// SPDX-License-Identifier: Apache-2.0
// The label pass's input: label features of the drawn tiles as layout candidates (collect), one
// name per street, the input's changes with their causes, and the text size of each label.
#include <algorithm>
#include <cmath>
#include <string>
#include <string_view>
#include <unordered_map>

#include <glm/geometric.hpp>

#include "label_pass.h"
#include "label_pass_screen.h"
#include "text/label_text_style.h"

namespace navmap::render::gl {

namespace {

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

}  // namespace navmap::render::gl
