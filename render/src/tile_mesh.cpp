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

namespace {

// The terrain grid (flat at 0 m where the tile has no DEM: the store warned at compile time) with
// its vertices' central-difference normals, across the border with the heights beyond it.
void buildTerrainGrid(const map::Tile& tile, TileMesh& mesh) {
    const bool has_dem = tile.dem.size >= 2 && tile.dem.heights.size() == std::size_t{tile.dem.size} * tile.dem.size;
    if (has_dem) {
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
    const HeightGrid grid{n, spacing, mesh.heights.data()};
    for (int r = 0; r < n; ++r) {
        for (int c = 0; c < n; ++c) {
            const NormalStencil s = normalStencil(grid, r, c, has_dem ? &tile.dem : nullptr);
            const float dzdx = (s.east - s.west) / static_cast<float>(s.dx_cells * spacing);
            const float dzdy = (s.north - s.south) / static_cast<float>(s.dy_cells * spacing);
            mesh.terrain[static_cast<std::size_t>(r) * n + c] = {
                glm::vec3(static_cast<float>(c * spacing), static_cast<float>(r * spacing), grid.at(r, c)),
                glm::normalize(glm::vec3(-dzdx, -dzdy, 1.0f))};
        }
    }
}

// Geomorph targets (terrain_lod.h): the coarser levels' surfaces at every grid vertex.
void addMorphTargets(const map::Tile& tile, std::span<const map::Tile* const> ancestors, TileMesh& mesh) {
    std::vector<glm::vec3> normals;
    for (int j = 0; j < kMorphLevels; ++j) {
        const auto k = static_cast<std::size_t>(j);
        const map::Tile* ancestor = k < ancestors.size() ? ancestors[k] : nullptr;
        ancestorSurface(tile, mesh.grid_size, mesh.heights, ancestor, j + 1, mesh.ancestor_heights[k], normals);
        for (std::size_t i = 0; i < mesh.terrain.size(); ++i) {
            mesh.terrain[i].ancestor_heights[k] = mesh.ancestor_heights[k][i];
            mesh.terrain[i].ancestor_normals[k] = glm::vec2(normals[i]);
        }
    }
}

// Skirts: a curtain hanging from every border vertex, so a coarser neighbour never shows a crack
// through to the sky. Adds the skirt vertices; returns for each grid vertex its skirt vertex (0: none).
std::vector<std::uint32_t> addSkirtVertices(TileMesh& mesh, float skirt_depth_m) {
    const int n = mesh.grid_size;
    std::vector<std::uint32_t> skirt_of(mesh.terrain.size(), 0);  // border vertex -> its skirt vertex
    auto add_skirt = [&](int r, int c) {
        const auto v = static_cast<std::size_t>(r) * n + c;
        if (skirt_of[v]) return;
        TerrainVertex s = mesh.terrain[v];
        s.position.z -= skirt_depth_m;
        for (float& a : s.ancestor_heights) a -= skirt_depth_m;  // morphs with its border vertex
        skirt_of[v] = static_cast<std::uint32_t>(mesh.terrain.size());
        mesh.terrain.push_back(s);
    };
    for (int i = 0; i < n; ++i) {
        add_skirt(0, i);
        add_skirt(n - 1, i);
        add_skirt(i, 0);
        add_skirt(i, n - 1);
    }
    return skirt_of;
}

// The heights a block's vertices can take: own and geomorph targets, skirts included.
void setBlockHeights(const TileMesh& mesh, TerrainBlock& block) {
    block.min_z = std::numeric_limits<float>::max();
    block.max_z = std::numeric_limits<float>::lowest();
    for (std::uint32_t i = block.first; i < block.first + block.count; ++i) {
        const TerrainVertex& v = mesh.terrain[mesh.terrain_indices[i]];
        const auto [lowest, highest] = std::minmax_element(v.ancestor_heights.begin(), v.ancestor_heights.end());
        block.min_z = std::min({block.min_z, v.position.z, *lowest});
        block.max_z = std::max({block.max_z, v.position.z, *highest});
    }
}

// The grid in blocks^2 square blocks, each with its part of the skirts, so a block can be drawn
// alone (the renderer picks per block which land-cover levels it needs).
void addTerrainBlocks(TileMesh& mesh, const std::vector<std::uint32_t>& skirt_of, double spacing, int blocks) {
    const int n = mesh.grid_size;
    auto vertex = [&](int r, int c) { return static_cast<std::uint32_t>(r * n + c); };
    // Border segment a -> b runs counter-clockwise round the tile (seen from above), so the
    // curtain faces outwards.
    auto skirt_segment = [&](std::uint32_t a, std::uint32_t b) {
        mesh.terrain_indices.insert(mesh.terrain_indices.end(), {a, skirt_of[a], skirt_of[b], a, skirt_of[b], b});
    };
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
            setBlockHeights(mesh, block);
            mesh.terrain_blocks.push_back(block);
        }
    }
}

