// SPDX-License-Identifier: Apache-2.0
#include "field_grid.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include "navmap/map/ortho/rng.h"
#include "navmap/map/ortho/super_land_cover.h"

namespace navmap::render::ortho {

namespace {

using map::ortho::Rng;
using Quad = std::array<glm::vec2, 4>;

float cross2(glm::vec2 a, glm::vec2 b) { return a.x * b.y - a.y * b.x; }

bool triangleContains(glm::vec2 a, glm::vec2 b, glm::vec2 c, glm::vec2 p) {
    const float d0 = cross2(b - a, p - a), d1 = cross2(c - b, p - b), d2 = cross2(a - c, p - c);
    const bool neg = d0 < 0 || d1 < 0 || d2<0, pos = d0> 0 || d1 > 0 || d2 > 0;
    return !(neg && pos);
}

float quadArea(const Quad& q) {
    float a = 0;
    for (std::size_t i = 0; i < 4; ++i) a += cross2(q[i], q[(i + 1) % 4]);
    return 0.5f * std::abs(a);
}

// Whether the convex quad and the axis-aligned square [lo, hi] overlap (separating axes: the
// square's two and the quad's four edge normals). Touching counts: a parcel too many is cut off
// by the farmland mask when drawn, a parcel too few leaves farmland without a field.
bool quadMeetsBox(const Quad& q, glm::vec2 lo, glm::vec2 hi) {
    glm::vec2 qlo = q[0], qhi = q[0];
    for (const glm::vec2& p : q) {
        qlo = glm::min(qlo, p);
        qhi = glm::max(qhi, p);
    }
    if (qhi.x < lo.x || qlo.x > hi.x || qhi.y < lo.y || qlo.y > hi.y) return false;
    const std::array<glm::vec2, 4> box{lo, {hi.x, lo.y}, hi, {lo.x, hi.y}};
    for (std::size_t i = 0; i < 4; ++i) {
        const glm::vec2 e = q[(i + 1) % 4] - q[i], n(-e.y, e.x);
        float a0 = 1e30f, a1 = -1e30f, b0 = 1e30f, b1 = -1e30f;
        for (std::size_t k = 0; k < 4; ++k) {
            const float a = glm::dot(q[k], n), b = glm::dot(box[k], n);
            a0 = std::min(a0, a);
            a1 = std::max(a1, a);
            b0 = std::min(b0, b);
            b1 = std::max(b1, b);
        }
        if (a1 < b0 || b1 < a0) return false;
    }
    return true;
}

glm::vec2 nearestOnSegment(glm::vec2 p, glm::vec2 a, glm::vec2 b) {
    const glm::vec2 d = b - a;
    const float len2 = glm::dot(d, d);
    const float t = len2 > 0 ? std::clamp(glm::dot(p - a, d) / len2, 0.0f, 1.0f) : 0.0f;
    return a + t * d;
}

bool majorRoad(map::RoadClass c) { return c <= map::RoadClass::Unclassified; }

}  // namespace

bool parcelContains(const FieldParcel& p, glm::vec2 point) {
    const auto& q = p.corners;
    return triangleContains(q[0], q[1], q[2], point) || triangleContains(q[0], q[2], q[3], point);
}

std::vector<std::uint8_t> farmlandMask(const map::Tile& tile) {
    const auto& cover = tile.ortho.cover;
    std::vector<std::uint8_t> mask(cover.size(), 0);
    for (std::size_t i = 0; i < cover.size(); ++i) {
        mask[i] = map::ortho::isFarmland(static_cast<map::ortho::SuperLandCover>(cover[i])) ? 1 : 0;
    }
    return mask;
}

float roadGridAngle(const map::Tile& tile) {
    std::array<double, 90> hist{};
    for (const auto& r : tile.roads) {
        // Weighted by length and importance (motorways 4x, secondary and below 1x, minor roads 1/4).
        const double weight = majorRoad(r.cls) ? std::max(1.0, 4.0 - static_cast<double>(r.cls)) : 0.25;
        for (std::size_t i = 1; i < r.points.size(); ++i) {
            const double dx = r.points[i].x - r.points[i - 1].x, dy = r.points[i].y - r.points[i - 1].y;
            const double len = std::hypot(dx, dy);
            if (len <= 0) continue;
            double deg = std::atan2(dy, dx) * 180.0 / std::numbers::pi;
            deg = std::fmod(std::fmod(deg, 90.0) + 90.0, 90.0);
            hist[static_cast<std::size_t>(std::min(89.0, std::floor(deg)))] += weight * len;
        }
    }
    double best = 0;
    int best_bin = -1;
    for (int b = 0; b < 90; ++b) {
        double s = 0;
        for (int k = -2; k <= 2; ++k) s += hist[static_cast<std::size_t>((b + k + 90) % 90)];
        if (s > best) {
            best = s;
            best_bin = b;
        }
    }
    if (best_bin < 0) return 0.0f;
    // The weighted mean angle within the winning window, so that a road at 30.0 degrees gives
    // 30 rather than the bin's centre.
    double sum = 0, weight = 0;
    for (int k = -2; k <= 2; ++k) {
        const double w = hist[static_cast<std::size_t>((best_bin + k + 90) % 90)];
        sum += w * (best_bin + k + 0.5);
        weight += w;
    }
    const double deg = std::fmod(sum / weight + 90.0, 90.0);
    return static_cast<float>(deg * std::numbers::pi / 180.0);
}

namespace {

// The tile's farmland texels (row 0 south).
class Farmland {
public:
    explicit Farmland(const map::Tile& tile)
        : m_mask(farmlandMask(tile)), m_n(tile.ortho.cover_size), m_texel(static_cast<float>(tile.size_m / m_n)) {}

