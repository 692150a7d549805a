// SPDX-License-Identifier: Apache-2.0
#include "vegetation.h"

#include <algorithm>
#include <cmath>
#include <iterator>
#include <numbers>

#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <glm/vec2.hpp>

#include "navmap/map/ortho/rng.h"
#include "navmap/map/ortho/super_land_cover.h"
#include "navmap/map/ortho/tile_sampler.h"

namespace navmap::render::ortho {

namespace {

using map::ortho::Rng;
using map::ortho::SuperLandCover;

// Half widths (m) of the roads kept free of plants, by class (motorway .. path).
float roadClearance(map::RoadClass c) {
    static constexpr float kWidth[] = {14, 12, 10, 8, 7, 6, 5, 4, 4, 3, 2};
    return kWidth[std::min<std::size_t>(static_cast<std::size_t>(c), std::size(kWidth) - 1)];
}

float cross2(glm::vec2 a, glm::vec2 b) { return a.x * b.y - a.y * b.x; }

bool inTriangle(glm::vec2 a, glm::vec2 b, glm::vec2 c, glm::vec2 p) {
    const float d0 = cross2(b - a, p - a), d1 = cross2(c - b, p - b), d2 = cross2(a - c, p - c);
    return !((d0 < 0 || d1 < 0 || d2 < 0) && (d0 > 0 || d1 > 0 || d2 > 0));
}

// Clears the texels whose centres lie within `radius` of p.
void clearDisc(std::vector<std::uint8_t>& mask, int n, float texel, glm::vec2 p, float radius) {
    const int c0 = std::max(0, static_cast<int>((p.x - radius) / texel));
    const int c1 = std::min(n - 1, static_cast<int>((p.x + radius) / texel));
    const int r0 = std::max(0, static_cast<int>((p.y - radius) / texel));
    const int r1 = std::min(n - 1, static_cast<int>((p.y + radius) / texel));
    for (int r = r0; r <= r1; ++r) {
        for (int c = c0; c <= c1; ++c) {
            const glm::vec2 t((c + 0.5f) * texel, (r + 0.5f) * texel);
            if (glm::length(t - p) <= radius) mask[static_cast<std::size_t>(r) * n + c] = 0;
        }
    }
}

// Clears the texels whose centres lie in a building's footprint.
void clearFootprints(const map::Tile& tile, std::vector<std::uint8_t>& mask, int n, float texel) {
    for (const auto& b : tile.buildings) {
        const auto& f = b.footprint;
        for (std::size_t t = 0; t + 2 < f.indices.size(); t += 3) {
            const auto& v0 = f.vertices[f.indices[t]];
            const auto& v1 = f.vertices[f.indices[t + 1]];
            const auto& v2 = f.vertices[f.indices[t + 2]];
            const glm::vec2 a(v0.x, v0.y), bb(v1.x, v1.y), c(v2.x, v2.y);
            const glm::vec2 lo = glm::min(glm::min(a, bb), c), hi = glm::max(glm::max(a, bb), c);
            const int c0 = std::max(0, static_cast<int>(lo.x / texel)),
                      c1 = std::min(n - 1, static_cast<int>(hi.x / texel));
            const int r0 = std::max(0, static_cast<int>(lo.y / texel)),
                      r1 = std::min(n - 1, static_cast<int>(hi.y / texel));
            for (int r = r0; r <= r1; ++r) {
                for (int cc = c0; cc <= c1; ++cc) {
                    if (inTriangle(a, bb, c, {(cc + 0.5f) * texel, (r + 0.5f) * texel})) {
                        mask[static_cast<std::size_t>(r) * n + cc] = 0;
                    }
                }
            }
        }
    }
}

// The vegetation mask (seed: land cover defines the seeding areas, the vector map the non-seeding
// ones): forest and scrub texels, less roads and buildings.
std::vector<std::uint8_t> vegetationMask(const map::Tile& tile, float texel) {
    const auto& o = tile.ortho;
    const int n = o.cover_size;
    std::vector<std::uint8_t> mask(o.cover.size(), 0);
    for (std::size_t i = 0; i < mask.size(); ++i) {
        mask[i] = map::ortho::isVegetation(static_cast<SuperLandCover>(o.cover[i])) ? 1 : 0;
    }
    for (const auto& road : tile.roads) {
        const float half = roadClearance(road.cls);
        for (std::size_t k = 1; k < road.points.size(); ++k) {
            const glm::vec2 a(road.points[k - 1].x, road.points[k - 1].y), b(road.points[k].x, road.points[k].y);
            const int steps = std::max(1, static_cast<int>(glm::length(b - a) / (0.5f * texel)));
            for (int s = 0; s <= steps; ++s) clearDisc(mask, n, texel, glm::mix(a, b, float(s) / float(steps)), half);
        }
    }
    clearFootprints(tile, mask, n, texel);
    return mask;
}

// A plant while the simulation runs.
struct Live {
    Plant plant;
    float growth = 0;  // growth factor here (timber line)
    float water = 0;
    bool alive = true;
};

float suitability(const Species& s, float w, float growth) { return growth * (1.0f - std::abs(w - s.wet_preference)); }

// The plants of one tile, step by step; the counts go to `result`.
class VegetationSim {
public:
    VegetationSim(const map::Tile& tile, const VegetationOptions& opt, std::vector<std::uint8_t> mask,
                  VegetationResult& result)
        : m_tile(tile),
          m_opt(opt),
          m_sampler(tile),
          m_n(tile.ortho.cover_size),
          m_g(tile.ortho.grid_size),
          m_size(static_cast<float>(tile.size_m)),
          m_texel(m_size / static_cast<float>(m_n)),
          m_spacing(m_size / static_cast<float>(m_g - 1)),
          m_mask(std::move(mask)),
          m_rng(map::ortho::mixSeed(0x76656765ULL, tile.id.key())),
          m_result(result) {
        float max_radius = 0;
        for (const auto& s : opt.species) max_radius = std::max(max_radius, s.max_radius_m);
        m_cell = 2.0f * max_radius;  // plants that can touch lie in the same or neighbouring cells
        m_cells = std::max(1, static_cast<int>(std::ceil(m_size / m_cell)));
        m_start.resize(static_cast<std::size_t>(m_cells) * static_cast<std::size_t>(m_cells) + 1);
    }

