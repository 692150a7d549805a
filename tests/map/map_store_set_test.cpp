// SPDX-License-Identifier: Apache-2.0
// Several stores mounted together (StoreSet): two stores 800 km apart drawn in one frame with
// their true positions, neighbouring tiles meeting edge to edge, and the refusals.

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>

#include "map_test_util.h"
#include "navmap/map/compile/compiler.h"
#include "navmap/map/road_graph.h"
#include "navmap/map/store_set.h"
#include "navmap/map/tile_cache.h"
#include "navmap/map/tile_store.h"
#include "synth_region.h"

using namespace navmap::map;
using navmap::map::test::repoData;
using navmap::map::test::ScratchDir;

namespace {

class TwoRegions : public ::testing::Test {
protected:
    static void SetUpTestSuite() {
        s_dir = new ScratchDir("store-set");
        CompileOptions a;
        a.osm = repoData("andorra-2021-04-14.osm.pbf");
        a.dems = {repoData("N42E001.hgt")};
        a.out = *s_dir / "andorra.navmap";
        (void)compileStore(a);
        // The same extract 7.2 degrees (800 km) north, in northern France, with its DEM moved along.
        std::filesystem::create_directories(*s_dir / "north");
        tools::SynthRegionOptions r;
        r.osm = a.osm;
        r.dem = repoData("N42E001.hgt");
        r.out_dir = *s_dir / "north";
        r.shift_lat_deg = 7.2;
        const tools::SynthRegion region = tools::synthesizeRegion(r);
        CompileOptions n;
        n.osm = region.osm;
        n.dems = region.dems;
        n.out = *s_dir / "north.navmap";
        (void)compileStore(n);
        a.out = *s_dir / "andorra-17.navmap";
        a.dem_samples = 17;
        (void)compileStore(a);
    }
    static void TearDownTestSuite() { delete s_dir; }
    static inline ScratchDir* s_dir = nullptr;
};

}  // namespace

TEST_F(TwoRegions, StoresFarApartAreDrawnInOneFrameAtTheirTruePositions) {
    const auto andorra = TileStore::open(*s_dir / "andorra.navmap");
    const auto north = TileStore::open(*s_dir / "north.navmap");
    const Projection frame = andorra->projection();
    const auto set = StoreSet::mount({andorra, north}, frame);
    EXPECT_GT(north->info().south - andorra->info().south, 7.1);
    // One scheme over both: the common ancestor of the two roots, a traversal root per store.
    EXPECT_TRUE(set->scheme().worldRoot().contains(andorra->scheme().worldRoot()));
    EXPECT_TRUE(set->scheme().worldRoot().contains(north->scheme().worldRoot()));
    ASSERT_EQ(set->roots().size(), 2u);
    EXPECT_EQ(set->scheme().worldTile(set->roots()[1]), north->scheme().worldRoot());

    // Every leaf tile of the north store, loaded through the set: its square is the set's, and
    // every road point lies where its own store puts it on the Earth, within a centimetre.
    const Projection north_frame = north->projection();
    const int leaf = north->scheme().leafLevel();
    std::size_t tiles = 0, points = 0, neighbours = 0;
    double worst = 0;
    for (const TileId nid : north->tileIds()) {
        if (nid.level != leaf) continue;
        const auto own = north->load(nid);
        ASSERT_TRUE(own.tile) << own.error;
        const auto id = set->scheme().fromWorld(north->scheme().worldTile(nid));
        ASSERT_TRUE(id);
        EXPECT_EQ(set->storeOf(*id), 1u);
        const auto r = set->load(*id);
        ASSERT_TRUE(r.tile) << r.error;
        const Box square = set->scheme().bounds(*id);
        EXPECT_EQ(r.tile->id, *id);
        EXPECT_DOUBLE_EQ(r.tile->origin_x, square.min_x);
        EXPECT_DOUBLE_EQ(r.tile->size_m, set->scheme().tileSize(id->level));
        if (r.tile->dem.size > 1) {
            EXPECT_NEAR(r.tile->dem.spacing_m * (r.tile->dem.size - 1), r.tile->size_m, 1e-3);
        }
        ASSERT_EQ(r.tile->roads.size(), own.tile->roads.size());
        for (std::size_t i = 0; i < own.tile->roads.size(); ++i) {
            const auto& mine = own.tile->roads[i].points;
            const auto& drawn = r.tile->roads[i].points;
            for (std::size_t j = 0; j < mine.size(); ++j) {
                double lat = 0, lon = 0;
                north_frame.reverse({own.tile->origin_x + mine[j].x, own.tile->origin_y + mine[j].y}, lat, lon);
                const PlanarPoint truth = frame.forward(lat, lon);
                worst = std::max(worst, std::hypot(r.tile->origin_x + drawn[j].x - truth.x,
                                                   r.tile->origin_y + drawn[j].y - truth.y));
                ++points;
            }
        }
        // Its east neighbour, where the store has one, starts where it ends: no crack, no overlap.
        const TileId east{nid.level, nid.x + 1, nid.y};
        if (north->contains(east)) {
            const auto e = set->load(*set->scheme().fromWorld(north->scheme().worldTile(east)));
            ASSERT_TRUE(e.tile);
            EXPECT_NEAR(e.tile->origin_x, r.tile->origin_x + r.tile->size_m, 1e-6);
            ++neighbours;
        }
        ++tiles;
    }
    EXPECT_GT(tiles, 50u);
    EXPECT_GT(points, 10000u);
    EXPECT_LT(worst, 0.01) << "metres";
    // Andorra's own tiles come through unchanged apart from their address.
    const TileId a_leaf = andorra->tileIds().back();
    const auto a = set->load(*set->scheme().fromWorld(andorra->scheme().worldTile(a_leaf)));
    ASSERT_TRUE(a.tile);
    EXPECT_EQ(a.tile->roads.size(), andorra->load(a_leaf).tile->roads.size());
    EXPECT_EQ(set->loads(0), 1u);
    EXPECT_EQ(set->loads(1), tiles + neighbours);
    // Between the two regions no store has a tile.
    const auto between = set->scheme().tileAt(set->scheme().leafLevel(), frame.forward(46.0, 1.5));
    ASSERT_TRUE(between);
    EXPECT_FALSE(set->contains(*between));
    EXPECT_TRUE(set->load(*between).missing);
}