    [[nodiscard]] int size() const { return m_n; }
    [[nodiscard]] glm::vec2 centre(int r, int c) const { return glm::vec2((c + 0.5f) * m_texel, (r + 0.5f) * m_texel); }
    [[nodiscard]] bool farm(int r, int c) const {
        return r >= 0 && c >= 0 && r < m_n && c < m_n && m_mask[static_cast<std::size_t>(r) * m_n + c] != 0;
    }
    /// Whether the quad meets a farmland texel; with `centres`, also how many farmland texel centres
    /// it holds (stored there).
    bool meetsFarmland(const Quad& q, int* centres) const;

private:
    std::vector<std::uint8_t> m_mask;
    int m_n;
    float m_texel;
};

bool Farmland::meetsFarmland(const Quad& q, int* centres) const {
    glm::vec2 qlo = q[0], qhi = q[0];
    for (const glm::vec2& p : q) {
        qlo = glm::min(qlo, p);
        qhi = glm::max(qhi, p);
    }
    const int c0 = std::max(0, static_cast<int>(std::floor(qlo.x / m_texel)));
    const int c1 = std::min(m_n - 1, static_cast<int>(std::floor(qhi.x / m_texel)));
    const int r0 = std::max(0, static_cast<int>(std::floor(qlo.y / m_texel)));
    const int r1 = std::min(m_n - 1, static_cast<int>(std::floor(qhi.y / m_texel)));
    FieldParcel p;
    p.corners = q;
    bool meets = false;
    int inside = 0;
    for (int r = r0; r <= r1; ++r) {
        for (int c = c0; c <= c1; ++c) {
            if (!farm(r, c)) continue;
            if (centres && parcelContains(p, centre(r, c))) ++inside;
            if (!meets) {
                const glm::vec2 lo_t(c * m_texel, r * m_texel);
                meets = quadMeetsBox(q, lo_t, lo_t + glm::vec2(m_texel));
                if (meets && !centres) return true;
            }
        }
    }
    if (centres) *centres = inside;
    return meets;
}

// The field grid's frame, aligned with the major roads: axes, its south-west corner in grid
// coordinates, the cell and the cells per side.
struct GridFrame {
    glm::vec2 ax, ay;
    glm::vec2 lo;
    float cell;
    int nx, ny;