    /// The initial plants, one per initial_spacing_m^2 of the `seeding` texels.
    void seed(std::size_t seeding) {
        const auto initial = static_cast<std::size_t>(static_cast<double>(seeding) * m_texel * m_texel /
                                                      (m_opt.initial_spacing_m * m_opt.initial_spacing_m));
        for (std::size_t k = 0; k < initial; ++k) {
            add({static_cast<float>(m_rng.uniform(0, m_size)), static_cast<float>(m_rng.uniform(0, m_size))}, -1);
        }
    }
    void step() {
        const std::size_t before = m_plants.size();
        grow(before);
        spreadSeeds(before);
        sortByCell();
        compete();
        std::erase_if(m_plants, [](const Live& l) { return !l.alive; });
    }
    /// The live plants into the result, with their pair-wise brightness changes.
    void finish();

private:
    bool seedable(glm::vec2 p) const {
        if (p.x < 0 || p.y < 0 || p.x >= m_size || p.y >= m_size) return false;
        const int c = std::min(m_n - 1, static_cast<int>(p.x / m_texel)),
                  r = std::min(m_n - 1, static_cast<int>(p.y / m_texel));
        return m_mask[static_cast<std::size_t>(r) * m_n + c] != 0;
    }
    // The nearest grid sample of a layer (slope and aspect: the water estimate needs no more).
    float nearest(const std::vector<std::uint8_t>& layer, glm::vec2 p) const {
        const int c = std::clamp(static_cast<int>(std::lround(p.x / m_spacing)), 0, m_g - 1);
        const int r = std::clamp(static_cast<int>(std::lround(p.y / m_spacing)), 0, m_g - 1);
        return static_cast<float>(layer[static_cast<std::size_t>(r) * m_g + c]);
    }
    float water(glm::vec2 p, const map::ortho::OrthoPixel& px) const;
    void add(glm::vec2 p, int species);
    int cellOf(glm::vec2 p) const {
        return std::clamp(static_cast<int>(p.y / m_cell), 0, m_cells - 1) * m_cells +
               std::clamp(static_cast<int>(p.x / m_cell), 0, m_cells - 1);
    }
    float ability(const Live& l) const {
        const Species& s = m_opt.species[l.plant.species];
        return (1.0f - std::abs(l.water - s.wet_preference)) * std::sqrt(l.plant.radius_m / s.max_radius_m) * l.growth;
    }
    void grow(std::size_t before);
    void spreadSeeds(std::size_t before);
    void sortByCell();
    void compete();

