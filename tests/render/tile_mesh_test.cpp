// SPDX-License-Identifier: Apache-2.0
// CPU preparation of tiles: skirts, draped roads, ordering, buildings, size growth of draping.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <map>
#include <memory>
#include <set>
#include <tuple>
#include <utility>
#include <vector>

#include "navmap/render/road_style.h"
#include "road_draping.h"
#include "tile_mesh.h"

namespace {

using namespace navmap;

map::Tile bumpyTile() {
    map::Tile t;
    t.size_m = 800.0;
    t.dem.size = 17;
    t.dem.spacing_m = 50.0f;
    for (int r = 0; r < 17; ++r)
        for (int c = 0; c < 17; ++c)
            t.dem.heights.push_back(700.0f + 30.0f * std::sin(r * 0.9f) + 20.0f * std::cos(c * 0.7f));
    return t;
}

map::Road road(map::RoadClass cls, std::vector<map::LocalPoint> points, std::uint8_t flags = 0) {
    map::Road r;
    r.cls = cls;
    r.points = std::move(points);
    r.flags = flags;
    return r;
}

// Two roads winding through several blocks of bumpyTile(): a wide wave and tight hairpins.
map::Tile windingRoadsTile() {
    map::Tile t = bumpyTile();
    std::vector<map::LocalPoint> wave, hairpins;
    for (int i = 0; i <= 390; ++i) {
        const float x = 10.0f + 2.0f * static_cast<float>(i);
        wave.push_back({x, 400.0f + 150.0f * std::sin(x / 60.0f)});
        hairpins.push_back({x, 150.0f + 40.0f * std::sin(x / 9.0f) + 0.3f * std::sin(x * 1.7f)});
    }
    t.roads = {road(map::RoadClass::Secondary, wave), road(map::RoadClass::Residential, hairpins)};
    return t;
}

TEST(TileMesh, TerrainHasGridAndSkirtsBelowTheBorder) {
    const map::Tile t = bumpyTile();
    const render::TileMesh m = render::buildTileMesh(t);
    EXPECT_EQ(m.grid_size, 17);
    const std::size_t grid = 17u * 17u, ring = 4u * 16u;
    ASSERT_EQ(m.terrain.size(), grid + ring);
    EXPECT_EQ(m.terrain_indices.size(), 16u * 16u * 6u + ring * 6u);
    for (std::size_t i = grid; i < m.terrain.size(); ++i) {
        const auto& s = m.terrain[i];
        const bool on_border =
            s.position.x == 0.0f || s.position.y == 0.0f || s.position.x == 800.0f || s.position.y == 800.0f;
        EXPECT_TRUE(on_border);
        EXPECT_NEAR(s.position.z, m.grid().heightAt(s.position.x, s.position.y) - 60.0, 1e-3);
    }
}

// The blocks partition the grid and the skirts: every grid triangle (with the split of
// gridTriangleIndices) and every skirt triangle exactly once, inside its block's extent.
TEST(TileMesh, TerrainBlocksPartitionGridAndSkirts) {
    const map::Tile t = bumpyTile();
    const render::TileMesh m = render::buildTileMesh(t);
    ASSERT_EQ(m.terrain_blocks.size(), std::size_t(render::kTerrainBlocks * render::kTerrainBlocks));
    std::uint32_t next = 0;
    std::set<std::array<std::uint32_t, 3>> seen;
    std::size_t skirt_triangles = 0;
    for (const render::TerrainBlock& b : m.terrain_blocks) {
        EXPECT_EQ(b.first, next);
        next = b.first + b.count;
        EXPECT_FLOAT_EQ(b.max.x - b.min.x, 200.0f);  // 16 cells of 50 m in 4 blocks
        EXPECT_FLOAT_EQ(b.max.y - b.min.y, 200.0f);
        for (std::uint32_t i = b.first; i < b.first + b.count; i += 3) {
            std::array<std::uint32_t, 3> tri{m.terrain_indices[i], m.terrain_indices[i + 1], m.terrain_indices[i + 2]};
            for (std::uint32_t v : tri) {
                const glm::vec3 p = m.terrain[v].position;
                EXPECT_TRUE(p.x >= b.min.x && p.x <= b.max.x && p.y >= b.min.y && p.y <= b.max.y) << p.x << ", " << p.y;
            }
            if (*std::max_element(tri.begin(), tri.end()) >= 17u * 17u) ++skirt_triangles;
            EXPECT_TRUE(seen.insert(tri).second) << "triangle drawn twice";
        }
    }
    EXPECT_EQ(next, m.terrain_indices.size());
    EXPECT_EQ(skirt_triangles, 4u * 16u * 2u);
    const auto grid = render::gridTriangleIndices(17);
    for (std::size_t i = 0; i < grid.size(); i += 3) EXPECT_TRUE(seen.count({grid[i], grid[i + 1], grid[i + 2]})) << i;
}

TEST(TileMesh, TileWithoutDemIsFlat) {
    map::Tile t;
    t.size_m = 500.0;
    const render::TileMesh m = render::buildTileMesh(t);
    EXPECT_EQ(m.grid_size, 2);
    EXPECT_EQ(m.min_height, 0.0f);
    EXPECT_EQ(m.max_height, 0.0f);
}

TEST(TileMesh, RoadsAreDrapedOrderedAndTunnelsHidden) {
    map::Tile t = bumpyTile();
    t.roads = {road(map::RoadClass::Motorway, {{10, 400}, {790, 400}}),
               road(map::RoadClass::Primary, {{400, 10}, {400, 790}}, map::road_flags::kTunnel),
               road(map::RoadClass::Residential, {{10, 10}, {790, 700}})};  // store order: most important first
    render::TileMeshOptions every_piece;
    every_piece.road_merge_tolerance_m = 0.0;
    const render::TileMesh m = render::buildTileMesh(t, every_piece);
    EXPECT_EQ(m.source_road_vertices, 6u);
    ASSERT_GT(m.roads.size(), 40u) << "draping inserts a vertex per triangle edge crossed";
    // By default pieces merge while they stay within the tolerance of the surface.
    const render::TileMesh merged = render::buildTileMesh(t);
    EXPECT_LT(merged.roads.size(), m.roads.size());
    EXPECT_GT(merged.roads.size(), 2u);
    // Least important first, tunnels absent.
    float last = 99.0f;
    for (const auto& r : m.roads) {
        EXPECT_NE(r.road_class, static_cast<float>(map::RoadClass::Primary));
        EXPECT_LE(r.road_class, last);
        last = r.road_class;
    }
    EXPECT_EQ(m.roads.front().road_class, static_cast<float>(map::RoadClass::Residential));
    EXPECT_EQ(m.roads.back().road_class, static_cast<float>(map::RoadClass::Motorway));
    // Every segment end lies on the terrain.
    const auto grid = m.grid();
    for (const auto& r : m.roads) {
        EXPECT_NEAR(r.p0.z, grid.heightAt(r.p0.x, r.p0.y), 1e-2);
        EXPECT_NEAR(r.p1.z, grid.heightAt(r.p1.x, r.p1.y), 1e-2);
    }
}

// The road runs cover the pieces in order, each run one class, one block (by the draped piece's
// midpoint) and one set of road levels, and each block's extent holds its pieces: the renderer
// culls per block.
TEST(TileMesh, RoadRunsGroupPiecesByClassAndBlock) {
    map::Tile t = bumpyTile();
    t.roads = {road(map::RoadClass::Motorway, {{10, 400}, {790, 420}, {20, 780}}),
               road(map::RoadClass::Residential, {{10, 10}, {790, 700}})};
    const render::TileMesh m = render::buildTileMesh(t);
    ASSERT_EQ(m.road_blocks.size(), std::size_t(render::kTerrainBlocks * render::kTerrainBlocks));
    ASSERT_FALSE(m.road_runs.empty());
    std::uint32_t next = 0;
    std::set<std::tuple<float, std::uint32_t, std::uint32_t>> groups;
    for (const render::BlockRun& run : m.road_runs) {
        EXPECT_EQ(run.first, next);
        EXPECT_GT(run.count, 0u);
        next = run.first + run.count;
        const float cls = m.roads[run.first].road_class;
        EXPECT_TRUE(groups.insert({cls, run.block, run.lods}).second) << "one run per class, block and levels";
        EXPECT_NE(run.lods, 0u);
        const render::BlockExtent& b = m.road_blocks[run.block];
        const float bx = static_cast<float>(run.block % render::kTerrainBlocks) * 200.0f;
        const float by = static_cast<float>(run.block / render::kTerrainBlocks) * 200.0f;
        for (std::uint32_t i = run.first; i < next; ++i) {
            const render::RoadInstance& r = m.roads[i];
            EXPECT_EQ(r.road_class, cls);
            const glm::vec3 mid = 0.5f * (r.p0 + r.p1);
            // (A simplified piece is a chord of its block's span and may reach out of it.)
            if (run.lods & 1u) {
                EXPECT_TRUE(mid.x >= bx && mid.x <= bx + 200.0f && mid.y >= by && mid.y <= by + 200.0f)
                    << mid.x << ", " << mid.y;
            }
            for (const glm::vec3& p : {r.p0, r.p1}) {
                EXPECT_TRUE(glm::all(glm::greaterThanEqual(p, b.min)) && glm::all(glm::lessThanEqual(p, b.max)));
            }
        }
    }
    EXPECT_EQ(next, m.roads.size());
    EXPECT_GT(groups.size(), 8u) << "both roads cross several blocks";
}

// Road levels of detail: each level's pieces of a block stay within the level's tolerance of
// every draped vertex there (planar and height error, 3D), and a road's span in a block keeps its
// end points at every level, so blocks drawn at different levels join without gaps.
TEST(TileMesh, RoadLevelsStayWithinTheirToleranceAndKeepTheBlockEnds) {
    map::Tile t = windingRoadsTile();
    // A roundabout: a closed way, its chord from the first to the last point of zero length.
    std::vector<map::LocalPoint> ring;
    for (int i = 0; i <= 48; ++i) {
        const float a = 2.0f * 3.14159265f * static_cast<float>(i % 48) / 48.0f;
        ring.push_back({300.0f + 40.0f * std::cos(a), 700.0f + 40.0f * std::sin(a)});
    }
    t.roads.push_back(road(map::RoadClass::Tertiary, ring));
    const render::TileMesh m = render::buildTileMesh(t);
    struct Key {
        float cls;
        std::uint32_t block;
        auto operator<=>(const Key&) const = default;
    };
    auto pieces_at = [&](int level) {
        std::map<Key, std::vector<render::RoadInstance>> out;
        for (const render::BlockRun& run : m.road_runs) {
            if (!(run.lods & (1u << level))) continue;
            for (std::uint32_t i = run.first; i < run.first + run.count; ++i)
                out[{m.roads[i].road_class, run.block}].push_back(m.roads[i]);
        }
        return out;
    };
    // The chain ends of a set of pieces: points that end an odd number of them.
    auto ends = [](const std::vector<render::RoadInstance>& pieces) {
        std::map<std::array<float, 3>, int> degree;
        for (const auto& r : pieces)
            for (const glm::vec3& p : {r.p0, r.p1}) ++degree[{p.x, p.y, p.z}];
        std::set<std::array<float, 3>> odd;
        for (const auto& [p, d] : degree)
            if (d % 2) odd.insert(p);
        return odd;
    };
    auto distance = [](glm::vec3 p, const render::RoadInstance& r) {
        const glm::vec3 d = r.p1 - r.p0;
        const float len2 = glm::dot(d, d);
        const float s = len2 > 0.0f ? std::clamp(glm::dot(p - r.p0, d) / len2, 0.0f, 1.0f) : 0.0f;
        return glm::length(p - (r.p0 + s * d));
    };
    const auto draped = pieces_at(0);
    ASSERT_GT(draped.size(), 6u) << "both roads cross several blocks";
    std::size_t draped_count = 0;
    for (const auto& [key, pieces] : draped) draped_count += pieces.size();
    std::size_t previous = draped_count;
    for (int level = 1; level < render::kRoadLods; ++level) {
        const auto simplified = pieces_at(level);
        const float tolerance = render::kRoadLodTolerance[static_cast<std::size_t>(level)];
        std::size_t count = 0;
        ASSERT_EQ(simplified.size(), draped.size()) << "level " << level << ": the same blocks";
        for (const auto& [key, pieces] : draped) {
            const auto it = simplified.find(key);
            ASSERT_NE(it, simplified.end());
            count += it->second.size();
            EXPECT_EQ(ends(it->second), ends(pieces)) << "level " << level << " block " << key.block;
            for (const auto& r : pieces) {
                float nearest = 1e30f;
                for (const auto& s : it->second) nearest = std::min(nearest, distance(r.p1, s));
                EXPECT_LE(nearest, tolerance + 1e-3f) << "level " << level << " block " << key.block;
            }
        }
        std::printf("[ measure  ] road level %d (%.0f m): %zu of %zu draped pieces\n", level, tolerance, count,
                    draped_count);
        EXPECT_LT(count, previous) << "level " << level << " has fewer pieces";
        previous = count;
    }
    EXPECT_LT(previous * 4, draped_count) << "the coarsest level keeps less than a quarter of the pieces";
}

TEST(TileMesh, RoadLevelFollowsTheScreenError) {
    // 600 px per unit of tan(angle), half a pixel: level 1 (1 m) from 1200 m, level 2 (4 m)
    // from 4800 m, level 3 (16 m) from 19.2 km; twice the focal length, twice the distances.
    struct Case {
        float distance_m, focal_px;
        int level;
    };
    for (const Case c : {Case{0.0f, 600.0f, 0}, Case{1199.0f, 600.0f, 0}, Case{1200.0f, 600.0f, 1},
                         Case{4799.0f, 600.0f, 1}, Case{4800.0f, 600.0f, 2}, Case{19200.0f, 600.0f, 3},
                         Case{1e9f, 600.0f, 3}, Case{2399.0f, 1200.0f, 0}, Case{2400.0f, 1200.0f, 1}}) {
        EXPECT_EQ(render::roadLodLevel(c.distance_m, c.focal_px, 0.5f), c.level)
            << c.distance_m << " m, " << c.focal_px << " px";
    }
}

TEST(TileMesh, JointCapReachFollowsTheTurn) {
    const glm::vec2 east(10.0f, 0.0f);
    auto towards = [](float degrees) {
        return 3.0f * glm::vec2(std::cos(glm::radians(degrees)), std::sin(glm::radians(degrees)));
    };
    EXPECT_NEAR(render::jointCapReach(east, east), render::kJointOverlap, 1e-6f) << "straight on";
    EXPECT_NEAR(render::jointCapReach(east, towards(60.0f)), 0.5f + render::kJointOverlap, 1e-5f) << "sin(30 deg)";
    EXPECT_NEAR(render::jointCapReach(east, towards(-60.0f)), 0.5f + render::kJointOverlap, 1e-5f) << "either side";
    EXPECT_NEAR(render::jointCapReach(east, towards(90.0f)), std::sqrt(0.5f) + render::kJointOverlap, 1e-5f);
    EXPECT_FLOAT_EQ(render::jointCapReach(east, towards(150.0f)), 1.0f) << "capped at the whole cap";
    EXPECT_FLOAT_EQ(render::jointCapReach(east, -east), 1.0f) << "turning back";
    EXPECT_FLOAT_EQ(render::jointCapReach(east, glm::vec2(0.0f)), 1.0f) << "no length in plan";
}

// seed 3.4 caps where pieces join: at every joint of every level, the two pieces' quads, each
// reaching only cap_reach beyond it, still cover the whole round join between them (checked on
// points of the disk around the joint, at one width); chain ends keep whole caps.
TEST(TileMesh, JoinedPiecesStillCoverTheirRoundJoin) {
    const render::TileMesh m = render::buildTileMesh(windingRoadsTile());
    // Narrow roads (long pieces) to roads far wider than most pieces are long (kept whole caps).
    for (const float half_width : {0.5f, 4.0f, 40.0f}) {
        std::size_t joints = 0, trimmed = 0, ends = 0;
        // Whether the quad of `r` (roads_geo.vert, in plan) covers the plan point q.
        auto covers = [&](const render::RoadInstance& r, glm::vec2 q) {
            const glm::vec2 d = glm::vec2(r.p1 - r.p0);
            const float len = glm::length(d);
            const glm::vec2 t_dir = d / len, n(-t_dir.y, t_dir.x);
            const glm::vec2 rel = q - 0.5f * glm::vec2(r.p0 + r.p1);
            const float x = glm::dot(rel, t_dir) / half_width, y = glm::dot(rel, n) / half_width;
            const float half_length = render::capHalfLength(len, 2.0f * half_width);
            if (x < -(half_length + render::capReach(r.cap_reach.x, half_length)) ||
                x > half_length + render::capReach(r.cap_reach.y, half_length))
                return false;
            return render::capCovers(x, y, half_length);
        };
        for (int level = 0; level < render::kRoadLods; ++level) {
            for (const render::BlockRun& run : m.road_runs) {
                if (!(run.lods & (1u << level))) continue;
                // The pieces of this level in this block, by the point they start and end at.
                std::map<std::array<float, 2>, std::vector<std::pair<const render::RoadInstance*, int>>> at;
                for (const render::BlockRun& other : m.road_runs) {
                    if (other.block != run.block || !(other.lods & (1u << level)) ||
                        m.roads[other.first].road_class != m.roads[run.first].road_class)
                        continue;
                    for (std::uint32_t i = other.first; i < other.first + other.count; ++i) {
                        at[{m.roads[i].p0.x, m.roads[i].p0.y}].push_back({&m.roads[i], 0});
                        at[{m.roads[i].p1.x, m.roads[i].p1.y}].push_back({&m.roads[i], 1});
                    }
                }
                for (std::uint32_t i = run.first; i < run.first + run.count; ++i) {
                    const render::RoadInstance& r = m.roads[i];
                    for (int end = 0; end < 2; ++end) {
                        const glm::vec3 p = end ? r.p1 : r.p0;
                        const auto& meeting = at[{p.x, p.y}];
                        const float reach = end ? r.cap_reach.y : r.cap_reach.x;
                        if (meeting.size() != 2) {
                            ++ends;
                            EXPECT_FLOAT_EQ(reach, 1.0f) << "a chain end keeps its whole cap";
                            continue;
                        }
                        const render::RoadInstance& o = *(meeting[0].first == &r ? meeting[1].first : meeting[0].first);
                        ++joints;
                        const float length = glm::length(glm::vec2(r.p1 - r.p0));
                        trimmed += render::capReach(reach, render::capHalfLength(length, 2.0f * half_width)) < 0.5f;
                        // Around the disk, and on the outer bisector, where the wedge between the bodies
                        // reaches farthest from both.
                        std::vector<glm::vec2> probes;
                        for (int k = 0; k < 64; ++k) {
                            const float a = 2.0f * 3.14159265f * static_cast<float>(k) / 64.0f;
                            for (float f : {0.5f, 0.9f, 0.99f})
                                probes.push_back(f * glm::vec2(std::cos(a), std::sin(a)));
                        }
                        const glm::vec2 in = glm::normalize(glm::vec2(end ? r.p1 - r.p0 : o.p1 - o.p0));
                        const glm::vec2 out = glm::normalize(glm::vec2(end ? o.p1 - o.p0 : r.p1 - r.p0));
                        if (glm::length(in - out) > 1e-3f) probes.push_back(0.99f * glm::normalize(in - out));
                        for (const glm::vec2 probe : probes) {
                            const glm::vec2 q = glm::vec2(p) + half_width * probe;
                            ASSERT_TRUE(covers(r, q) || covers(o, q))
                                << "level " << level << ": round join not covered at " << p.x << ", " << p.y;
                        }
                    }
                }
            }
        }
        std::printf(
            "[ measure  ] half width %.1f m: %zu joined piece ends, %zu of them reach less than half the cap; %zu "
            "chain ends\n",
            half_width, joints, trimmed, ends);
        if (half_width < 1.0f) {
            EXPECT_GT(trimmed * 2, joints) << "most joints bend little";
        }
        EXPECT_GT(ends, 0u);
    }
}

TEST(TileMesh, BridgesSpanStraightBetweenTheirEnds) {
    map::Tile t = bumpyTile();
    map::Road bridge;
    bridge.cls = map::RoadClass::Primary;
    bridge.flags = map::road_flags::kBridge;
    bridge.points = {{100, 100}, {300, 100}, {500, 100}};
    t.roads = {bridge};
    const render::TileMesh m = render::buildTileMesh(t);
    ASSERT_EQ(m.roads.size(), 2u) << "bridges are not clipped to the terrain";
    const auto grid = m.grid();
    const double z0 = grid.heightAt(100, 100) + 2.0, z1 = grid.heightAt(500, 100) + 2.0;
    EXPECT_NEAR(m.roads[0].p0.z, z0, 1e-3);
    EXPECT_NEAR(m.roads[0].p1.z, (z0 + z1) / 2.0, 1e-3);
    EXPECT_NEAR(m.roads[1].p1.z, z1, 1e-3);
}

// Building indices run block by block (by the footprint's centre); each block's extent holds its
// buildings' vertices, so the renderer can cull per block.
TEST(TileMesh, BuildingRunsHoldTheBuildingsOfTheirBlock) {
    map::Tile t = bumpyTile();
    for (const auto& [x, y] :
         {std::pair{100.0f, 100.0f}, std::pair{650.0f, 120.0f}, std::pair{150.0f, 160.0f}, std::pair{420.0f, 700.0f}}) {
        map::Building b;
        b.footprint.vertices = {{x, y}, {x + 40, y}, {x + 40, y + 30}, {x, y + 30}};
        b.footprint.ring_ends = {4};
        b.footprint.indices = {0, 1, 2, 0, 2, 3};
        b.height_m = 10.0f;
        t.buildings.push_back(b);
    }
    const render::TileMesh m = render::buildTileMesh(t);
    ASSERT_EQ(m.building_blocks.size(), std::size_t(render::kTerrainBlocks * render::kTerrainBlocks));
    ASSERT_EQ(m.building_runs.size(), 3u) << "two buildings share the south-west block";
    std::uint32_t next = 0;
    for (const render::BlockRun& run : m.building_runs) {
        EXPECT_EQ(run.first, next);
        next = run.first + run.count;
        const render::BlockExtent& e = m.building_blocks[run.block];
        const float bx = static_cast<float>(run.block % render::kTerrainBlocks) * 200.0f;
        const float by = static_cast<float>(run.block / render::kTerrainBlocks) * 200.0f;
        for (std::uint32_t i = run.first; i < next; ++i) {
            const glm::vec3 p = m.buildings[m.building_indices[i]].position;
            EXPECT_TRUE(glm::all(glm::greaterThanEqual(p, e.min)) && glm::all(glm::lessThanEqual(p, e.max)));
            EXPECT_TRUE(p.x >= bx && p.x <= bx + 200.0f && p.y >= by && p.y <= by + 200.0f) << p.x << ", " << p.y;
        }
    }
    EXPECT_EQ(next, m.building_indices.size());
    EXPECT_EQ(m.building_runs[0].block, 0u);
    EXPECT_EQ(m.building_runs[0].count, 2u * 30u) << "indices of the roof (2 triangles) and 4 walls (8) of each";
}

TEST(TileMesh, BuildingWallsFaceOutwardAndStandOnTheLowestGround) {
    map::Tile t = bumpyTile();
    map::Building b;
    b.footprint.vertices = {{100, 100}, {140, 100}, {140, 130}, {100, 130}};  // counter-clockwise
    b.footprint.ring_ends = {4};
    b.footprint.indices = {0, 1, 2, 0, 2, 3};
    b.height_m = 12.0f;
    t.buildings = {b};
    const render::TileMesh m = render::buildTileMesh(t);
    const auto grid = m.grid();
    float base = 1e9f;
    for (const auto& p : b.footprint.vertices) base = std::min(base, float(grid.heightAt(p.x, p.y)));
    // Roof at base + height; the first wall (south edge) faces south.
    EXPECT_NEAR(m.buildings[0].position.z, base + 12.0f, 1e-3);
    const auto& south_wall = m.buildings[4];
    EXPECT_NEAR(south_wall.normal.y, -1.0f, 1e-6);
    EXPECT_NEAR(south_wall.position.z, base, 1e-3);
}

TEST(TileMesh, LandCoverKeepsWaterOnTop) {
    map::Tile t = bumpyTile();
    map::Area water, forest;
    water.cls = map::AreaClass::Water;
    forest.cls = map::AreaClass::Forest;
    for (auto* a : {&water, &forest}) {
        a->polygon.vertices = {{0, 0}, {100, 0}, {100, 100}};
        a->polygon.ring_ends = {3};
        a->polygon.indices = {0, 1, 2};
    }
    t.areas = {water, forest};
    const render::TileMesh m = render::buildTileMesh(t);
    ASSERT_EQ(m.land_cover.size(), 6u);
    EXPECT_EQ(m.land_cover.front().color, render::landCoverColor(map::AreaClass::Forest));
    EXPECT_EQ(m.land_cover.back().color, render::landCoverColor(map::AreaClass::Water));
}

// A steep, curved slope (store-frame metres): 0.5 to 1.1 rising eastwards, curving both ways.
float steepSlope(double x, double y) {
    return static_cast<float>(1000.0 + 0.8 * x + 300.0 * std::sin(x / 400.0) + 200.0 * std::cos(y / 300.0));
}

map::Tile slopeTile(map::TileId id, double size, int n) {
    map::Tile t;
    t.id = id;
    t.origin_x = id.x * size;
    t.origin_y = id.y * size;
    t.size_m = size;
    t.dem.size = static_cast<std::uint16_t>(n);
    t.dem.spacing_m = static_cast<float>(size / (n - 1));
    t.dem.coverage = 1.0f;
    for (int r = 0; r < n; ++r)
        for (int c = 0; c < n; ++c)
            t.dem.heights.push_back(steepSlope(t.origin_x + c * size / (n - 1), t.origin_y + r * size / (n - 1)));
    return t;
}

// The tiles of a source, as attachDemBorders asks for them.
struct SlopeSource {
    std::vector<std::shared_ptr<map::Tile>> tiles;
    std::shared_ptr<const map::Tile> operator()(map::TileId id) const {
        for (const auto& t : tiles)
            if (t->id == id) return t;
        return nullptr;
    }
    const map::Tile& add(map::TileId id, double size, int n = 17) {
        tiles.push_back(std::make_shared<map::Tile>(slopeTile(id, size, n)));
        return *tiles.back();
    }
    // Every tile with the heights beyond its edges, as a tile source loads it.
    void attachBorders() {
        for (const auto& t : tiles) map::attachDemBorders(*t, *this);
    }
};

// The normal of the central differences of steepSlope's samples spaced `s` apart at (x, y).
glm::vec3 centralNormal(double x, double y, double s) {
    const double dzdx = (double(steepSlope(x + s, y)) - steepSlope(x - s, y)) / (2 * s);
    const double dzdy = (double(steepSlope(x, y + s)) - steepSlope(x, y - s)) / (2 * s);
    return glm::normalize(glm::vec3(float(-dzdx), float(-dzdy), 1.0f));
}

// attachDemBorders takes from each tile of the same level across an edge the samples next to the
// shared border, and leaves an edge without a tile (or with another grid) empty.
TEST(TileMesh, DemBordersAreTheNeighboursSamplesNextToTheBorder) {
    SlopeSource source;
    source.add({3, 1, 1}, 800.0);
    const map::Tile& west = source.add({3, 0, 1}, 800.0);
    const map::Tile& east = source.add({3, 2, 1}, 800.0);
    const map::Tile& north = source.add({3, 1, 2}, 800.0);
    source.add({3, 1, 0}, 800.0, 9);  // south: another grid
    source.attachBorders();
    const map::TileDem& dem = source.tiles.front()->dem;
    ASSERT_EQ(dem.beyond[map::kDemWest].size(), 17u);
    ASSERT_EQ(dem.beyond[map::kDemEast].size(), 17u);
    ASSERT_EQ(dem.beyond[map::kDemNorth].size(), 17u);
    EXPECT_TRUE(dem.beyond[map::kDemSouth].empty());
    for (int i = 0; i < 17; ++i) {
        const auto k = static_cast<std::size_t>(i);
        EXPECT_EQ(dem.beyond[map::kDemWest][k], west.dem.at(i, 15));
        EXPECT_EQ(dem.beyond[map::kDemEast][k], east.dem.at(i, 1));
        EXPECT_EQ(dem.beyond[map::kDemNorth][k], north.dem.at(1, i));
    }
    // The scheme's west edge: tile x 0 has nothing across it.
    EXPECT_TRUE(west.dem.beyond[map::kDemWest].empty());
}

// Two tiles west and east of a border that is also their parents' border: each computes at the
// vertices it shares with the other the same normal, for its own surface and for its parent's
// (the geomorph target), namely the central difference across the border that a tile spanning
// the border would compute. One-sided differences at the border did not (rectangular shading
// seams at tile borders on hillsides); the skirts take the border's normals.
TEST(TileMesh, BorderNormalsAreTheCentralDifferencesAcrossTheBorder) {
    SlopeSource source;
    const map::Tile& west = source.add({3, 1, 0}, 800.0);
    const map::Tile& east = source.add({3, 2, 0}, 800.0);
    const map::Tile& west_parent = source.add({2, 0, 0}, 1600.0);
    const map::Tile& east_parent = source.add({2, 1, 0}, 1600.0);
    const render::TileMesh one_sided = render::buildTileMesh(west);
    source.attachBorders();
    const map::Tile* west_ancestors[] = {&west_parent};
    const map::Tile* east_ancestors[] = {&east_parent};
    const render::TileMesh w = render::buildTileMesh(west, {}, west_ancestors);
    const render::TileMesh e = render::buildTileMesh(east, {}, east_ancestors);
    const int n = 17;
    int differs = 0;
    for (int r = 0; r < n; ++r) {
        const render::TerrainVertex& a = w.terrain[static_cast<std::size_t>(r) * n + n - 1];
        const render::TerrainVertex& b = e.terrain[static_cast<std::size_t>(r) * n];
        EXPECT_EQ(a.normal, b.normal) << "row " << r;
        EXPECT_EQ(a.ancestor_normals[0], b.ancestor_normals[0]) << "row " << r;
        if (a.normal != one_sided.terrain[static_cast<std::size_t>(r) * n + n - 1].normal) ++differs;
        if (r == 0 || r == n - 1) continue;  // no tile south or north: one-sided there
        const glm::vec3 own = centralNormal(1600.0, r * 50.0, 50.0);
        EXPECT_NEAR(a.normal.x, own.x, 1e-4f) << "row " << r;
        EXPECT_NEAR(a.normal.y, own.y, 1e-4f) << "row " << r;
        if (r % 2 == 0) {  // on a parent sample: the parent's central difference (100 m spacing)
            const glm::vec3 parent = centralNormal(1600.0, r * 50.0, 100.0);
            EXPECT_NEAR(a.ancestor_normals[0].x, parent.x, 1e-4f) << "row " << r;
            EXPECT_NEAR(a.ancestor_normals[0].y, parent.y, 1e-4f) << "row " << r;
        }
    }
    EXPECT_EQ(differs, n);  // every border vertex had a one-sided normal before
    // Inside the tile the normals are those without the borders.
    for (int r = 1; r < n - 1; ++r)
        for (int c = 1; c < n - 2; ++c)
            EXPECT_EQ(w.terrain[static_cast<std::size_t>(r) * n + c].normal,
                      one_sided.terrain[static_cast<std::size_t>(r) * n + c].normal);
    // The skirts hang from the border vertices with their normals.
    int skirts = 0;
    for (std::size_t i = static_cast<std::size_t>(n) * n; i < w.terrain.size(); ++i) {
        const render::TerrainVertex& s = w.terrain[i];
        if (s.position.x < 799.0f || s.position.y < 1.0f || s.position.y > 799.0f) continue;
        const auto r = static_cast<std::size_t>(std::lround(s.position.y / 50.0f));
        EXPECT_EQ(s.normal, w.terrain[r * n + n - 1].normal);
        EXPECT_EQ(s.ancestor_normals[0], w.terrain[r * n + n - 1].ancestor_normals[0]);
        ++skirts;
    }
    EXPECT_EQ(skirts, n - 2);
}

// A fine tile next to a coarse one (a level-of-detail border): fully morphed, the fine tile has
// at the border the normals the coarse tile has there, so the shading does not step where the
// levels meet (the fine tile's parent and the coarse tile are neighbours of one level, and each
// has the other's samples beyond their shared edge).
TEST(TileMesh, MorphedBorderNormalsAreThoseOfTheCoarserTileAcrossTheEdge) {
    SlopeSource source;
    const map::Tile& coarse = source.add({2, 0, 0}, 1600.0);
    const map::Tile& parent = source.add({2, 1, 0}, 1600.0);
    const map::Tile& fine = source.add({3, 2, 0}, 800.0);
    source.attachBorders();
    const map::Tile* fine_ancestors[] = {&parent};
    const render::TileMesh f = render::buildTileMesh(fine, {}, fine_ancestors);
    const render::TileMesh c = render::buildTileMesh(coarse);
    const int n = 17;
    for (int r = 0; r < n; r += 2) {  // the fine rows on a coarse sample
        const glm::vec2 morphed = f.terrain[static_cast<std::size_t>(r) * n].ancestor_normals[0];
        const glm::vec3 coarse_normal = c.terrain[static_cast<std::size_t>(r / 2) * n + n - 1].normal;
        EXPECT_NEAR(morphed.x, coarse_normal.x, 1e-6f) << "row " << r;
        EXPECT_NEAR(morphed.y, coarse_normal.y, 1e-6f) << "row " << r;
    }
}

}  // namespace