// The block (as terrain_blocks, row-major) holding a tile-local point.
struct BlockOf {
    float block_size;
    int blocks;
    std::uint32_t operator()(glm::vec2 p) const {
        const int bx = std::clamp(static_cast<int>(std::floor(p.x / block_size)), 0, blocks - 1);
        const int by = std::clamp(static_cast<int>(std::floor(p.y / block_size)), 0, blocks - 1);
        return static_cast<std::uint32_t>(by * blocks + bx);
    }
};

// No extent yet (min > max).
BlockExtent noExtent() {
    return BlockExtent{glm::vec3(std::numeric_limits<float>::max()), glm::vec3(std::numeric_limits<float>::lowest())};
}

void extendBlock(BlockExtent& e, glm::vec3 low, glm::vec3 high) {
    e.min = glm::min(e.min, low);
    e.max = glm::max(e.max, high);
}

// One road piece while the tile's roads are built: its instance, the road's draw order, its block
// and the levels of detail it is drawn at (bit k: level k).
struct Piece {
    RoadInstance inst;
    int order;
    std::uint32_t block = 0;
    std::uint32_t lods = 1;  // level 0
};

// The road's polyline on the terrain (seed 3.6.1): draped onto the grid, or, for a bridge, straight
// between its ends (drawn above what it crosses).
std::vector<glm::dvec3> drapeRoad(const map::Road& road, const std::vector<glm::dvec2>& line, const HeightGrid& grid,
                                  const TileMeshOptions& options) {
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
            const double z = bridge ? z0 + (z1 - z0) * (total > 0 ? run / total : 0.0) + bridgeDeckHeightM(road.layer)
                                    : grid.heightAt(line[i].x, line[i].y);
            draped.emplace_back(line[i].x, line[i].y, z);
        }
    } else {
        draped = drapePolyline(grid, line);
        if (options.road_merge_tolerance_m > 0.0) draped = mergeDrapedPieces(draped, options.road_merge_tolerance_m);
    }
    return draped;
}

// A piece a -> b of the road (its caps are set per level afterwards, joinChain).
void addPiece(std::vector<Piece>& pieces, const map::Road& road, int order, const glm::dvec3& a, const glm::dvec3& b,
              std::uint32_t block, std::uint32_t lods) {
    RoadInstance inst{glm::vec3(a), glm::vec3(b), static_cast<float>(road.cls), static_cast<float>(road.flags)};
    inst.cap_reach = glm::vec2(0.0f);  // set per level, from the piece's neighbours
    pieces.push_back({inst, order, block, lods});
}