TEST_F(TwoRegions, StoresWithDifferentDemGridsAreRefusedNamingBoth) {
    const auto andorra = TileStore::open(*s_dir / "andorra.navmap");
    const auto coarse = TileStore::open(*s_dir / "andorra-17.navmap");
    try {
        (void)StoreSet::mount({andorra, coarse}, andorra->projection());
        ADD_FAILURE() << "mounted";
    } catch (const StoreError& e) {
        EXPECT_EQ(std::string(e.what()), (*s_dir / "andorra-17.navmap").string() + ": 17 DEM samples per tile side, " +
                                             (*s_dir / "andorra.navmap").string() +
                                             " has 33 (stores mounted together need the same grid)");
    }
    EXPECT_THROW((void)StoreSet::mount({}, andorra->projection()), StoreError);
}

// A loaded tile carries the samples of the tiles of its level next to each shared border
// (TileDem::beyond), read from the store, so that the terrain's normals at the border are the same
// in both tiles; mounted in a set in another frame it carries the same heights.
TEST_F(TwoRegions, ATileCarriesItsNeighboursSamplesNextToItsBorders) {
    const auto andorra = TileStore::open(*s_dir / "andorra.navmap");
    const auto north = TileStore::open(*s_dir / "north.navmap");
    const auto set = StoreSet::mount({north, andorra}, north->projection());
    const int n = static_cast<int>(andorra->demSamples());
    int checked = 0;
    for (const TileId id : andorra->tileIds()) {
        if (id.level != andorra->scheme().leafLevel() || id.x == 0 || id.y == 0 || checked >= 8) continue;
        const TileId west{id.level, id.x - 1, id.y}, east{id.level, id.x + 1, id.y};
        const TileId south{id.level, id.x, id.y - 1}, northern{id.level, id.x, id.y + 1};
        if (!andorra->contains(west) || !andorra->contains(east) || !andorra->contains(south) ||
            !andorra->contains(northern))
            continue;
        const auto t = andorra->load(id).tile;
        ASSERT_TRUE(t);
        TileStore::LoadResult status;
        const auto alone = andorra->loadAlone(id, status);
        ASSERT_TRUE(alone);
        for (const auto& edge : alone->dem.beyond) EXPECT_TRUE(edge.empty());
        const auto w = andorra->load(west).tile, e = andorra->load(east).tile;
        const auto s = andorra->load(south).tile, no = andorra->load(northern).tile;
        for (const auto& edge : t->dem.beyond) ASSERT_EQ(edge.size(), static_cast<std::size_t>(n));
        for (int i = 0; i < n; ++i) {
            const auto k = static_cast<std::size_t>(i);
            EXPECT_EQ(t->dem.beyond[kDemWest][k], w->dem.at(i, n - 2));
            EXPECT_EQ(t->dem.beyond[kDemEast][k], e->dem.at(i, 1));
            EXPECT_EQ(t->dem.beyond[kDemSouth][k], s->dem.at(n - 2, i));
            EXPECT_EQ(t->dem.beyond[kDemNorth][k], no->dem.at(1, i));
        }
        // The tile across the east edge has this tile's samples next to the border beyond its west.
        for (int i = 0; i < n; ++i)
            EXPECT_EQ(e->dem.beyond[kDemWest][static_cast<std::size_t>(i)], t->dem.at(i, n - 2));
        const auto in_set = set->load(*set->scheme().fromWorld(andorra->scheme().worldTile(id))).tile;
        ASSERT_TRUE(in_set);
        EXPECT_NE(in_set->dem.spacing_m, t->dem.spacing_m) << "re-expressed into the north store's frame";
        for (std::size_t k = 0; k < 4; ++k) EXPECT_EQ(in_set->dem.beyond[k], t->dem.beyond[k]) << "edge " << k;
        ++checked;
    }
    EXPECT_EQ(checked, 8);
}

