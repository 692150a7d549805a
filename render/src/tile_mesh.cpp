#include "navmap/render/tile_mesh.h"

#include <algorithm>
#include <cmath>
#include <numeric>

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

// Draw order of land cover: large natural classes first, water last so rivers stay visible.
int landCoverOrder(map::AreaClass c) {
    using A = map::AreaClass;
    switch (c) {
        case A::Forest: case A::Scrub: case A::Grass: case A::Farmland: case A::Rock: case A::Glacier: return 0;
        case A::Residential: case A::Commercial: case A::Industrial: case A::Military: case A::Cemetery: return 1;
        case A::Park: case A::Sport: case A::Other: return 2;
        case A::Wetland: return 3;
        case A::Water: return 4;
    }
    return 2;
}

}  // namespace

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
    }
    return rgba(0xc8c8b0, 0.3f);
}

TileMesh buildTileMesh(const map::Tile& tile, const TileMeshOptions& options) {
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
    mesh.terrain_indices = gridTriangleIndices(n);
    // Skirts: a curtain hanging from every border vertex, so a coarser neighbour never shows a
    // crack through to the sky.
    std::vector<std::uint32_t> ring;  // border vertex indices, counter-clockwise from south-west
    for (int c = 0; c < n - 1; ++c) ring.push_back(static_cast<std::uint32_t>(c));
    for (int r = 0; r < n - 1; ++r) ring.push_back(static_cast<std::uint32_t>(r * n + n - 1));
    for (int c = n - 1; c > 0; --c) ring.push_back(static_cast<std::uint32_t>((n - 1) * n + c));
    for (int r = n - 1; r > 0; --r) ring.push_back(static_cast<std::uint32_t>(r * n));
    const auto skirt_base = static_cast<std::uint32_t>(mesh.terrain.size());
    for (std::uint32_t v : ring) {
        TerrainVertex s = mesh.terrain[v];
        s.position.z -= options.skirt_depth_m;
        mesh.terrain.push_back(s);
    }
    for (std::size_t i = 0; i < ring.size(); ++i) {
        const std::uint32_t a = ring[i], b = ring[(i + 1) % ring.size()];
        const auto sa = skirt_base + static_cast<std::uint32_t>(i);
        const auto sb = skirt_base + static_cast<std::uint32_t>((i + 1) % ring.size());
        // Outward-facing (the ring runs counter-clockwise seen from above).
        mesh.terrain_indices.insert(mesh.terrain_indices.end(), {a, sa, sb, a, sb, b});
    }
    const HeightGrid grid = mesh.grid();

    // --- land cover
    std::vector<const map::Area*> areas;
    for (const auto& a : tile.areas) areas.push_back(&a);
    std::stable_sort(areas.begin(), areas.end(),
                     [](const map::Area* a, const map::Area* b) { return landCoverOrder(a->cls) < landCoverOrder(b->cls); });
    for (const map::Area* a : areas) {
        const glm::vec4 color = landCoverColor(a->cls);
        for (std::uint32_t i : a->polygon.indices) {
            if (i >= a->polygon.vertices.size()) continue;
            const auto& p = a->polygon.vertices[i];
            mesh.land_cover.push_back({glm::vec2(p.x, p.y), color});
        }
    }

    // --- roads: draped onto the grid (seed 3.6.1), one instance per piece (seed 3.4)
    struct Piece {
        RoadInstance inst;
        int order;
    };
    std::vector<Piece> pieces;
    std::vector<glm::dvec2> line;
    for (const auto& road : tile.roads) {
        if (road.points.size() < 2) continue;
        mesh.source_road_vertices += road.points.size();
        if (road.flags & map::RoadFlags::Tunnel) continue;  // tunnels are hidden in the map view
        line.clear();
        for (const auto& p : road.points) line.emplace_back(p.x, p.y);
        std::vector<glm::dvec3> draped;
        const bool bridge = (road.flags & map::RoadFlags::Bridge) != 0;
        if (bridge || !options.drape_roads) {
            // A bridge spans straight between its ends (drawn above what it crosses).
            draped.reserve(line.size());
            const double z0 = grid.heightAt(line.front().x, line.front().y);
            const double z1 = grid.heightAt(line.back().x, line.back().y);
            double total = 0.0, run = 0.0;
            for (std::size_t i = 1; i < line.size(); ++i) total += glm::length(line[i] - line[i - 1]);
            for (std::size_t i = 0; i < line.size(); ++i) {
                if (i > 0) run += glm::length(line[i] - line[i - 1]);
                const double z = bridge ? z0 + (z1 - z0) * (total > 0 ? run / total : 0.0) + 2.0
                                        : grid.heightAt(line[i].x, line[i].y);
                draped.emplace_back(line[i].x, line[i].y, z);
            }
        } else {
            draped = drapePolyline(grid, line);
            if (options.road_merge_tolerance_m > 0.0) draped = mergeDrapedPieces(draped, options.road_merge_tolerance_m);
        }
        // Least important first so more important classes overwrite them at junctions
        // (seed 3.6.3 "Intersections"); bridges after everything.
        const int order = (bridge ? 1000 : 0) + (map::kRoadClassCount - static_cast<int>(road.cls));
        for (std::size_t i = 0; i + 1 < draped.size(); ++i) {
            pieces.push_back({RoadInstance{glm::vec3(draped[i]), glm::vec3(draped[i + 1]),
                                           static_cast<float>(road.cls), static_cast<float>(road.flags)},
                              order});
        }
    }
    std::stable_sort(pieces.begin(), pieces.end(), [](const Piece& a, const Piece& b) { return a.order < b.order; });
    mesh.roads.reserve(pieces.size());
    for (const auto& p : pieces) mesh.roads.push_back(p.inst);

    // --- buildings: walls and a flat roof over the lowest terrain point of the footprint
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
        // Roof.
        const auto roof_base = static_cast<std::uint32_t>(mesh.buildings.size());
        for (const auto& p : fp.vertices) mesh.buildings.push_back({{p.x, p.y, top}, {0, 0, 1}, color * 1.05f, size});
        for (std::uint32_t i : fp.indices) {
            if (i < fp.vertices.size()) mesh.building_indices.push_back(roof_base + i);
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
                mesh.building_indices.insert(mesh.building_indices.end(), {w, w + 1, w + 2, w, w + 2, w + 3});
            }
            start = end;
        }
    }
    return mesh;
}

}  // namespace navmap::render