    [[nodiscard]] glm::vec2 toGrid(glm::vec2 p) const { return glm::vec2(glm::dot(p, ax), glm::dot(p, ay)); }
    [[nodiscard]] glm::vec2 fromGrid(glm::vec2 g) const { return g.x * ax + g.y * ay; }
    /// Index of vertex (i, j).
    [[nodiscard]] std::size_t vi(int i, int j) const {
        return static_cast<std::size_t>(j) * static_cast<std::size_t>(nx + 1) + static_cast<std::size_t>(i);
    }
};

// The frame at `angle` over the farmland texels' centres, with a cell of margin: the outer ring of
// vertices never moves and encloses the farmland texels.
GridFrame gridFrame(float angle, const std::vector<glm::vec2>& farm_points, float cell) {
    GridFrame f;
    f.ax = glm::vec2(std::cos(angle), std::sin(angle));
    f.ay = glm::vec2(-f.ax.y, f.ax.x);
    glm::vec2 lo(1e30f), hi(-1e30f);
    for (glm::vec2 p : farm_points) {
        const glm::vec2 g = f.toGrid(p);
        lo = glm::min(lo, g);
        hi = glm::max(hi, g);
    }
    f.cell = cell;
    lo -= glm::vec2(cell);
    hi += glm::vec2(cell);
    f.lo = lo;
    f.nx = std::max(1, static_cast<int>(std::ceil((hi.x - lo.x) / cell)));
    f.ny = std::max(1, static_cast<int>(std::ceil((hi.y - lo.y) / cell)));
    return f;
}

// Adapts towards the silhouette (seed: 10 iterations): each inner vertex moves half way to the
// nearest silhouette point within half a cell, never further than `limit` from where it started
// (`base`), so the cells stay convex and the grid keeps tiling the plane without gaps.
void adaptToSilhouette(const GridFrame& f, const std::vector<glm::vec2>& silhouette, int iterations, float limit,
                       const std::vector<glm::vec2>& base, std::vector<glm::vec2>& vert) {
    const int nx = f.nx, ny = f.ny;
    const float reach = 0.5f * f.cell;
    std::vector<std::vector<std::uint32_t>> buckets(static_cast<std::size_t>(nx * ny));
    for (std::size_t s = 0; s < silhouette.size(); ++s) {
        const glm::vec2 g = (f.toGrid(silhouette[s]) - f.lo) / f.cell;
        const int i = std::clamp(static_cast<int>(g.x), 0, nx - 1), j = std::clamp(static_cast<int>(g.y), 0, ny - 1);
        buckets[static_cast<std::size_t>(j) * static_cast<std::size_t>(nx) + static_cast<std::size_t>(i)].push_back(
            static_cast<std::uint32_t>(s));
    }
    for (int it = 0; it < iterations; ++it) {
        for (int j = 1; j < ny; ++j) {
            for (int i = 1; i < nx; ++i) {
                glm::vec2& v = vert[f.vi(i, j)];
                float best = reach * reach;
                glm::vec2 target = v;
                bool found = false;
                for (int bj = j - 1; bj <= j; ++bj) {
                    for (int bi = i - 1; bi <= i; ++bi) {
                        for (std::uint32_t s : buckets[static_cast<std::size_t>(bj) * static_cast<std::size_t>(nx) +
                                                       static_cast<std::size_t>(bi)]) {
                            const glm::vec2 d = silhouette[s] - v;
                            const float d2 = glm::dot(d, d);
                            if (d2 < best) {
                                best = d2;
                                target = silhouette[s];
                                found = true;
                            }
                        }
                    }
                }
                if (!found) continue;
                glm::vec2 moved = glm::mix(v, target, 0.5f);
                const glm::vec2 shift = moved - base[f.vi(i, j)];
                const float len = glm::length(shift);
                if (len > limit) moved = base[f.vi(i, j)] + shift * (limit / len);
                v = moved;
            }
        }
    }
}

// Inner vertices near a major road (within snap_m) snap onto it, within the same shift limit.
void snapToRoads(const map::Tile& tile, const GridFrame& f, float snap_m, float limit,
                 const std::vector<glm::vec2>& base, std::vector<glm::vec2>& vert) {
    for (int j = 1; j < f.ny; ++j) {
        for (int i = 1; i < f.nx; ++i) {
            glm::vec2& v = vert[f.vi(i, j)];
            float best = snap_m;
            glm::vec2 target = v;
            for (const auto& road : tile.roads) {
                if (!majorRoad(road.cls)) continue;
                for (std::size_t k = 1; k < road.points.size(); ++k) {
                    const glm::vec2 q = nearestOnSegment(v, {road.points[k - 1].x, road.points[k - 1].y},
                                                         {road.points[k].x, road.points[k].y});
                    const float d = glm::length(q - v);
                    if (d < best) {
                        best = d;
                        target = q;
                    }
                }
            }
            if (glm::length(target - base[f.vi(i, j)]) <= limit) v = target;
        }
    }
}

// Splits the cell q into pieces down to `threshold` m^2, keeping those meeting farmland.
void subdivideCell(const Quad& q, float threshold, const Farmland& farmland, Rng& rng, std::vector<Quad>& leaves) {
    std::vector<Quad> stack{q};
    while (!stack.empty()) {
        const Quad p = stack.back();
        stack.pop_back();
        if (quadArea(p) <= threshold) {
            leaves.push_back(p);
            continue;
        }
        // Split across the longer pair of sides at 35-65 %; both halves share the new edge's
        // end points exactly.
        const auto t = static_cast<float>(rng.uniform(0.35, 0.65));
        const bool along =
            glm::length(p[1] - p[0]) + glm::length(p[2] - p[3]) >= glm::length(p[3] - p[0]) + glm::length(p[2] - p[1]);
        Quad a{}, b{};
        if (along) {
            const glm::vec2 m0 = glm::mix(p[0], p[1], t), m1 = glm::mix(p[3], p[2], t);
            a = {p[0], m0, m1, p[3]};
            b = {m0, p[1], p[2], m1};
        } else {
            const glm::vec2 m0 = glm::mix(p[0], p[3], t), m1 = glm::mix(p[1], p[2], t);
            a = {p[0], p[1], m1, m0};
            b = {m0, m1, p[2], p[3]};
        }
        for (const Quad& child : {b, a}) {
            if (farmland.meetsFarmland(child, nullptr)) stack.push_back(child);
        }
    }
}

// Cells meeting a farmland texel, subdivided into parcels (seed: "until a given area threshold is
// reached"); only the pieces meeting farmland are kept, so their union covers every farmland
// texel whole.
std::vector<Quad> parcelQuads(const GridFrame& f, const std::vector<glm::vec2>& vert, const Farmland& farmland,
                              const FieldOptions& opt, Rng& rng) {
    std::vector<Quad> leaves;
    for (int j = 0; j < f.ny; ++j) {
        for (int i = 0; i < f.nx; ++i) {
            const Quad q{vert[f.vi(i, j)], vert[f.vi(i + 1, j)], vert[f.vi(i + 1, j + 1)], vert[f.vi(i, j + 1)]};
            if (!farmland.meetsFarmland(q, nullptr)) continue;
            const auto threshold = static_cast<float>(rng.uniform(opt.min_parcel_m2, opt.max_parcel_m2));
            subdivideCell(q, threshold, farmland, rng, leaves);
        }
    }
    return leaves;
}

// Crop patterns by a random walk over the atlas (seed 6.7.2, Fig. 6.17): S_k, bounded to
// [-walk_range, walk_range], scaled to the offset o in [0, n/2]; each parcel picks from the
// sliding window [o, o + m).
void addParcels(const std::vector<Quad>& leaves, const Farmland& farmland, const FieldOptions& opt, Rng& rng,
                FieldGrid& grid) {
    int walk = 0;
    const int half = kCropPatterns / 2;
    const int window = std::max(opt.atlas_window, 1), range = std::max(opt.walk_range, 1);
    for (const Quad& leaf : leaves) {
        walk = std::clamp(walk + (rng.below(2) != 0 ? 1 : -1), -range, range);
        const auto offset = static_cast<int>(std::lround(double(walk + range) / (2.0 * range) * half));
        FieldParcel p;
        p.corners = leaf;
        p.pattern =
            std::min(offset + static_cast<int>(rng.below(static_cast<std::uint64_t>(window))), kCropPatterns - 1);
        const glm::vec2 e = leaf[1] - leaf[0];
        p.angle = std::atan2(e.y, e.x) + (rng.below(2) != 0 ? 0.0f : std::numbers::pi_v<float> / 2.0f);
        farmland.meetsFarmland(leaf, &p.farm_texels);
        grid.parcels.push_back(p);
    }
}

// Pair-wise colour changes (seed 6.7.5): parcel 2k brighter and warmer by as much as parcel 2k + 1
// is darker and cooler, weighted by their farmland so the pair's mean stays the network's. The
// larger parcel of the pair takes the smaller change.
void pairColours(Rng& rng, FieldGrid& grid) {
    for (std::size_t k = 0; k + 1 < grid.parcels.size(); k += 2) {
        FieldParcel &a = grid.parcels[k], &b = grid.parcels[k + 1];
        const auto v = static_cast<float>(rng.uniform(0.04, 0.12)), h = static_cast<float>(rng.uniform(-0.05, 0.05));
        const float wa = static_cast<float>(std::max(a.farm_texels, 1)),
                    wb = static_cast<float>(std::max(b.farm_texels, 1));
        const float big = std::max(wa, wb);
        a.variation = v * wb / big;
        a.hue = h * wb / big;
        b.variation = -v * wa / big;
        b.hue = -h * wa / big;
    }
}

}  // namespace

FieldGrid buildFieldGrid(const map::Tile& tile, const FieldOptions& opt) {
    FieldGrid grid;
    const auto& o = tile.ortho;
    if (o.empty() || o.cover.size() != std::size_t{o.cover_size} * o.cover_size) return grid;
    const Farmland farmland(tile);
    const int n = farmland.size();

    // Silhouette points, row by row: farmland texels with a non-farmland 4-neighbour.
    std::vector<glm::vec2> silhouette, farm_points;
    for (int r = 0; r < n; ++r) {
        for (int c = 0; c < n; ++c) {
            if (!farmland.farm(r, c)) continue;
            farm_points.push_back(farmland.centre(r, c));
            if (!farmland.farm(r - 1, c) || !farmland.farm(r + 1, c) || !farmland.farm(r, c - 1) ||
                !farmland.farm(r, c + 1)) {
                silhouette.push_back(farmland.centre(r, c));
            }
        }
    }
    if (farm_points.empty()) return grid;

    // The grid's frame, aligned with the major roads (seed 6.7.2 "Road network").
    grid.angle = roadGridAngle(tile);
    const GridFrame f = gridFrame(grid.angle, farm_points, opt.cell_m);
    std::vector<glm::vec2> base(static_cast<std::size_t>((f.nx + 1) * (f.ny + 1)));
    for (int j = 0; j <= f.ny; ++j) {
        for (int i = 0; i <= f.nx; ++i) base[f.vi(i, j)] = f.fromGrid(f.lo + glm::vec2(i, j) * f.cell);
    }
    std::vector<glm::vec2> vert = base;
    const float limit = opt.max_shift * f.cell;
    adaptToSilhouette(f, silhouette, opt.adapt_iterations, limit, base, vert);
    snapToRoads(tile, f, opt.snap_m, limit, base, vert);

    Rng rng(map::ortho::mixSeed(0x6669656c64ULL, tile.id.key()));
    const std::vector<Quad> leaves = parcelQuads(f, vert, farmland, opt, rng);
    addParcels(leaves, farmland, opt, rng, grid);
    pairColours(rng, grid);
    return grid;
}

}  // namespace navmap::render::ortho