// seed 3.4's caps where pieces join: along each level's chain within a span, a piece reaches beyond
// a joint only as far as the bend needs (jointCapReach), the most that any of its levels needs. A
// span's ends keep whole caps: the next block may be drawn at another level. (Other roads meeting
// here are unaffected: the joined pieces still cover their whole round join between them.)
void joinChain(std::vector<Piece>& pieces, const std::vector<std::size_t>& chain) {
    pieces[chain.front()].inst.cap_reach.x = 1.0f;
    pieces[chain.back()].inst.cap_reach.y = 1.0f;
    for (std::size_t c = 0; c + 1 < chain.size(); ++c) {
        RoadInstance& from = pieces[chain[c]].inst;
        RoadInstance& to = pieces[chain[c + 1]].inst;
        const float reach = jointCapReach(glm::vec2(from.p1 - from.p0), glm::vec2(to.p1 - to.p0));
        from.cap_reach.y = std::max(from.cap_reach.y, reach);
        to.cap_reach.x = std::max(to.cap_reach.x, reach);
    }
}

// The levels of one span of a road in one block: the draped vertices `span`, whose level-0 pieces
// are pieces[a, b). The coarser levels' pieces are added (the levels' kept sets nest, so a chord is
// shared by the levels keeping it), and every level's chain joined.
void addSpanLevels(std::vector<Piece>& pieces, const map::Road& road, int order, std::span<const glm::dvec3> span,
                   std::size_t a, std::size_t b) {
    const std::uint32_t block = pieces[a].block;
    struct Chord {
        std::size_t from, to, piece;
    };
    std::vector<Chord> chords;  // the pieces added for this span
    std::vector<std::size_t> chain(b - a);
    std::iota(chain.begin(), chain.end(), a);
    joinChain(pieces, chain);
    for (int k = 1; k < kRoadLods; ++k) {
        const std::vector<char> keep = map::douglasPeucker(
            span.size(), kRoadLodTolerance[static_cast<std::size_t>(k)],
            [&](std::size_t v, std::size_t i, std::size_t j) { return segmentDistance(span[v], span[i], span[j]); });
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
                    addPiece(pieces, road, order, span[i], span[j], block, 0u);
                }
            }
            pieces[chain.back()].lods |= bit;
            i = j;
        }
        joinChain(pieces, chain);
    }
}

// One road's pieces of every level (seed 3.4: one instance per piece): the draped pieces (level 0),
// then per span of the road in one block the coarser levels.
void addRoadPieces(const map::Road& road, const std::vector<glm::dvec3>& draped, const BlockOf& block_of,
                   std::vector<Piece>& pieces) {
    const int order = roadDrawOrder(road);
    const std::size_t first = pieces.size();
    for (std::size_t i = 0; i + 1 < draped.size(); ++i) {
        addPiece(pieces, road, order, draped[i], draped[i + 1],
                 block_of(0.5f * (glm::vec2(glm::dvec2(draped[i])) + glm::vec2(glm::dvec2(draped[i + 1])))), 1u);
    }
    // The coarser levels, per span of the road in one block: draped vertices a .. b.
    const std::size_t last = pieces.size();
    for (std::size_t a = first; a < last;) {
        const std::uint32_t block = pieces[a].block;
        std::size_t b = a + 1;
        while (b < last && pieces[b].block == block) ++b;
        addSpanLevels(pieces, road, order, std::span<const glm::dvec3>(draped.data() + (a - first), b - a + 1), a, b);
        a = b;
    }
}

// The tile's roads draped onto the grid (seed 3.6.1) as pieces; tunnels are left out.
std::vector<Piece> roadPieces(const map::Tile& tile, const TileMeshOptions& options, const HeightGrid& grid,
                              const BlockOf& block_of, TileMesh& mesh) {
    std::vector<Piece> pieces;
    std::vector<glm::dvec2> line;
    for (const auto& road : tile.roads) {
        if (road.points.size() < 2) continue;
        mesh.source_road_vertices += road.points.size();
        if (road.flags & map::road_flags::kTunnel) continue;  // tunnels are hidden in the map view
        line.clear();
        for (const auto& p : road.points) line.emplace_back(p.x, p.y);
        const std::vector<glm::dvec3> draped = drapeRoad(road, line, grid, options);
        addRoadPieces(road, draped, block_of, pieces);
    }
    return pieces;
}

