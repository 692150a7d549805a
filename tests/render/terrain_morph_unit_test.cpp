// SPDX-License-Identifier: Apache-2.0
// Geomorphing of terrain tiles (terrain_lod.h): the morph factor, the morph range that ends
// where the level-of-detail rule switches a tile to its parent, and the parent surface that a
// fully morphed tile must reproduce exactly (CPU side; the GPU side is terrain_morph_test.cpp).
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <random>

#include "navmap/render/terrain_lod.h"
#include "tile_mesh.h"

namespace {

using namespace navmap;
using render::TileMorph;

TEST(TerrainMorph, FactorIsZeroBeforeStartOneAfterEndLinearBetween) {
    EXPECT_EQ(render::morphFactor(0.0f, 1000.0f, 2000.0f), 0.0f);
    EXPECT_EQ(render::morphFactor(1000.0f, 1000.0f, 2000.0f), 0.0f);
    EXPECT_FLOAT_EQ(render::morphFactor(1250.0f, 1000.0f, 2000.0f), 0.25f);
    EXPECT_FLOAT_EQ(render::morphFactor(1500.0f, 1000.0f, 2000.0f), 0.5f);
    EXPECT_EQ(render::morphFactor(2000.0f, 1000.0f, 2000.0f), 1.0f);
    EXPECT_EQ(render::morphFactor(50000.0f, 1000.0f, 2000.0f), 1.0f);
    // No range (above the root, or morphing off): never morphs.
    EXPECT_EQ(render::morphFactor(5000.0f, 0.0f, 0.0f), 0.0f);
}

TEST(TerrainMorph, HeightBlendsThroughTheAncestorLevelsWithDistance) {
    // Level 6 of a 16 km store, ranges doubling per level: 1000-2000, 2000-4000, 4000-8000, 8000-16000.
    TileMorph m;
    for (int j = 0; j < render::kMorphLevels; ++j) {
        m.end_m[j] = 2000.0f * float(1 << j);
        m.start_m[j] = 0.5f * m.end_m[j];
    }
    const std::array<float, render::kMorphLevels> up{20.0f, 30.0f, 40.0f, 50.0f};
    EXPECT_EQ(render::morphedHeight(500.0f, m, 10.0f, up), 10.0f);         // own level
    EXPECT_FLOAT_EQ(render::morphedHeight(1500.0f, m, 10.0f, up), 15.0f);  // half way to the parent
    EXPECT_EQ(render::morphedHeight(2000.0f, m, 10.0f, up), 20.0f);        // the parent exactly
    EXPECT_FLOAT_EQ(render::morphedHeight(3000.0f, m, 10.0f, up), 25.0f);  // parent -> grandparent
    EXPECT_EQ(render::morphedHeight(16000.0f, m, 10.0f, up), 50.0f);       // the coarsest carried level
    // Beyond the end of its first range a tile shows what its parent shows at that distance
    // (the parent's own chain is the ancestors shifted by one): the switch is invisible.
    TileMorph parent;
    for (int j = 0; j + 1 < render::kMorphLevels; ++j) {
        parent.start_m[j] = m.start_m[j + 1];
        parent.end_m[j] = m.end_m[j + 1];
    }
    parent.start_m[3] = 16000.0f;
    parent.end_m[3] = 32000.0f;
    for (float d = 2000.0f; d < 12000.0f; d += 250.0f) {
        EXPECT_FLOAT_EQ(render::morphedHeight(d, m, 10.0f, up),
                        render::morphedHeight(d, parent, 20.0f, {30.0f, 40.0f, 50.0f, 60.0f}))
            << d;
    }
}

TEST(TerrainMorph, DistanceAddsTheCameraHeightAboveTheBand) {
    TileMorph m;
    m.eye_dz_m = 300.0f;
    EXPECT_FLOAT_EQ(render::morphDistance(400.0f, 0.0f, m), 500.0f);
    render::LodOptions o;
    EXPECT_EQ(render::morphEyeDz(1200.0, o), 0.0);  // inside the band: horizontal distance only
    EXPECT_EQ(render::morphEyeDz(o.max_height_m + 250.0, o), 250.0);
    EXPECT_EQ(render::morphEyeDz(o.min_height_m - 40.0, o), 40.0);
}

TEST(TerrainMorph, RangeEndsWhereTheParentReachesTheErrorThreshold) {
    const map::TileScheme scheme{0.0, 0.0, 16384.0, 6};
    render::LodOptions o;
    o.dem_samples = 65;
    o.max_error_px = 3.0;
    for (float e : render::morphRange(scheme, 0, 45.0, 480, o).end_m) EXPECT_EQ(e, 0.0f) << "the root has no parent";
    for (int level = 1; level < scheme.levelCount(); ++level) {
        const TileMorph m = render::morphRange(scheme, level, 45.0, 480, o);
        for (int j = 0; j < render::kMorphLevels; ++j) {
            if (level - j <= 0) {
                EXPECT_EQ(m.end_m[j], 0.0f) << "no level above the root";
                continue;
            }
            // Slot j ends where the level above level - j reaches the error threshold.
            const double coarser_error = render::levelError(scheme, level - j - 1, o);
            EXPECT_NEAR(render::screenSpaceError(coarser_error, m.end_m[j], 45.0, 480), o.max_error_px, 1e-3) << level;
            EXPECT_NEAR(m.start_m[j], o.morph_start * m.end_m[j], 1e-2);
            // Each slot's range is twice the previous one (the error doubles per level up).
            if (j > 0) {
                EXPECT_NEAR(m.end_m[j], 2.0 * m.end_m[j - 1], 1e-2);
            }
        }
        // The tile itself is drawn from refineDistance(level) on, which is before the morph starts.
        EXPECT_LT(render::refineDistance(scheme, level, 45.0, 480, o), m.start_m[0]);
    }
}

// A quadtree where every tile is resident (the fake of terrain_lod_test.cpp).
struct AllResident {
    map::TileScheme scheme{0.0, 0.0, 16384.0, 6};
    std::map<std::uint64_t, std::shared_ptr<const map::Tile>> tiles;
    std::shared_ptr<const map::Tile> get(map::TileId id) {
        auto& t = tiles[id.key()];
        if (!t) {
            auto tile = std::make_shared<map::Tile>();
            tile->id = id;
            t = tile;
        }
        return t;
    }
};

TEST(TerrainMorph, SelectionGivesEveryDrawnTileItsParentAndARangeBeyondTheParentBox) {
    AllResident s;
    render::Camera cam;
    cam.eye = {8000.0, 2000.0, 300.0};
    cam.target = {8000.0, 3000.0, 0.0};
    cam.far_m = 30000.0;
    render::LodOptions o;
    o.dem_samples = 33;
    const auto sel = render::selectLod(
        s.scheme, cam, 1280.0 / 480.0, 480, [&](map::TileId id) { return s.scheme.valid(id); },
        [&](map::TileId id) { return s.get(id); }, o);
    ASSERT_EQ(sel.morph.size(), sel.draw.size());
    int morphing = 0;
    for (std::size_t i = 0; i < sel.draw.size(); ++i) {
        const map::TileId id = sel.draw[i]->id;
        const TileMorph& m = sel.morph[i];
        if (id.level == 0) {
            EXPECT_EQ(m.end_m[0], 0.0f);
            continue;
        }
        ++morphing;
        map::TileId up = id;
        for (int j = 0; j < render::kMorphLevels && up.level > 0; ++j) {
            up = up.parent();
            ASSERT_TRUE(m.ancestors[j]) << id.toString() << " ancestor " << j;
            EXPECT_EQ(m.ancestors[j]->id, up);
        }
        // The invariant the morph relies on: the parent is refined (so this tile drawn) only
        // while its box is nearer than end_m; once it is farther every vertex of this tile is
        // at >= end_m, i.e. fully morphed, and the switch changes nothing.
        const map::Box b = s.scheme.bounds(id.parent());
        const double dx = std::max({b.min_x - cam.eye.x, 0.0, cam.eye.x - b.max_x});
        const double dy = std::max({b.min_y - cam.eye.y, 0.0, cam.eye.y - b.max_y});
        EXPECT_LT(std::hypot(dx, dy), m.end_m[0]) << id.toString();
    }
    EXPECT_GT(morphing, 3);
    o.morph = false;
    const auto plain = render::selectLod(
        s.scheme, cam, 1280.0 / 480.0, 480, [&](map::TileId id) { return s.scheme.valid(id); },
        [&](map::TileId id) { return s.get(id); }, o);
    EXPECT_TRUE(plain.morph.empty());
}

std::shared_ptr<map::Tile> demTile(map::TileId id, double origin_x, double origin_y, double size, int n,
                                   std::mt19937& rng) {
    auto t = std::make_shared<map::Tile>();
    t->id = id;
    t->origin_x = origin_x;
    t->origin_y = origin_y;
    t->size_m = size;
    t->dem.size = static_cast<std::uint16_t>(n);
    t->dem.spacing_m = static_cast<float>(size / (n - 1));
    t->dem.coverage = 1.0f;
    std::uniform_real_distribution<float> h(800.0f, 1400.0f);
    for (int i = 0; i < n * n; ++i) t->dem.heights.push_back(h(rng));
    return t;
}

TEST(TerrainMorph, FullyMorphedTileIsExactlyItsParentsSurface) {
    std::mt19937 rng(7);
    // Parent 1000 m, 17 samples; its north-east child 500 m, 17 samples, unrelated heights (the
    // store low-pass filters each level, so a child's samples are not its parent's).
    const auto parent = demTile({3, 2, 2}, 4000.0, 6000.0, 1000.0, 17, rng);
    const auto child = demTile({4, 5, 5}, 4500.0, 6500.0, 500.0, 17, rng);
    const map::Tile* ancestors[] = {parent.get()};
    const render::TileMesh mesh = render::buildTileMesh(*child, {}, ancestors);
    const render::HeightGrid pg{17, 1000.0 / 16, parent->dem.heights.data()};
    const render::HeightGrid morphed = mesh.ancestorGrid(0);
    // Anywhere on the child, the morphed (parent-height) triangles lie on the parent's triangles.
    std::uniform_real_distribution<double> u(0.0, 500.0);
    for (int i = 0; i < 2000; ++i) {
        const double x = u(rng), y = u(rng);
        ASSERT_NEAR(morphed.heightAt(x, y), pg.heightAt(x + 500.0, y + 500.0), 1e-3) << x << ", " << y;
    }
    // The vertex data carries the same target, skirts included (they hang from their border vertex).
    const int n = mesh.grid_size;
    for (int i = 0; i < n * n; ++i) EXPECT_EQ(mesh.terrain[i].ancestor_heights[0], mesh.ancestor_heights[0][i]);
    for (std::size_t i = static_cast<std::size_t>(n) * n; i < mesh.terrain.size(); ++i) {
        const auto& s = mesh.terrain[i];
        EXPECT_NEAR(s.position.z - s.ancestor_heights[0],
                    mesh.grid().heightAt(s.position.x, s.position.y) - morphed.heightAt(s.position.x, s.position.y),
                    1e-3);
        EXPECT_LE(glm::length(s.ancestor_normals[0]), 1.0f);
    }
}

TEST(TerrainMorph, WithoutAParentTheTargetIsTheEvenSamples) {
    std::mt19937 rng(11);
    const auto tile = demTile({4, 1, 1}, 0.0, 0.0, 640.0, 33, rng);
    const render::TileMesh mesh = render::buildTileMesh(*tile);
    const int n = 33;
    for (int r = 0; r < n; ++r) {
        for (int c = 0; c < n; ++c) {
            const float p = mesh.ancestor_heights[0][static_cast<std::size_t>(r) * n + c];
            auto h = [&](int rr, int cc) { return tile->dem.at(rr, cc); };
            if (r % 2 == 0 && c % 2 == 0) {
                EXPECT_EQ(p, h(r, c));
            } else if (r % 2 == 0) {
                EXPECT_NEAR(p, 0.5f * (h(r, c - 1) + h(r, c + 1)), 1e-3f);
            } else if (c % 2 == 0) {
                EXPECT_NEAR(p, 0.5f * (h(r - 1, c) + h(r + 1, c)), 1e-3f);
            } else {
                // Cell centre of the coarse grid: on its south-west -> north-east diagonal.
                EXPECT_NEAR(p, 0.5f * (h(r - 1, c - 1) + h(r + 1, c + 1)), 1e-3f);
            }
        }
    }
    // Parent normals at even samples: central differences over the coarse spacing.
    const double s2 = 2.0 * 640.0 / 32;
    const int r = 8, c = 12;
    const glm::vec3 expect =
        glm::normalize(glm::vec3(-(tile->dem.at(r, c + 2) - tile->dem.at(r, c - 2)) / (2 * s2),
                                 -(tile->dem.at(r + 2, c) - tile->dem.at(r - 2, c)) / (2 * s2), 1.0));
    const glm::vec2 got = mesh.terrain[static_cast<std::size_t>(r) * n + c].ancestor_normals[0];
    EXPECT_NEAR(glm::distance(got, glm::vec2(expect)), 0.0f, 1e-4f);
    // Two levels up without the tile at hand: every 4th sample.
    EXPECT_EQ(mesh.ancestor_heights[1][static_cast<std::size_t>(8) * n + 12], tile->dem.at(8, 12));
    EXPECT_NEAR(mesh.ancestor_heights[1][static_cast<std::size_t>(8) * n + 10],
                0.5f * (tile->dem.at(8, 8) + tile->dem.at(8, 12)), 1e-3f);
}

}  // namespace
