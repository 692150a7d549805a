// SPDX-License-Identifier: Apache-2.0
#include "navmap/render/terrain_lod.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <optional>

#include <glm/gtc/matrix_transform.hpp>

namespace navmap::render {

namespace {

struct Frustum {
    std::array<glm::dvec4, 6> planes;  // inside: dot(plane.xyz, p) + plane.w >= 0
};

Frustum frustumOf(const glm::dmat4& m) {
    // Gribb/Hartmann plane extraction from the view-projection matrix.
    Frustum f;
    const glm::dvec4 r0(m[0][0], m[1][0], m[2][0], m[3][0]);
    const glm::dvec4 r1(m[0][1], m[1][1], m[2][1], m[3][1]);
    const glm::dvec4 r2(m[0][2], m[1][2], m[2][2], m[3][2]);
    const glm::dvec4 r3(m[0][3], m[1][3], m[2][3], m[3][3]);
    f.planes = {r3 + r0, r3 - r0, r3 + r1, r3 - r1, r3 + r2, r3 - r2};
    return f;
}

bool boxOutside(const Frustum& f, const glm::dvec3& lo, const glm::dvec3& hi) {
    for (const auto& p : f.planes) {
        const glm::dvec3 v{p.x >= 0 ? hi.x : lo.x, p.y >= 0 ? hi.y : lo.y, p.z >= 0 ? hi.z : lo.z};
        if (p.x * v.x + p.y * v.y + p.z * v.z + p.w < 0) return true;
    }
    return false;
}

double distanceToBox(const glm::dvec3& p, const glm::dvec3& lo, const glm::dvec3& hi) {
    const glm::dvec3 q = glm::clamp(p, lo, hi);
    return glm::length(p - q);
}

}  // namespace

double screenSpaceError(double error_m, double distance_m, double fov_y_deg, int viewport_height) {
    const double d = std::max(distance_m, 1e-3);
    return error_m * viewport_height / (2.0 * d * std::tan(glm::radians(fov_y_deg) / 2.0));
}

double levelError(const map::TileScheme& scheme, int level, const LodOptions& options) {
    const int samples = std::max(options.dem_samples, 2);
    return options.error_per_spacing * scheme.tileSize(level) / (samples - 1);
}

double refineDistance(const map::TileScheme& scheme, int level, double fov_y_deg, int viewport_height,
                      const LodOptions& options) {
    // screenSpaceError(e, d) = e * h / (2 d tan(fov / 2)) solved for d at max_error_px.
    const double px = std::max(options.max_error_px, 1e-6);
    return levelError(scheme, level, options) * viewport_height / (2.0 * px * std::tan(glm::radians(fov_y_deg) / 2.0));
}

TileMorph morphRange(const map::TileScheme& scheme, int level, double fov_y_deg, int viewport_height,
                     const LodOptions& options) {
    TileMorph m;
    const double ratio = std::clamp(options.morph_start, 0.0, 0.99);
    for (int j = 0; j < kMorphLevels; ++j) {
        const int finer = level - j;
        if (finer <= 0) break;
        // The level above `finer` is refined (so `finer` drawn) only while its box is nearer than
        // this: from here on a tile of `finer` must look exactly like that coarser level.
        const double end = refineDistance(scheme, finer - 1, fov_y_deg, viewport_height, options);
        m.end_m[static_cast<std::size_t>(j)] = static_cast<float>(end);
        m.start_m[static_cast<std::size_t>(j)] = static_cast<float>(ratio * end);
    }
    return m;
}

double morphEyeDz(double eye_z, const LodOptions& options) {
    return std::max({0.0, eye_z - options.max_height_m, options.min_height_m - eye_z});
}

float morphDistance(float dx, float dy, const TileMorph& morph) {
    return std::sqrt(dx * dx + dy * dy + morph.eye_dz_m * morph.eye_dz_m);
}

float morphFactor(float distance_m, float start_m, float end_m) {
    if (end_m <= start_m) return 0.0f;
    return std::clamp((distance_m - start_m) / (end_m - start_m), 0.0f, 1.0f);
}

float morphedHeight(float distance_m, const TileMorph& morph, float own,
                    const std::array<float, kMorphLevels>& ancestors) {
    // From the coarsest level inwards: S_k = mix(h_k, S_k-1, f_k).
    float s = ancestors[kMorphLevels - 1];
    for (int j = kMorphLevels - 1; j >= 0; --j) {
        const float h = j == 0 ? own : ancestors[static_cast<std::size_t>(j - 1)];
        const auto k = static_cast<std::size_t>(j);
        s = h + (s - h) * morphFactor(distance_m, morph.start_m[k], morph.end_m[k]);
    }
    return s;
}

LodSelection selectLod(const map::TileScheme& scheme, const Camera& camera, double aspect, int viewport_height,
                       const std::function<bool(map::TileId)>& exists,
                       const std::function<std::shared_ptr<const map::Tile>(map::TileId)>& resident,
                       const LodOptions& options, const std::vector<map::TileId>& roots) {
    LodSelection out;
    // Frustum in a frame centred on the camera (double), so far-away stores stay precise.
    const glm::dmat4 view = glm::lookAt(glm::dvec3(0.0), camera.target - camera.eye, camera.up);
    const glm::dmat4 proj = glm::dmat4(camera.projection(aspect));
    const Frustum frustum = frustumOf(proj * view);

    // Where a tile lies: its distance from the eye, or none when the frustum culls it. From the
    // scheme's box and the assumed height range, not the tile's data: the same for tiles not
    // loaded yet.
    const auto inView = [&](map::TileId id) -> std::optional<double> {
        const map::Box b = scheme.bounds(id);
        const glm::dvec3 lo = glm::dvec3(b.min_x, b.min_y, options.min_height_m) - camera.eye;
        const glm::dvec3 hi = glm::dvec3(b.max_x, b.max_y, options.max_height_m) - camera.eye;
        if (boxOutside(frustum, lo, hi)) return std::nullopt;
        return distanceToBox(glm::dvec3(0.0), lo, hi);
    };
    const auto refines = [&](map::TileId id, double distance) {
        return id.level < scheme.leafLevel() &&
               screenSpaceError(levelError(scheme, id.level, options), distance, camera.fov_y_deg, viewport_height) >
                   options.max_error_px;
    };
    // The existing children of `id`, first in the array; how many.
    const auto childrenOf = [&](map::TileId id, std::array<map::TileId, 4>& children) {
        int present = 0;
        for (int i = 0; i < 4; ++i) {
            const map::TileId c{static_cast<std::uint8_t>(id.level + 1), id.x * 2 + (i & 1), id.y * 2 + (i >> 1)};
            // A mounted store's root inside another's subtree is drawn from its own traversal.
            const bool other_root = roots.size() > 1 && std::find(roots.begin(), roots.end(), c) != roots.end();
            if (exists(c) && !other_root) children[static_cast<std::size_t>(present++)] = c;
        }
        return present;
    };

    std::vector<map::TileId> stack = roots;
    // Below a tile that is not resident (or a parent whose children are not all resident) the
    // traversal stops drawing, but the camera's needs go on: `ahead` walks on through those
    // subtrees with the same tests and requests what it meets, so that a view loads every level
    // it will draw in one round instead of one level per frame (start-up, a jump of the camera).
    std::vector<map::TileId> ahead;
    std::array<map::TileId, 4> children;
    while (!stack.empty()) {
        const map::TileId id = stack.back();
        stack.pop_back();
        const std::optional<double> distance = inView(id);
        if (!distance) {
            ++out.culled;
            continue;
        }
        const double priority = 1000.0 + 100.0 * id.level - *distance / scheme.tileSize(id.level);
        auto self = resident(id);
        if (!self) {
            // Not loaded: ask for it; the caller's previous selection (parent) covers the gap.
            if (exists(id)) {
                out.wanted.push_back({id, static_cast<float>(priority)});
                ahead.push_back(id);
            }
            continue;
        }
        if (refines(id, *distance)) {
            const int present = childrenOf(id, children);
            bool all_ready = true;
            for (int i = 0; i < present; ++i) {
                if (resident(children[static_cast<std::size_t>(i)])) continue;
                all_ready = false;
                out.wanted.push_back({children[static_cast<std::size_t>(i)], static_cast<float>(priority + 100.0)});
            }
            // Refine only when every existing child can be drawn (no holes). The compiler writes
            // no tile where there is no data, so a missing child is a quarter outside the data.
            if (all_ready && present > 0) {
                stack.insert(stack.end(), children.begin(), children.begin() + present);
                continue;
            }
            ahead.insert(ahead.end(), children.begin(), children.begin() + present);
        }
        out.draw.push_back(std::move(self));
        out.finest_level = std::max(out.finest_level, static_cast<int>(id.level));
    }
    while (!ahead.empty()) {
        const map::TileId id = ahead.back();
        ahead.pop_back();
        const std::optional<double> distance = inView(id);
        if (!distance || !refines(id, *distance)) continue;
        const int present = childrenOf(id, children);
        for (int i = 0; i < present; ++i) {
            const map::TileId c = children[static_cast<std::size_t>(i)];
            // After every tile the drawn traversal asks for, coarse before fine: each level is
            // drawn only once the one above it is resident.
            if (!resident(c))
                out.wanted.push_back(
                    {c, static_cast<float>(-1e5 - 100.0 * c.level - *distance / scheme.tileSize(c.level))});
            ahead.push_back(c);
        }
    }
    // Deterministic draw order: by level then address.
    std::sort(out.draw.begin(), out.draw.end(), [](const auto& a, const auto& b) { return a->id.key() < b->id.key(); });
    if (options.morph) {
        // Geomorphing ranges (see the header). The ancestors are resident, since the traversal
        // reached every drawn tile through them.
        const auto eye_dz = static_cast<float>(morphEyeDz(camera.eye.z, options));
        out.morph.reserve(out.draw.size());
        for (const auto& t : out.draw) {
            TileMorph m = morphRange(scheme, t->id.level, camera.fov_y_deg, viewport_height, options);
            map::TileId up = t->id;
            for (int j = 0; j < kMorphLevels && up.level > 0; ++j) {
                up = up.parent();
                m.ancestors[static_cast<std::size_t>(j)] = resident(up);
            }
            m.eye_dz_m = eye_dz;
            out.morph.push_back(std::move(m));
        }
    }
    return out;
}

}  // namespace navmap::render