// Within a group the pieces run block by block (the order among pieces of one class does not
// matter: casings and fills are separate passes), so the renderer can leave out the blocks
// outside the view and still draw the groups in order.
void addRoadRuns(std::vector<Piece>& pieces, int blocks, TileMesh& mesh) {
    mesh.road_blocks.assign(static_cast<std::size_t>(blocks * blocks), noExtent());
    for (const Piece& p : pieces)
        extendBlock(mesh.road_blocks[p.block], glm::min(p.inst.p0, p.inst.p1), glm::max(p.inst.p0, p.inst.p1));
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
}

// One building: walls and a flat roof over the lowest terrain point of the footprint; its indices
// go to its block's (by the footprint's centre).
void addBuilding(const map::Building& b, const HeightGrid& grid, const BlockOf& block_of, TileMesh& mesh,
                 std::vector<std::vector<std::uint32_t>>& block_indices) {
    const auto& fp = b.footprint;
    if (fp.vertices.size() < 3 || fp.ring_ends.empty()) return;
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
    extendBlock(mesh.building_blocks[block], glm::vec3(lo2, bottom), glm::vec3(hi2, top));
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

// The buildings, their indices block by block for culling.
void addBuildings(const map::Tile& tile, const HeightGrid& grid, const BlockOf& block_of, TileMesh& mesh) {
    mesh.building_blocks.assign(static_cast<std::size_t>(block_of.blocks * block_of.blocks), noExtent());
    std::vector<std::vector<std::uint32_t>> block_indices(mesh.building_blocks.size());
    for (const auto& b : tile.buildings) addBuilding(b, grid, block_of, mesh, block_indices);
    for (std::size_t k = 0; k < block_indices.size(); ++k) {
        if (block_indices[k].empty()) continue;
        mesh.building_runs.push_back({static_cast<std::uint32_t>(mesh.building_indices.size()),
                                      static_cast<std::uint32_t>(block_indices[k].size()),
                                      static_cast<std::uint32_t>(k)});
        mesh.building_indices.insert(mesh.building_indices.end(), block_indices[k].begin(), block_indices[k].end());
    }
}

}  // namespace

TileMesh buildTileMesh(const map::Tile& tile, const TileMeshOptions& options,
                       std::span<const map::Tile* const> ancestors) {
    TileMesh mesh;
    mesh.id = tile.id;
    mesh.origin = glm::dvec3(tile.origin_x, tile.origin_y, 0.0);
    mesh.size_m = static_cast<float>(tile.size_m);

    // --- terrain: the grid, its geomorph targets, skirts, in kTerrainBlocks^2 blocks
    buildTerrainGrid(tile, mesh);
    addMorphTargets(tile, ancestors, mesh);
    const int n = mesh.grid_size;
    const double spacing = tile.size_m / (n - 1);
    const std::vector<std::uint32_t> skirt_of = addSkirtVertices(mesh, options.skirt_depth_m);
    const int blocks = std::min(kTerrainBlocks, n - 1);
    addTerrainBlocks(mesh, skirt_of, spacing, blocks);
    const HeightGrid grid = mesh.grid();

    mesh.land_cover = landCoverTriangles(tile);

    // --- roads: draped onto the grid (seed 3.6.1), one instance per piece (seed 3.4)
    const BlockOf block_of{mesh.size_m / static_cast<float>(blocks), blocks};
    std::vector<Piece> pieces = roadPieces(tile, options, grid, block_of, mesh);
    addRoadRuns(pieces, blocks, mesh);

    // --- buildings: walls and a flat roof over the lowest terrain point of the footprint; the
    // indices block by block (by the footprint's centre) for culling
    addBuildings(tile, grid, block_of, mesh);
    return mesh;
}

}  // namespace navmap::render
