// SPDX-License-Identifier: Apache-2.0
// Level-of-detail selection over the tile quadtree (screen-space error, frustum culling,
// parents standing in for children that are still loading).
#include <gtest/gtest.h>

#include <map>
#include <set>

#include "navmap/render/terrain_lod.h"

namespace {

using namespace navmap;

struct FakeStore {
    map::TileScheme scheme{0.0, 0.0, 16384.0, 6};  // leaf tiles of 512 m
    std::map<std::uint64_t, std::shared_ptr<const map::Tile>> loaded;

    std::shared_ptr<const map::Tile> make(map::TileId id) {
        auto t = std::make_shared<map::Tile>();
        t->id = id;
        return t;
    }
    void loadAll() {
        for (int l = 0; l < scheme.levelCount(); ++l)
            for (std::uint32_t x = 0; x < (1u << l); ++x)
                for (std::uint32_t y = 0; y < (1u << l); ++y)
                    loaded[map::TileId{std::uint8_t(l), x, y}.key()] = make({std::uint8_t(l), x, y});
    }
    render::LodSelection select(const render::Camera& cam, double max_px = 3.0) {
        render::LodOptions o;
        o.max_error_px = max_px;
        o.dem_samples = 33;
        return render::selectLod(
            scheme, cam, 1280.0 / 480.0, 480, [&](map::TileId id) { return scheme.valid(id); },
            [&](map::TileId id) -> std::shared_ptr<const map::Tile> {
                auto it = loaded.find(id.key());
                return it == loaded.end() ? nullptr : it->second;
            },
            o);
    }
};

render::Camera lowCamera() {
    render::Camera c;
    c.eye = {8000.0, 2000.0, 300.0};
    c.target = {8000.0, 3000.0, 0.0};
    c.far_m = 30000.0;
    return c;
}

TEST(TerrainLod, NearTilesAreFinerThanFarTilesAndNothingOverlaps) {
    FakeStore s;
    s.loadAll();
    const auto sel = s.select(lowCamera());
    ASSERT_FALSE(sel.draw.empty());
    EXPECT_TRUE(sel.wanted.empty());
    EXPECT_EQ(sel.finest_level, 5);
    EXPECT_GT(sel.culled, 0u) << "tiles behind the camera are culled";
    // The tile under the camera's look-at point is a leaf; a distant tile is coarser.
    int near_level = -1, far_level = 99;
    for (const auto& t : sel.draw) {
        const auto b = s.scheme.bounds(t->id);
        if (b.contains({8000.0, 3000.0})) near_level = t->id.level;
        if (b.contains({8000.0, 15000.0})) far_level = t->id.level;
    }
    EXPECT_EQ(near_level, 5);
    EXPECT_LT(far_level, near_level);
    // No two drawn tiles overlap (a tile and its ancestor never both drawn).
    for (const auto& a : sel.draw)
        for (const auto& b : sel.draw) {
            if (a == b) continue;
            map::TileId x = a->id;
            while (x.level > b->id.level) x = x.parent();
            EXPECT_FALSE(x == b->id) << a->id.toString() << " inside " << b->id.toString();
        }
}

TEST(TerrainLod, HigherThresholdDrawsFewerTiles) {
    FakeStore s;
    s.loadAll();
    EXPECT_LT(s.select(lowCamera(), 12.0).draw.size(), s.select(lowCamera(), 2.0).draw.size());
}

TEST(TerrainLod, MissingChildrenAreRequestedAndTheParentIsDrawn) {
    FakeStore s;
    s.loaded[map::TileId{0, 0, 0}.key()] = s.make({0, 0, 0});
    const auto sel = s.select(lowCamera());
    ASSERT_EQ(sel.draw.size(), 1u);
    EXPECT_EQ(sel.draw[0]->id.level, 0);
    ASSERT_FALSE(sel.wanted.empty());
    // The missing children first, then the levels below them, coarse before fine.
    std::map<int, std::pair<float, float>> priority;  // level -> lowest, highest
    for (const auto& w : sel.wanted) {
        auto [it, fresh] = priority.try_emplace(w.id.level, w.priority, w.priority);
        it->second = {std::min(it->second.first, w.priority), std::max(it->second.second, w.priority)};
    }
    ASSERT_EQ(priority.begin()->first, 1);
    EXPECT_EQ(priority.rbegin()->first, 5) << "the leaves under the camera are asked for too";
    for (auto it = std::next(priority.begin()); it != priority.end(); ++it)
        EXPECT_LT(it->second.second, std::prev(it)->second.first) << "level " << it->first;
}

TEST(TerrainLod, OneRoundOfLoadingCompletesTheViewOfAnUnmovedCamera) {
    // Start-up and camera jumps: everything the first selection asks for, once loaded, is the
    // whole view; the selection does not discover one more level per round. Cameras at several
    // heights, headings and places, each from a store holding only the root.
    int cameras = 0;
    for (double height : {60.0, 300.0, 1500.0, 6000.0})
        for (double heading = 0.0; heading < 360.0; heading += 45.0)
            for (double x : {1000.0, 8000.0, 15800.0}) {
                FakeStore partial, full;
                full.loadAll();
                render::Camera c;
                const double a = glm::radians(heading);
                c.eye = {x, 8000.0, height};
                c.target = c.eye + glm::dvec3(std::sin(a) * 1000.0, std::cos(a) * 1000.0, -height * 0.8);
                c.far_m = 30000.0;
                partial.loaded[map::TileId{}.key()] = partial.make({});
                const auto first = partial.select(c);
                for (const auto& w : first.wanted) partial.loaded[w.id.key()] = partial.make(w.id);
                const auto second = partial.select(c);
                const auto reference = full.select(c);
                EXPECT_TRUE(second.wanted.empty()) << "height " << height << " heading " << heading << " x " << x
                                                   << ": " << second.wanted.size() << " more tiles wanted";
                std::set<std::uint64_t> drawn, expected;
                for (const auto& t : second.draw) drawn.insert(t->id.key());
                for (const auto& t : reference.draw) expected.insert(t->id.key());
                EXPECT_EQ(drawn, expected) << "height " << height << " heading " << heading << " x " << x;
                ++cameras;
            }
    EXPECT_EQ(cameras, 96);
}

TEST(TerrainLod, ScreenSpaceErrorHalvesWithDistance) {
    const double a = render::screenSpaceError(10.0, 1000.0, 45.0, 480);
    const double b = render::screenSpaceError(10.0, 2000.0, 45.0, 480);
    EXPECT_NEAR(a / b, 2.0, 1e-9);
    EXPECT_NEAR(a, 10.0 * 480 / (2.0 * 1000.0 * std::tan(glm::radians(22.5))), 1e-9);
}

}  // namespace