TEST_F(TwoRegions, ARecentredSetAndItsCacheGiveTheSameTilesInTheNewFrame) {
    const auto andorra = TileStore::open(*s_dir / "andorra.navmap");
    const auto north = TileStore::open(*s_dir / "north.navmap");
    const auto set = StoreSet::mount({andorra, north}, andorra->projection());
    // A frame around a vehicle in the north store, as the daemon re-centres it.
    const Projection around(49.7, 1.52);
    const auto moved = set->inFrame(around);
    const auto fresh = StoreSet::mount({andorra, north}, around);
    EXPECT_EQ(moved->scheme().worldRoot(), set->scheme().worldRoot());
    EXPECT_EQ(moved->roots(), set->roots()) << "the same tile ids";
    EXPECT_EQ(moved->frame().originLat(), 49.7);

    // Tiles of both stores come out as a set mounted in that frame gives them, and the load
    // counters go on counting.
    const int leaf = north->scheme().leafLevel();
    std::vector<TileId> ids;
    for (const TileId nid : north->tileIds())
        if (nid.level == leaf && ids.size() < 12)
            ids.push_back(*set->scheme().fromWorld(north->scheme().worldTile(nid)));
    ids.push_back(*set->scheme().fromWorld(andorra->scheme().worldTile(andorra->tileIds().back())));
    for (const TileId id : ids) {
        const auto a = moved->load(id), b = fresh->load(id);
        ASSERT_TRUE(a.tile && b.tile);
        EXPECT_EQ(a.tile->origin_x, b.tile->origin_x);
        EXPECT_EQ(a.tile->origin_y, b.tile->origin_y);
        ASSERT_EQ(a.tile->roads.size(), b.tile->roads.size());
        for (std::size_t i = 0; i < a.tile->roads.size(); ++i) {
            ASSERT_EQ(a.tile->roads[i].points.size(), b.tile->roads[i].points.size());
            for (std::size_t j = 0; j < a.tile->roads[i].points.size(); ++j) {
                EXPECT_EQ(a.tile->roads[i].points[j].x, b.tile->roads[i].points[j].x);
                EXPECT_EQ(a.tile->roads[i].points[j].y, b.tile->roads[i].points[j].y);
            }
        }
    }
    EXPECT_EQ(set->loads(1), ids.size() - 1) << "counted through the set it was re-centred from";
    EXPECT_EQ(set->loads(0), 1u);

    // The cache switches to the new frame: the tiles it was drawing are there again at once, in
    // the new frame; the ones nobody asked for lately are not reloaded.
    TileCache cache(set);
    std::vector<TileRequest> wanted;
    wanted.reserve(ids.size());
    for (const TileId id : ids) wanted.push_back({id, 1.0f});
    (void)cache.request(wanted);
    ASSERT_TRUE(cache.waitIdle(std::chrono::seconds(10)));
    const auto old_tile = cache.find(ids.front());
    ASSERT_TRUE(old_tile);
    EXPECT_EQ(cache.replaceSource(moved), ids.size());
    EXPECT_EQ(&cache.source(), moved.get());
    for (const TileId id : ids) {
        const auto t = cache.find(id);
        ASSERT_TRUE(t) << id.level << "/" << id.x << "/" << id.y;
        EXPECT_EQ(t->origin_x, moved->scheme().bounds(id).min_x);
        EXPECT_EQ(t->origin_y, moved->scheme().bounds(id).min_y);
    }
    EXPECT_NE(cache.find(ids.front())->origin_y, old_tile->origin_y);
    const auto loaded = cache.request(wanted);
    for (const auto& t : loaded) EXPECT_TRUE(t) << "all resident: nothing to wait for";
    EXPECT_EQ(cache.metrics().misses, ids.size()) << "only the first request missed";
}

