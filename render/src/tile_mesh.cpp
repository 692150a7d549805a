// SPDX-License-Identifier: Apache-2.0
#include "tile_mesh.h"
#include "navmap/map/feature_classes.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numeric>

#include "navmap/map/geometry.h"
#include "navmap/render/terrain_lod.h"

namespace navmap::render {

namespace {

glm::vec4 rgba(unsigned hex, float a) {
    return glm::vec4(glm::vec3((hex >> 16) & 0xff, (hex >> 8) & 0xff, hex & 0xff) / 255.0f, a);
}

glm::vec3 buildingColor(float height_m) {
    // Taller buildings a little lighter, so the skyline reads; warm stone tones of the valley.
    const float t = std::clamp(height_m / 30.0f, 0.0f, 1.0f);
    return glm::mix(glm::vec3(0.80f, 0.74f, 0.68f), glm::vec3(0.90f, 0.87f, 0.84f), t);
}

// Central-difference normal of a grid sample (one-sided at the border), as the terrain mesh uses.
glm::vec3 gridNormal(const HeightGrid& g, int r, int c) {
    const int n = g.size;
    const int c0 = std::max(c - 1, 0), c1 = std::min(c + 1, n - 1);
    const int r0 = std::max(r - 1, 0), r1 = std::min(r + 1, n - 1);
    const auto dzdx = static_cast<float>((g.at(r, c1) - g.at(r, c0)) / ((c1 - c0) * g.spacing));
    const auto dzdy = static_cast<float>((g.at(r1, c) - g.at(r0, c)) / ((r1 - r0) * g.spacing));
    return glm::normalize(glm::vec3(-dzdx, -dzdy, 1.0f));
}

// Barycentric weights of (x, y) in the grid triangle containing it (HeightGrid's split along
// the cell's south-west -> north-east diagonal), with the three sample indices.
struct GridWeights {
    std::array<std::size_t, 3> index;
    std::array<double, 3> weight;
};

GridWeights gridWeights(const HeightGrid& g, double x, double y) {
    const int cells = g.size - 1;
    const double u = std::clamp(x / g.spacing, 0.0, double(cells)), v = std::clamp(y / g.spacing, 0.0, double(cells));
    const int col = std::clamp(static_cast<int>(std::floor(u)), 0, cells - 1);
    const int row = std::clamp(static_cast<int>(std::floor(v)), 0, cells - 1);
    const double fx = u - col, fy = v - row;
    const auto at = [&](int r, int c) { return static_cast<std::size_t>(r) * g.size + c; };
    if (fy <= fx) return {{at(row, col), at(row, col + 1), at(row + 1, col + 1)}, {1.0 - fx, fx - fy, fy}};  // SW SE NE
    return {{at(row, col), at(row + 1, col + 1), at(row + 1, col)}, {1.0 - fy, fx, fy - fx}};                // SW NE NW
}

// Distance of p from the segment a-b in 3D (the road levels' simplification error). Not GLM's
// closestPointOnLine: it divides by the segment's length, and a closed way's chord has none.
double segmentDistance(const glm::dvec3& p, const glm::dvec3& a, const glm::dvec3& b) {
    const glm::dvec3 d = b - a;
    const double len2 = glm::dot(d, d);
    const double t = len2 > 0.0 ? std::clamp(glm::dot(p - a, d) / len2, 0.0, 1.0) : 0.0;
    return glm::length(p - (a + t * d));
}

}  // namespace

float jointCapReach(glm::vec2 from, glm::vec2 to) {
    const float lengths = glm::length(from) * glm::length(to);
    if (!(lengths > 1e-12f)) return 1.0f;  // a piece without length in plan has no direction to trim along
    // The outer wedge between the two bodies lies within the round join; both quads reach into it,
    // so each needs only what the other leaves: the wedge's points lie at most sin(turn / 2) half
    // widths beyond the joint along one piece or the other (the farthest on the bisector).
    const float cos_turn = std::clamp(glm::dot(from, to) / lengths, -1.0f, 1.0f);
    const float sin_half_turn = std::sqrt(0.5f * (1.0f - cos_turn));
    return std::min(1.0f, sin_half_turn + kJointOverlap);
}

void ancestorSurface(const map::Tile& tile, int n, std::span<const float> heights, const map::Tile* ancestor,
                     int levels_up, std::vector<float>& out_heights, std::vector<glm::vec3>& out_normals) {
    const std::size_t count = static_cast<std::size_t>(n) * n;
    out_heights.assign(count, 0.0f);
    out_normals.assign(count, glm::vec3(0.0f, 0.0f, 1.0f));
    if (n < 2 || heights.size() != count) return;
    const double spacing = tile.size_m / (n - 1);
    const int stride = 1 << std::clamp(levels_up, 0, 16);
    // The ancestor's grid and where the tile's south-west corner sits in it.
    std::vector<float> decimated;
    HeightGrid ag;
    glm::dvec2 offset(0.0);
    const bool has_ancestor = ancestor && ancestor->dem.size >= 2 && ancestor->size_m > 0 &&
                              ancestor->dem.heights.size() == std::size_t{ancestor->dem.size} * ancestor->dem.size;
    if (has_ancestor) {
        ag = HeightGrid{ancestor->dem.size, ancestor->size_m / (ancestor->dem.size - 1), ancestor->dem.heights.data()};
        offset = {tile.origin_x - ancestor->origin_x, tile.origin_y - ancestor->origin_y};
    } else if ((n - 1) % stride == 0 && n > stride) {
        // Not at hand: the coarser grid of every stride-th own sample (CDLOD's usual target).
        const int m = (n - 1) / stride + 1;
        decimated.resize(static_cast<std::size_t>(m) * m);
        for (int r = 0; r < m; ++r)
            for (int c = 0; c < m; ++c)
                decimated[static_cast<std::size_t>(r) * m + c] =
                    heights[static_cast<std::size_t>(stride * r) * n + stride * c];
        ag = HeightGrid{m, stride * spacing, decimated.data()};
    } else {
        ag = HeightGrid{n, spacing, heights.data()};  // too coarse a grid to decimate: its own surface
    }
    std::vector<glm::vec3> an(static_cast<std::size_t>(ag.size) * ag.size);
    for (int r = 0; r < ag.size; ++r)
        for (int c = 0; c < ag.size; ++c) an[static_cast<std::size_t>(r) * ag.size + c] = gridNormal(ag, r, c);
    for (int r = 0; r < n; ++r) {
        for (int c = 0; c < n; ++c) {
            const GridWeights w = gridWeights(ag, offset.x + c * spacing, offset.y + r * spacing);
            double h = 0.0;
            glm::vec3 nrm(0.0f);
            for (std::size_t k = 0; k < 3; ++k) {
                h += w.weight[k] * ag.heights[w.index[k]];
                nrm += static_cast<float>(w.weight[k]) * an[w.index[k]];
            }
            const std::size_t i = static_cast<std::size_t>(r) * n + c;
            out_heights[i] = static_cast<float>(h);
            out_normals[i] = glm::normalize(nrm);
        }
    }
}

int roadDrawOrder(const map::Road& road) {
    const bool bridge = (road.flags & map::road_flags::kBridge) != 0;
    const int layer = std::clamp(static_cast<int>(road.layer), -5, 5) + 5;
    return layer * 2000 + (bridge ? 1000 : 0) + (map::kRoadClassCount - static_cast<int>(road.cls));
}

double bridgeDeckHeightM(int layer) { return 2.0 + 4.0 * std::max(0, layer - 1); }

glm::vec4 landCoverColor(map::AreaClass cls) {
    using A = map::AreaClass;
    switch (cls) {
        case A::Water: return rgba(0x8fb8de, 1.0f);
        case A::Wetland: return rgba(0xa8c8b8, 0.7f);
        case A::Glacier: return rgba(0xf4f8fc, 0.95f);
        case A::Forest: return rgba(0x5d8a4e, 0.8f);
        case A::Scrub: return rgba(0x93a86a, 0.6f);
        case A::Grass: return rgba(0xa9c77c, 0.6f);
        case A::Farmland: return rgba(0xd6d39a, 0.6f);
        case A::Rock: return rgba(0xb5aca2, 0.7f);
        case A::Residential: return rgba(0xd9d2cc, 0.8f);
        case A::Commercial: return rgba(0xe6cfcf, 0.8f);
        case A::Industrial: return rgba(0xd4c8d8, 0.8f);
        case A::Park: return rgba(0xb5d69a, 0.7f);
        case A::Sport: return rgba(0x9fd6b2, 0.7f);
        case A::Cemetery: return rgba(0xaac4a0, 0.7f);
        case A::Military: return rgba(0xd8b0a8, 0.5f);
        case A::Other: return rgba(0xc8c8b0, 0.3f);
        // Opaque: the terrain's hypsometric tint at 0 m (green) must not show through. A little
        // deeper than inland water, so coast and lakes read apart. Night: MapStyle::brightness.
        case A::Sea: return rgba(0x7fa9d6, 1.0f);
        // Over the water (drawn after it): piers and breakwaters opaque in a pale stone colour;
        // a marina or harbour a faint deep-blue tint blended over whatever lies under it.
        case A::Pier: return rgba(0xe4e0d8, 1.0f);
        case A::Harbour: return rgba(0x3f6f9f, 0.25f);
    }
    return rgba(0xc8c8b0, 0.3f);
}

std::vector<LandCoverVertex> landCoverTriangles(const map::Tile& tile) {
    std::vector<const map::Area*> areas;
    for (const auto& a : tile.areas) areas.push_back(&a);
    std::stable_sort(areas.begin(), areas.end(), [](const map::Area* a, const map::Area* b) {
        return map::areaDrawOrder(a->cls) < map::areaDrawOrder(b->cls);
    });
    std::vector<LandCoverVertex> out;
    for (const map::Area* a : areas) {
        const glm::vec4 color = landCoverColor(a->cls);
        const bool tint = map::areaIsTint(a->cls);
        for (std::uint32_t i : a->polygon.indices) {
            if (i >= a->polygon.vertices.size()) continue;
            const auto& p = a->polygon.vertices[i];
            out.push_back({glm::vec2(p.x, p.y), color, tint});
        }
    }
    return out;
}

TileMesh buildTileMesh(const map::Tile& tile, const TileMeshOptions& options,
                       std::span<const map::Tile* const> ancestors) {
    TileMesh mesh;
    mesh.id = tile.id;
    mesh.origin = glm::dvec3(tile.origin_x, tile.origin_y, 0.0);
    mesh.size_m = static_cast<float>(tile.size_m);

    // --- terrain grid (flat at 0 m where the tile has no DEM: the store warned at compile time)
    if (tile.dem.size >= 2 && tile.dem.heights.size() == std::size_t{tile.dem.size} * tile.dem.size) {
        mesh.grid_size = tile.dem.size;
        mesh.heights = tile.dem.heights;
    } else {
        mesh.grid_size = 2;
        mesh.heights.assign(4, 0.0f);
    }
    const int n = mesh.grid_size;
    const double spacing = tile.size_m / (n - 1);
    const auto [lo, hi] = std::minmax_element(mesh.heights.begin(), mesh.heights.end());
    mesh.min_height = *lo;
    mesh.max_height = *hi;
    mesh.terrain.resize(static_cast<std::size_t>(n) * n);
    auto h = [&](int r, int c) {
        return mesh.heights[static_cast<std::size_t>(std::clamp(r, 0, n - 1)) * n + std::clamp(c, 0, n - 1)];
    };
    for (int r = 0; r < n; ++r) {
        for (int c = 0; c < n; ++c) {
            // Central differences (one-sided at the border).
            const int c0 = std::max(c - 1, 0), c1 = std::min(c + 1, n - 1);
            const int r0 = std::max(r - 1, 0), r1 = std::min(r + 1, n - 1);
            const float dzdx = (h(r, c1) - h(r, c0)) / static_cast<float>((c1 - c0) * spacing);
            const float dzdy = (h(r1, c) - h(r0, c)) / static_cast<float>((r1 - r0) * spacing);
            mesh.terrain[static_cast<std::size_t>(r) * n + c] = {
                glm::vec3(static_cast<float>(c * spacing), static_cast<float>(r * spacing), h(r, c)),
                glm::normalize(glm::vec3(-dzdx, -dzdy, 1.0f))};
        }
    }
    // Geomorph targets (terrain_lod.h): the coarser levels' surfaces at every grid vertex.
    std::vector<glm::vec3> normals;
    for (int j = 0; j < kMorphLevels; ++j) {
        const auto k = static_cast<std::size_t>(j);
        const map::Tile* ancestor = k < ancestors.size() ? ancestors[k] : nullptr;
        ancestorSurface(tile, n, mesh.heights, ancestor, j + 1, mesh.ancestor_heights[k], normals);
        for (std::size_t i = 0; i < mesh.terrain.size(); ++i) {
            mesh.terrain[i].ancestor_heights[k] = mesh.ancestor_heights[k][i];
            mesh.terrain[i].ancestor_normals[k] = glm::vec2(normals[i]);
        }
    }
    // Skirts: a curtain hanging from every border vertex, so a coarser neighbour never shows a
    // crack through to the sky.
    std::vector<std::uint32_t> skirt_of(mesh.terrain.size(), 0);  // border vertex -> its skirt vertex
    auto add_skirt = [&](int r, int c) {
        const auto v = static_cast<std::size_t>(r) * n + c;
        if (skirt_of[v]) return;
        TerrainVertex s = mesh.terrain[v];
        s.position.z -= options.skirt_depth_m;
        for (float& a : s.ancestor_heights) a -= options.skirt_depth_m;  // morphs with its border vertex
        skirt_of[v] = static_cast<std::uint32_t>(mesh.terrain.size());
        mesh.terrain.push_back(s);
    };
    for (int i = 0; i < n; ++i) {
        add_skirt(0, i);
        add_skirt(n - 1, i);
        add_skirt(i, 0);
        add_skirt(i, n - 1);
    }
    auto vertex = [&](int r, int c) { return static_cast<std::uint32_t>(r * n + c); };
    // Border segment a -> b runs counter-clockwise round the tile (seen from above), so the
    // curtain faces outwards.
    auto skirt_segment = [&](std::uint32_t a, std::uint32_t b) {
        mesh.terrain_indices.insert(mesh.terrain_indices.end(), {a, skirt_of[a], skirt_of[b], a, skirt_of[b], b});
    };
    // The grid in kTerrainBlocks^2 square blocks, each with its part of the skirts, so a block
    // can be drawn alone (the renderer picks per block which land-cover levels it needs).
    const int blocks = std::min(kTerrainBlocks, n - 1);
    for (int by = 0; by < blocks; ++by) {
        for (int bx = 0; bx < blocks; ++bx) {
            const int r0 = (n - 1) * by / blocks, r1 = (n - 1) * (by + 1) / blocks;
            const int c0 = (n - 1) * bx / blocks, c1 = (n - 1) * (bx + 1) / blocks;
            TerrainBlock block;
            block.first = static_cast<std::uint32_t>(mesh.terrain_indices.size());
            block.min = glm::vec2(static_cast<float>(c0 * spacing), static_cast<float>(r0 * spacing));
            block.max = glm::vec2(static_cast<float>(c1 * spacing), static_cast<float>(r1 * spacing));
            for (int r = r0; r < r1; ++r) {
                for (int c = c0; c < c1; ++c) {
                    // The split of HeightGrid (gridTriangleIndices).
                    const auto sw = vertex(r, c), se = vertex(r, c + 1), nw = vertex(r + 1, c),
                               ne = vertex(r + 1, c + 1);
                    mesh.terrain_indices.insert(mesh.terrain_indices.end(), {sw, se, ne, sw, ne, nw});
                }
            }
            for (int c = c0; by == 0 && c < c1; ++c) skirt_segment(vertex(0, c), vertex(0, c + 1));
            for (int r = r0; bx == blocks - 1 && r < r1; ++r) skirt_segment(vertex(r, n - 1), vertex(r + 1, n - 1));
            for (int c = c0; by == blocks - 1 && c < c1; ++c) skirt_segment(vertex(n - 1, c + 1), vertex(n - 1, c));
            for (int r = r0; bx == 0 && r < r1; ++r) skirt_segment(vertex(r + 1, 0), vertex(r, 0));
            block.count = static_cast<std::uint32_t>(mesh.terrain_indices.size()) - block.first;
            block.min_z = std::numeric_limits<float>::max();
            block.max_z = std::numeric_limits<float>::lowest();
            for (std::uint32_t i = block.first; i < block.first + block.count; ++i) {
                const TerrainVertex& v = mesh.terrain[mesh.terrain_indices[i]];
                const auto [lowest, highest] =
                    std::minmax_element(v.ancestor_heights.begin(), v.ancestor_heights.end());
                block.min_z = std::min({block.min_z, v.position.z, *lowest});
                block.max_z = std::max({block.max_z, v.position.z, *highest});
            }
            mesh.terrain_blocks.push_back(block);
        }
    }
    const HeightGrid grid = mesh.grid();

    mesh.land_cover = landCoverTriangles(tile);

    // --- roads: draped onto the grid (seed 3.6.1), one instance per piece (seed 3.4)
    struct Piece {
        RoadInstance inst;
        int order;
        std::uint32_t block = 0;
        std::uint32_t lods = 1;  // level 0
    };
    std::vector<Piece> pieces;
    // The block (as terrain_blocks, row-major) holding a tile-local point.
    const float block_size = mesh.size_m / static_cast<float>(blocks);
    auto block_of = [&](glm::vec2 p) {
        const int bx = std::clamp(static_cast<int>(std::floor(p.x / block_size)), 0, blocks - 1);
        const int by = std::clamp(static_cast<int>(std::floor(p.y / block_size)), 0, blocks - 1);
        return static_cast<std::uint32_t>(by * blocks + bx);
    };
    std::vector<glm::dvec2> line;
    for (const auto& road : tile.roads) {
        if (road.points.size() < 2) continue;
        mesh.source_road_vertices += road.points.size();
        if (road.flags & map::road_flags::kTunnel) continue;  // tunnels are hidden in the map view
        line.clear();
        for (const auto& p : road.points) line.emplace_back(p.x, p.y);
        std::vector<glm::dvec3> draped;
        const bool bridge = (road.flags & map::road_flags::kBridge) != 0;
        if (bridge || !options.drape_roads) {
            // A bridge spans straight between its ends (drawn above what it crosses).
            draped.reserve(line.size());
            const double z0 = grid.heightAt(line.front().x, line.front().y);
            const double z1 = grid.heightAt(line.back().x, line.back().y);
            double total = 0.0, run = 0.0;
            for (std::size_t i = 1; i < line.size(); ++i) total += glm::length(line[i] - line[i - 1]);
            for (std::size_t i = 0; i < line.size(); ++i) {
                if (i > 0) run += glm::length(line[i] - line[i - 1]);
                const double z = bridge
                                     ? z0 + (z1 - z0) * (total > 0 ? run / total : 0.0) + bridgeDeckHeightM(road.layer)
                                     : grid.heightAt(line[i].x, line[i].y);
                draped.emplace_back(line[i].x, line[i].y, z);
            }
        } else {
            draped = drapePolyline(grid, line);
            if (options.road_merge_tolerance_m > 0.0)
                draped = mergeDrapedPieces(draped, options.road_merge_tolerance_m);
        }
        const int order = roadDrawOrder(road);
        auto piece = [&](const glm::dvec3& a, const glm::dvec3& b, std::uint32_t block, std::uint32_t lods) {
            RoadInstance inst{glm::vec3(a), glm::vec3(b), static_cast<float>(road.cls), static_cast<float>(road.flags)};
            inst.cap_reach = glm::vec2(0.0f);  // set per level below, from the piece's neighbours
            pieces.push_back({inst, order, block, lods});
        };
        // seed 3.4's caps where pieces join: along each level's chain within a span, a piece
        // reaches beyond a joint only as far as the bend needs (jointCapReach), the most that any
        // of its levels needs. A span's ends keep whole caps: the next block may be drawn at
        // another level. (Other roads meeting here are unaffected: the joined pieces still cover
        // their whole round join between them.)
        auto join = [&](const std::vector<std::size_t>& chain) {
            pieces[chain.front()].inst.cap_reach.x = 1.0f;
            pieces[chain.back()].inst.cap_reach.y = 1.0f;
            for (std::size_t c = 0; c + 1 < chain.size(); ++c) {
                RoadInstance& from = pieces[chain[c]].inst;
                RoadInstance& to = pieces[chain[c + 1]].inst;
                const float reach = jointCapReach(glm::vec2(from.p1 - from.p0), glm::vec2(to.p1 - to.p0));
                from.cap_reach.y = std::max(from.cap_reach.y, reach);
                to.cap_reach.x = std::max(to.cap_reach.x, reach);
            }
        };
        std::vector<std::size_t> chain;
        const std::size_t first = pieces.size();
        for (std::size_t i = 0; i + 1 < draped.size(); ++i) {
            piece(draped[i], draped[i + 1],
                  block_of(0.5f * (glm::vec2(glm::dvec2(draped[i])) + glm::vec2(glm::dvec2(draped[i + 1])))), 1u);
        }
        // The coarser levels, per span of the road in one block: draped vertices a .. b.
        const std::size_t last = pieces.size();
        for (std::size_t a = first; a < last;) {
            const std::uint32_t block = pieces[a].block;
            std::size_t b = a + 1;
            while (b < last && pieces[b].block == block) ++b;
            const std::span<const glm::dvec3> span(draped.data() + (a - first), b - a + 1);
            struct Chord {
                std::size_t from, to, piece;
            };
            std::vector<Chord> chords;  // the pieces added for this span (the levels' kept sets nest)
            chain.resize(b - a);
            std::iota(chain.begin(), chain.end(), a);
            join(chain);
            for (int k = 1; k < kRoadLods; ++k) {
                const std::vector<char> keep =
                    map::douglasPeucker(span.size(), kRoadLodTolerance[static_cast<std::size_t>(k)],
                                        [&](std::size_t v, std::size_t i, std::size_t j) {
                                            return segmentDistance(span[v], span[i], span[j]);
                                        });
                const std::uint32_t bit = 1u << k;
                chain.clear();
                for (std::size_t i = 0, j = 1; j < span.size(); ++j) {
                    if (!keep[j]) continue;
                    if (j == i + 1) {
                        chain.push_back(a + i);  // the draped piece itself
                    } else {
                        const auto chord = std::find_if(chords.begin(), chords.end(),
                                                        [&](const Chord& c) { return c.from == i && c.to == j; });
                        if (chord != chords.end()) {
                            chain.push_back(chord->piece);
                        } else {
                            chords.push_back({i, j, pieces.size()});
                            chain.push_back(pieces.size());
                            piece(span[i], span[j], block, 0u);
                        }
                    }
                    pieces[chain.back()].lods |= bit;
                    i = j;
                }
                join(chain);
            }
            a = b;
        }
    }
    // Within a group the pieces run block by block (the order among pieces of one class does not
    // matter: casings and fills are separate passes), so the renderer can leave out the blocks
    // outside the view and still draw the groups in order.
    auto extend = [](BlockExtent& e, glm::vec3 low, glm::vec3 high) {
        e.min = glm::min(e.min, low);
        e.max = glm::max(e.max, high);
    };
    const BlockExtent none{glm::vec3(std::numeric_limits<float>::max()),
                           glm::vec3(std::numeric_limits<float>::lowest())};
    mesh.road_blocks.assign(static_cast<std::size_t>(blocks * blocks), none);
    for (const Piece& p : pieces)
        extend(mesh.road_blocks[p.block], glm::min(p.inst.p0, p.inst.p1), glm::max(p.inst.p0, p.inst.p1));
    std::stable_sort(pieces.begin(), pieces.end(), [](const Piece& a, const Piece& b) {
        return a.order != b.order ? a.order < b.order : a.block != b.block ? a.block < b.block : a.lods < b.lods;
    });
    mesh.roads.reserve(pieces.size());
    for (std::size_t i = 0; i < pieces.size(); ++i) {
        const Piece& p = pieces[i];
        if (i == 0 || p.order != pieces[i - 1].order || p.block != pieces[i - 1].block || p.lods != pieces[i - 1].lods)
            mesh.road_runs.push_back({static_cast<std::uint32_t>(i), 0, p.block, p.lods});
        ++mesh.road_runs.back().count;
        mesh.roads.push_back(p.inst);
    }

    // --- buildings: walls and a flat roof over the lowest terrain point of the footprint; the
    // indices block by block (by the footprint's centre) for culling
    mesh.building_blocks.assign(static_cast<std::size_t>(blocks * blocks), none);
    std::vector<std::vector<std::uint32_t>> block_indices(mesh.building_blocks.size());
    for (const auto& b : tile.buildings) {
        const auto& fp = b.footprint;
        if (fp.vertices.size() < 3 || fp.ring_ends.empty()) continue;
        float base = std::numeric_limits<float>::max();
        glm::vec2 lo2(std::numeric_limits<float>::max()), hi2(std::numeric_limits<float>::lowest());
        for (std::uint32_t i = 0; i < fp.ring_ends.back(); ++i) {
            const auto& p = fp.vertices[i];
            base = std::min(base, static_cast<float>(grid.heightAt(p.x, p.y)));
            lo2 = glm::min(lo2, glm::vec2(p.x, p.y));
            hi2 = glm::max(hi2, glm::vec2(p.x, p.y));
        }
        const float size = glm::length(hi2 - lo2);
        const float bottom = base + b.min_height_m;
        const float top = base + std::max(b.height_m, b.min_height_m + 1.0f);
        const glm::vec3 color = buildingColor(b.height_m);
        const std::uint32_t block = block_of(0.5f * (lo2 + hi2));
        extend(mesh.building_blocks[block], glm::vec3(lo2, bottom), glm::vec3(hi2, top));
        std::vector<std::uint32_t>& indices = block_indices[block];
        // Roof.
        const auto roof_base = static_cast<std::uint32_t>(mesh.buildings.size());
        for (const auto& p : fp.vertices) mesh.buildings.push_back({{p.x, p.y, top}, {0, 0, 1}, color * 1.05f, size});
        for (std::uint32_t i : fp.indices) {
            if (i < fp.vertices.size()) indices.push_back(roof_base + i);
        }
        // Walls: one quad per ring edge, flat normal (per-face lighting).
        std::uint32_t start = 0;
        for (std::uint32_t end : fp.ring_ends) {
            for (std::uint32_t i = start; i < end; ++i) {
                const std::uint32_t j = (i + 1 < end) ? i + 1 : start;
                const glm::vec2 a(fp.vertices[i].x, fp.vertices[i].y), c(fp.vertices[j].x, fp.vertices[j].y);
                const glm::vec2 e = c - a;
                if (glm::dot(e, e) < 1e-6f) continue;
                // Outer rings are counter-clockwise, holes clockwise: (e.y, -e.x) points outwards for both.
                const glm::vec3 normal = glm::normalize(glm::vec3(e.y, -e.x, 0.0f));
                const auto w = static_cast<std::uint32_t>(mesh.buildings.size());
                mesh.buildings.push_back({{a, bottom}, normal, color, size});
                mesh.buildings.push_back({{c, bottom}, normal, color, size});
                mesh.buildings.push_back({{c, top}, normal, color, size});
                mesh.buildings.push_back({{a, top}, normal, color, size});
                indices.insert(indices.end(), {w, w + 1, w + 2, w, w + 2, w + 3});
            }
            start = end;
        }
    }
    for (std::size_t k = 0; k < block_indices.size(); ++k) {
        if (block_indices[k].empty()) continue;
        mesh.building_runs.push_back({static_cast<std::uint32_t>(mesh.building_indices.size()),
                                      static_cast<std::uint32_t>(block_indices[k].size()),
                                      static_cast<std::uint32_t>(k)});
        mesh.building_indices.insert(mesh.building_indices.end(), block_indices[k].begin(), block_indices[k].end());
    }
    return mesh;
}

namespace {

// A point of the route in tile-local metres with its distance along the route.
struct RoutePoint {
    glm::dvec2 p;
    double measure_m = 0.0;
};

// The route's runs over the square [0, e]^2 (tile-local): each a polyline of two points or more,
// split where the route leaves the square. `clipped` counts the segments overlapping it.
std::vector<std::vector<RoutePoint>> routeRunsInSquare(const RouteGeometry& route, const glm::dvec3& origin, double e,
                                                       std::size_t& clipped) {
    std::vector<std::vector<RoutePoint>> runs;
    bool open_end = false;  // the last run ends where its segment ends (not cut by the square)
    std::size_t last_segment = 0;
    for (std::size_t i = 0; i + 1 < route.points.size(); ++i) {
        const glm::dvec2 a(route.points[i].x - origin.x, route.points[i].y - origin.y);
        const glm::dvec2 b(route.points[i + 1].x - origin.x, route.points[i + 1].y - origin.y);
        if (std::max(a.x, b.x) < 0.0 || std::min(a.x, b.x) > e || std::max(a.y, b.y) < 0.0 || std::min(a.y, b.y) > e)
            continue;
        // Liang-Barsky clip of a -> b to the tile square.
        const glm::dvec2 d = b - a;
        double t0 = 0.0, t1 = 1.0;
        bool inside = true;
        const double p[4] = {-d.x, d.x, -d.y, d.y};
        const double q[4] = {a.x, e - a.x, a.y, e - a.y};
        for (int k = 0; k < 4 && inside; ++k) {
            if (p[k] == 0.0) {
                inside = q[k] >= 0.0;
            } else {
                const double t = q[k] / p[k];
                if (p[k] < 0.0)
                    t0 = std::max(t0, t);
                else
                    t1 = std::min(t1, t);
            }
        }
        if (!inside || t1 - t0 <= 1e-12) continue;
        if (glm::length(d) * (t1 - t0) < 1e-6) continue;
        ++clipped;
        const double m0 = route.measure_m[i], m1 = route.measure_m[i + 1];
        const RoutePoint q0{a + t0 * d, m0 + (m1 - m0) * t0};
        const RoutePoint q1{a + t1 * d, m0 + (m1 - m0) * t1};
        if (runs.empty() || !open_end || last_segment + 1 != i || t0 > 0.0) runs.push_back({q0});
        runs.back().push_back(q1);
        open_end = t1 >= 1.0;
        last_segment = i;
    }
    return runs;
}

double chordDistance(const glm::dvec2& p, const glm::dvec2& a, const glm::dvec2& b) {
    const glm::dvec2 ab = b - a;
    const double len2 = glm::dot(ab, ab);
    const double t = len2 > 0.0 ? std::clamp(glm::dot(p - a, ab) / len2, 0.0, 1.0) : 0.0;
    return glm::length(p - (a + t * ab));
}

// Which cells of an n x n raster over [0, e]^2 a segment's centreline passes (sampled every half
// cell), into `cells` (cleared first).
void coverageCells(const RoutePoint& a, const RoutePoint& b, double e, int n, std::vector<std::uint32_t>& cells) {
    cells.clear();
    const double cell = e / n;
    const double len = glm::length(b.p - a.p);
    const auto steps = static_cast<std::size_t>(std::ceil(len / (0.5 * cell))) + 1;
    for (std::size_t k = 0; k <= steps; ++k) {
        const glm::dvec2 p = glm::mix(a.p, b.p, double(k) / double(steps));
        const int c = std::clamp(static_cast<int>(p.x / cell), 0, n - 1);
        const int r = std::clamp(static_cast<int>(p.y / cell), 0, n - 1);
        const auto at = static_cast<std::uint32_t>(r * n + c);
        if (cells.empty() || cells.back() != at) cells.push_back(at);
    }
}

}  // namespace

std::vector<RoutePiece> drapeRoute(const RouteGeometry& route, const glm::dvec3& origin, const HeightGrid& grid,
                                   const std::array<HeightGrid, kMorphLevels>& ancestors,
                                   const RouteDrapeOptions& options, RouteDrapeCounts* counts) {
    RouteDrapeCounts local;
    RouteDrapeCounts& n = counts ? *counts : local;
    n = {};
    std::vector<RoutePiece> out;
    if (grid.size < 2 || route.points.size() < 2 || route.measure_m.size() != route.points.size()) return out;
    const double e = grid.extent();
    // Clipped to the tile, then each run inside it simplified to the view's tolerance: what is
    // draped depends on the tile and the tolerance, not on how densely the route is given.
    std::vector<std::pair<RoutePoint, RoutePoint>> segments;
    for (const std::vector<RoutePoint>& run : routeRunsInSquare(route, origin, e, n.segments_clipped)) {
        const std::vector<char> keep = map::douglasPeucker(
            run.size(), options.tolerance_m,
            [&](std::size_t k, std::size_t i, std::size_t j) { return chordDistance(run[k].p, run[i].p, run[j].p); });
        std::size_t from = 0;
        for (std::size_t j = 1; j < run.size(); ++j) {
            if (!keep[j]) continue;
            segments.emplace_back(run[from], run[j]);
            from = j;
        }
    }
    // seed 3.6.1: a vertex wherever a segment crosses a triangle edge of this tile's grid. False
    // when the segment would take the pieces over `limit` (nothing of it is added then).
    std::vector<glm::dvec2> seg(2);
    auto drape = [&](const RoutePoint& a, const RoutePoint& b, std::size_t limit) {
        seg[0] = a.p;
        seg[1] = b.p;
        const std::vector<glm::dvec3> draped = drapePolyline(grid, seg);
        if (draped.size() < 2) return true;
        if (out.size() + draped.size() - 1 > limit) return false;
        const double len = glm::length(b.p - a.p);
        auto measure_at = [&](const glm::dvec3& v) {
            return static_cast<float>(a.measure_m + (b.measure_m - a.measure_m) *
                                                        std::clamp(glm::length(glm::dvec2(v) - a.p) / len, 0.0, 1.0));
        };
        for (std::size_t k = 0; k + 1 < draped.size(); ++k) {
            const glm::dvec3& q0 = draped[k];
            const glm::dvec3& q1 = draped[k + 1];
            RoutePiece piece{glm::vec3(q0), glm::vec3(q1), {}, {}, measure_at(q0), measure_at(q1)};
            for (std::size_t j = 0; j < ancestors.size(); ++j) {
                if (!ancestors[j].heights) continue;
                piece.ancestor_z0[j] = static_cast<float>(ancestors[j].heightAt(q0.x, q0.y));
                piece.ancestor_z1[j] = static_cast<float>(ancestors[j].heightAt(q1.x, q1.y));
            }
            out.push_back(piece);
        }
        return true;
    };
    bool fits = true;
    for (const auto& [a, b] : segments) {
        if (!(fits = drape(a, b, options.max_pieces))) break;
    }
    if (fits) {
        n.segments_draped = segments.size();
        return out;
    }
    // Over the bound (a route that crosses the tile again and again): only the segments that
    // draw somewhere the route is not drawn yet, at the coverage raster's resolution, coarser
    // until they fit; at the coarsest, none beyond the bound.
    n.coverage_used = true;
    std::vector<char> covered;
    std::vector<std::uint32_t> cells;
    for (int cells_per_side = kRouteCoverageCells;; cells_per_side /= 2) {
        const bool last_try = cells_per_side <= kRouteCoverageCellsCoarsest;
        out.clear();
        n.segments_draped = n.segments_covered = n.segments_over_limit = 0;
        covered.assign(static_cast<std::size_t>(cells_per_side) * static_cast<std::size_t>(cells_per_side), 0);
        std::size_t covered_count = 0;
        bool full = false;
        for (const auto& [a, b] : segments) {
            if (full) {
                ++n.segments_over_limit;
                continue;
            }
            if (covered_count == covered.size()) {
                ++n.segments_covered;
                continue;
            }
            coverageCells(a, b, e, cells_per_side, cells);
            if (std::all_of(cells.begin(), cells.end(), [&](std::uint32_t c) { return covered[c] != 0; })) {
                ++n.segments_covered;
                continue;
            }
            if (!drape(a, b, options.max_pieces)) {
                full = true;
                ++n.segments_over_limit;
                if (!last_try) break;  // coarser cells
                continue;
            }
            ++n.segments_draped;
            for (const std::uint32_t c : cells) {
                covered_count += covered[c] == 0 ? 1 : 0;
                covered[c] = 1;
            }
        }
        if (!full || last_try) break;
    }
    return out;
}

void morphRoute(std::span<const RoutePiece> pieces, const TileMorph& morph, const glm::vec2& eye_local,
                std::vector<RoadInstance>& out) {
    out.clear();
    out.reserve(pieces.size());
    auto at = [&](glm::vec3 p, const std::array<float, kMorphLevels>& ancestor_z) {
        const glm::vec2 d = glm::vec2(p) - eye_local;
        p.z = morphedHeight(morphDistance(d.x, d.y, morph), morph, p.z, ancestor_z);
        return p;
    };
    for (const RoutePiece& r : pieces) {
        out.push_back({at(r.p0, r.ancestor_z0), at(r.p1, r.ancestor_z1), 0.0f, 0.0f, r.measure0, r.measure1});
    }
}

int roadLodLevel(float distance_m, float focal_px, float max_error_px) {
    int level = 0;
    for (int k = 1; k < kRoadLods; ++k) {
        if (kRoadLodTolerance[static_cast<std::size_t>(k)] * focal_px <= max_error_px * distance_m) level = k;
    }
    return level;
}

}  // namespace navmap::render
