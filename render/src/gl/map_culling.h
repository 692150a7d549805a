// SPDX-License-Identifier: Apache-2.0
#pragma once
// View tests and road extents shared by the passes of MapRenderer: boxes against the frustum,
// how far road and route quads reach beyond their pieces (roads_geo.vert's widths, seed 3.6.3),
// and a frustum test per road piece. GL-free. Private to render/.

#include <algorithm>
#include <array>
#include <numbers>

#include <glm/glm.hpp>
#include <glm/gtc/matrix_access.hpp>

#include "navmap/render/road_style.h"
#include "tile_mesh.h"

namespace navmap::render::gl {

// The route's casing per side, as a fraction of its width (roads_geo.vert's u_route_casing_m).
inline constexpr float kRouteCasingFraction = 0.25f;
// Full width of the route's quads with their casing (its widest pass), metres.
inline float routeOuterWidth(float route_width_m) { return (1.0f + 2.0f * kRouteCasingFraction) * route_width_m; }
// How far, in pixels, roads_geo.vert can move any road or route quad's upper side beyond the quad
// on the ground when it widens a foreshortened road to RoadStyle::min_width_px: the most of
// leastWidthGrowthPx (OutlineCells::markQuad's bound per quad) over the classes and the route.
inline float roadWideningPx(const MapStyle& style) {
    const float min_width = style.roads.min_width_px;
    float most = leastWidthGrowthPx(min_width, routeOuterWidth(style.route_width_m), style.route_width_m);
    for (const RoadClassStyle& c : style.roads.classes)
        most = std::max(most, leastWidthGrowthPx(min_width, c.outerWidth(), c.width_m));
    return most;
}

// False when the box [lo, hi] (tile-local) lies entirely outside one plane of the view frustum;
// `far` false leaves the far plane out.
inline bool boxInView(const glm::mat4& view_projection, glm::vec3 lo, glm::vec3 hi, bool far = true) {
    std::array<int, 6> outside{};
    for (int i = 0; i < 8; ++i) {
        const glm::vec4 c =
            view_projection * glm::vec4((i & 1) ? hi.x : lo.x, (i & 2) ? hi.y : lo.y, (i & 4) ? hi.z : lo.z, 1.0f);
        outside[0] += c.x < -c.w;
        outside[1] += c.x > c.w;
        outside[2] += c.y < -c.w;
        outside[3] += c.y > c.w;
        outside[4] += c.z < -c.w;
        outside[5] += far && c.z > c.w;
    }
    return std::none_of(outside.begin(), outside.end(), [](int n) { return n == 8; });
}
inline bool boxInView(const glm::mat4& view_projection, const TerrainBlock& b) {
    return boxInView(view_projection, glm::vec3(b.min, b.min_z), glm::vec3(b.max, b.max_z));
}
// Half the widest road footprint of the style (casing included), metres before distance scaling.
inline float widestHalfWidth(const RoadStyle& rs) {
    float half_width = 0.0f;
    for (const RoadClassStyle& c : rs.classes) half_width = std::max(half_width, 0.5f * c.outerWidth());
    return half_width;
}

// How far road or route quads drawn from pieces within `e` reach beyond it, before the least-width
// widening: `half_width` (fill and casing) at the distance scale (seed 3.6.3) of the extent's
// farthest point from `eye`, times sqrt 2 (a corner lies that far along and across the piece).
struct QuadReach {
    float farthest_m = 0.0f;
    float reach_m = 0.0f;
};
inline QuadReach quadReach(glm::vec3 eye, const BlockExtent& e, float half_width, const RoadStyle& rs) {
    const float farthest = glm::length(glm::max(glm::abs(eye - e.min), glm::abs(eye - e.max)));
    return {farthest, std::numbers::sqrt2_v<float> * half_width *
                          distanceWidthScale(farthest, rs.scale_threshold_m, rs.max_scale)};
}

// Whether road or route quads drawn from pieces within `e`, reaching `reach` beyond it, can reach
// the view. The far plane is left out: the view-space offset against z-fighting (seed 3.6.2)
// pulls pieces a little towards the camera.
inline bool quadsInView(const glm::mat4& view_projection, const BlockExtent& e, float reach) {
    if (e.min.x > e.max.x) return false;  // nothing there
    return boxInView(view_projection, e.min - reach, e.max + reach, false);
}

// The view frustum's side and near planes (tile-local, metric), for a test per road piece: in
// the blocks in view, about a third to a half of the pieces still lie outside the view, and on
// llvmpipe each costs the render thread its vertices and triangle setup.
class PieceFrustum {
public:
    explicit PieceFrustum(const glm::mat4& view_projection) {
        const glm::vec4 x = glm::row(view_projection, 0), y = glm::row(view_projection, 1);
        const glm::vec4 z = glm::row(view_projection, 2), w = glm::row(view_projection, 3);
        m_planes = {w + x, w - x, w + y, w - y, w + z};  // the far plane left out, as in quadsInView
        for (glm::vec4& p : m_planes) p /= glm::length(glm::vec3(p));
    }
    /// Whether the quad roads_geo.vert expands from `r` can reach the view: the sphere around the
    /// piece's middle through its end points, grown by the widest quad's corner reach (half the
    /// width, scaled by distance as the shader does at the middle, times sqrt 2). The view-space
    /// offset (seed 3.6.2) moves points towards the eye, along the side planes' rays.
    [[nodiscard]] bool holds(const RoadInstance& r, glm::vec3 eye, float half_width, const RoadStyle& rs) const {
        const glm::vec3 mid = 0.5f * (r.p0 + r.p1);
        const float reach = half_width * distanceWidthScale(glm::length(mid - eye), rs.scale_threshold_m, rs.max_scale);
        const float radius = 0.5f * glm::length(r.p1 - r.p0) + std::numbers::sqrt2_v<float> * reach;
        for (const glm::vec4& p : m_planes) {
            if (glm::dot(glm::vec3(p), mid) + p.w < -radius) return false;
        }
        return true;
    }

private:
    std::array<glm::vec4, 5> m_planes{};
};

}  // namespace navmap::render::gl