TEST_F(TwoRegions, RoadGraphsOfTwoStoresAreMatchedInOneFrame) {
    const auto andorra = TileStore::open(*s_dir / "andorra.navmap");
    const auto north = TileStore::open(*s_dir / "north.navmap");
    RoadGraph both = andorra->loadGraph();
    const RoadGraph first = both;
    const RoadGraph second = north->loadGraph();
    ASSERT_GT(second.edges.size(), 1000u);
    const FrameTransform t = andorra->projection().transformFrom(north->projection());
    appendRoadGraph(both, second, t);
    ASSERT_EQ(both.nodes.size(), first.nodes.size() + second.nodes.size());
    ASSERT_EQ(both.edges.size(), first.edges.size() + second.edges.size());
    // The first graph's edges keep their indices; the second's nodes lie where their store puts them.
    for (std::size_t e = 0; e < first.edges.size(); e += 97) {
        EXPECT_EQ(both.edges[e].from, first.edges[e].from);
        EXPECT_EQ(both.edges[e].shape_begin, first.edges[e].shape_begin);
    }
    const Projection nf = north->projection();
    const Projection af = andorra->projection();
    for (std::size_t n = 0; n < second.nodes.size(); n += 101) {
        double lat = 0, lon = 0;
        nf.reverse({second.nodes[n].x, second.nodes[n].y}, lat, lon);
        const PlanarPoint p = af.forward(lat, lon);
        const GraphNode& m = both.nodes[first.nodes.size() + n];
        EXPECT_NEAR(m.x, p.x, 0.01);
        EXPECT_NEAR(m.y, p.y, 0.01);
        EXPECT_EQ(m.osm_id, second.nodes[n].osm_id);
    }
    // Each edge of the second graph leads out of its own node and along its own shape.
    for (std::uint32_t n = 0; n < second.nodes.size(); n += 53) {
        const auto mine = second.outEdges(n);
        const auto merged = both.outEdges(static_cast<std::uint32_t>(first.nodes.size()) + n);
        ASSERT_EQ(mine.size(), merged.size());
        for (std::size_t k = 0; k < mine.size(); ++k) {
            EXPECT_EQ(merged[k].to, mine[k].to + first.nodes.size());
            EXPECT_EQ(merged[k].shape_end - merged[k].shape_begin, mine[k].shape_end - mine[k].shape_begin);
            const LocalPoint a = both.shape[merged[k].shape_begin];
            const LocalPoint b = second.shape[mine[k].shape_begin];
            EXPECT_NEAR(a.x, t.scale * b.x + t.offset_x, 0.1);
            EXPECT_NEAR(a.y, t.scale * b.y + t.offset_y, 0.1);
        }
    }
}