    const map::Tile& m_tile;
    const VegetationOptions& m_opt;
    const map::ortho::OrthoTileSampler m_sampler;
    const int m_n, m_g;
    const float m_size, m_texel, m_spacing;
    const std::vector<std::uint8_t> m_mask;
    Rng m_rng;
    VegetationResult& m_result;
    std::vector<Live> m_plants;
    float m_cell = 0;
    int m_cells = 1;
    // The grid as sorted plants: each step the live plants are counting-sorted by cell, so a cell's
    // plants lie together in memory between m_start[cell] and m_start[cell + 1].
    std::vector<std::uint32_t> m_start;
    std::vector<Live> m_sorted;
};

// Water available (the seed takes an available water capacity map, which the tile does not
// carry): wetter with more rain, on gentle slopes and on north-facing ones.
float VegetationSim::water(glm::vec2 p, const map::ortho::OrthoPixel& px) const {
    const float rain = std::clamp(std::sqrt((px.precip_dec_mm + px.precip_jul_mm) / 300.0f), 0.0f, 1.0f);
    const float slope = nearest(m_tile.ortho.slope, p);
    const float aspect_deg = nearest(m_tile.ortho.aspect, p) * 360.0f / 256.0f;
    const float north = 0.5f + 0.5f * std::cos(aspect_deg * std::numbers::pi_v<float> / 180.0f);
    return std::clamp(0.5f * rain + 0.3f * (1.0f - slope / 45.0f) + 0.2f * (slope > 3.0f ? north : 0.5f), 0.0f, 1.0f);
}

// A plant of `species` at p; species < 0: the species drawn by its suitability there.
void VegetationSim::add(glm::vec2 p, int species) {
    if (m_plants.size() >= m_opt.max_plants || !seedable(p)) return;
    const map::ortho::OrthoPixel px = m_sampler.pixel(p.x, p.y);
    const float h = px.elevation_m, w = water(p, px);
    if (species < 0) {
        // Initial plants: the species drawn by its suitability here.
        float total = 0;
        for (const auto& s : m_opt.species) total += suitability(s, w, growthFactor(s, h));
        if (total <= 0) return;
        float pick = static_cast<float>(m_rng.uniform()) * total;
        species = 0;
        for (std::size_t k = 0; k < m_opt.species.size(); ++k) {
            pick -= suitability(m_opt.species[k], w, growthFactor(m_opt.species[k], h));
            if (pick <= 0) {
                species = static_cast<int>(k);
                break;
            }
        }
    }
    const float gf = growthFactor(m_opt.species[static_cast<std::size_t>(species)], h);
    if (gf <= 0.0f) return;  // at or above its timber line no plant of this species grows
    Live l;
    l.plant.position = p;
    l.plant.radius_m = 0.3f;
    l.plant.species = static_cast<std::uint8_t>(species);
    l.growth = gf;
    l.water = w;
    m_plants.push_back(l);
    ++m_result.seeded;
}

// 1. Growth; a plant past its maximum size dies.
void VegetationSim::grow(std::size_t before) {
    for (std::size_t i = 0; i < before; ++i) {
        Live& l = m_plants[i];
        const Species& s = m_opt.species[l.plant.species];
        l.plant.radius_m += s.growth_m * l.growth;
        if (l.plant.radius_m > s.max_radius_m) {
            l.alive = false;
            ++m_result.died_old;
        }
    }
}

// 2. Seeds around the grown plants.
void VegetationSim::spreadSeeds(std::size_t before) {
    for (std::size_t i = 0; i < before; ++i) {
        if (!m_plants[i].alive) continue;
        const Species& s = m_opt.species[m_plants[i].plant.species];
        if (m_plants[i].plant.radius_m < 0.5f * s.max_radius_m) continue;
        const glm::vec2 p = m_plants[i].plant.position;
        const int species = m_plants[i].plant.species;
        for (int k = 0; k < s.seeds; ++k) {
            const double a = m_rng.uniform(0, 2 * std::numbers::pi), d = m_rng.uniform(0.5, 1.0) * s.seed_distance_m;
            add(p + glm::vec2(std::cos(a), std::sin(a)) * static_cast<float>(d), species);
        }
    }
}

// The live plants counting-sorted by cell (m_start).
void VegetationSim::sortByCell() {
    std::fill(m_start.begin(), m_start.end(), 0u);
    for (const Live& l : m_plants) {
        if (l.alive) ++m_start[static_cast<std::size_t>(cellOf(l.plant.position)) + 1];
    }
    for (std::size_t c = 1; c < m_start.size(); ++c) m_start[c] += m_start[c - 1];
    m_sorted.resize(m_start.back());
    {
        std::vector<std::uint32_t> fill(m_start.begin(), m_start.end() - 1);
        for (const Live& l : m_plants) {
            if (l.alive) m_sorted[fill[static_cast<std::size_t>(cellOf(l.plant.position))]++] = l;
        }
    }
    m_plants.swap(m_sorted);
}

// 3. Competition: of two intersecting plants the weaker dies.
void VegetationSim::compete() {
    for (std::size_t i = 0; i < m_plants.size(); ++i) {
        Live& a = m_plants[i];
        if (!a.alive) continue;
        const int c = cellOf(a.plant.position), cx = c % m_cells, cy = c / m_cells;
        for (int rr = std::max(cy - 1, 0); rr <= std::min(cy + 1, m_cells - 1) && a.alive; ++rr) {
            for (int cc = std::max(cx - 1, 0); cc <= std::min(cx + 1, m_cells - 1) && a.alive; ++cc) {
                const auto k =
                    static_cast<std::size_t>(rr) * static_cast<std::size_t>(m_cells) + static_cast<std::size_t>(cc);
                for (std::size_t j = std::max<std::size_t>(m_start[k], i + 1); j < m_start[k + 1]; ++j) {
                    Live& b = m_plants[j];
                    if (!b.alive) continue;
                    const float touch = a.plant.radius_m + b.plant.radius_m;
                    const glm::vec2 d = a.plant.position - b.plant.position;
                    if (glm::dot(d, d) >= touch * touch) continue;
                    (ability(a) >= ability(b) ? b : a).alive = false;
                    ++m_result.died_competing;
                    if (!a.alive) break;
                }
            }
        }
    }
}

void VegetationSim::finish() {
    m_result.plants.reserve(m_plants.size());
    for (const Live& l : m_plants) m_result.plants.push_back(l.plant);
    // Pair-wise brightness changes (seed 6.7.5), weighted by crown area so that a pair's mean colour
    // is the network's: the larger crown of the pair takes the smaller change.
    for (std::size_t k = 0; k + 1 < m_result.plants.size(); k += 2) {
        Plant &a = m_result.plants[k], &b = m_result.plants[k + 1];
        const auto v = static_cast<float>(m_rng.uniform(0.08, 0.2));
        const float wa = a.radius_m * a.radius_m, wb = b.radius_m * b.radius_m, big = std::max(wa, wb);
        a.variation = v * wb / big;
        b.variation = -v * wa / big;
    }
}

}  // namespace

std::vector<Species> defaultSpecies() {
    return {{"broadleaf", 6.0f, 0.6f, 2, 12.0f, 0.8f, 1800.0f, 600.0f},
            {"conifer", 4.5f, 0.45f, 2, 10.0f, 0.35f, 2300.0f, 500.0f},
            {"shrub", 2.5f, 0.35f, 3, 6.0f, 0.1f, 2700.0f, 500.0f}};
}

float growthFactor(const Species& s, float elevation_m) {
    if (elevation_m >= s.timber_line_m) return 0.0f;
    return std::clamp((s.timber_line_m - elevation_m) / std::max(s.transition_m, 1.0f), 0.0f, 1.0f);
}

VegetationResult simulateVegetation(const map::Tile& tile, const VegetationOptions& opt) {
    VegetationResult result;
    if (tile.ortho.empty() || opt.species.empty() || !map::ortho::orthoLayersProblem(tile).empty()) return result;
    const float texel = static_cast<float>(tile.size_m) / static_cast<float>(tile.ortho.cover_size);
    std::vector<std::uint8_t> mask = vegetationMask(tile, texel);
    std::size_t seeding = 0;
    for (std::uint8_t m : mask) seeding += m;
    if (seeding == 0) return result;
    VegetationSim sim(tile, opt, std::move(mask), result);
    sim.seed(seeding);
    for (int step = 0; step < opt.steps; ++step) sim.step();
    sim.finish();
    return result;
}

}  // namespace navmap::render::ortho
