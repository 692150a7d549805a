// SPDX-License-Identifier: Apache-2.0
// Tile codec and store round trip, bad stores (other version, truncated, corrupt tile), the
// runtime cache (eviction under budget, corrupt tile skipped), tile selection, DEM input, the
// writer's lock and temporary file, and damage in every section of a store.
#include <gtest/gtest.h>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>
#include <zlib.h>

#include <algorithm>
#include <cmath>
#include <condition_variable>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <functional>
#include <mutex>
#include <random>
#include <thread>

#include "bounded_inflate.h"
#include "fuzz_corpus.h"
#include "map_test_util.h"
#include "navmap/map/compile/dem_mosaic.h"
#include "navmap/map/compile/spill_file.h"
#include "navmap/map/compile/store_writer.h"
#include "navmap/map/dem.h"
#include "navmap/map/tile_cache.h"
#include "navmap/map/tile_codec.h"
#include "navmap/map/tile_store.h"
#include "store_header.h"
#include "tile_selection.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size);

using namespace navmap::map;
using navmap::map::test::sampleTile;
using navmap::map::test::ScratchDir;

namespace {

StoreInfo smallInfo() {
    StoreInfo info;
    info.origin_lat = 42.5;
    info.origin_lon = 1.5;
    // World tile 12/2065/2583 (about 7.2 km at 42.5 N) holds the origin; 1.8 km leaves.
    info.scheme = TileScheme(Projection(info.origin_lat, info.origin_lon), worldTileAt(12, 42.5, 1.5), 3);
    info.dem_samples = 5;
    info.south = 42.46;
    info.north = 42.54;
    info.west = 1.45;
    info.east = 1.55;
    return info;
}

/// Writes every tile of the 3-level pyramid (1 + 4 + 16) with sample content.
void writeSmallStore(const std::filesystem::path& path, const RoadGraph* graph = nullptr) {
    const StoreInfo info = smallInfo();
    StoreWriter w(path, info);
    for (int level = 0; level < 3; ++level) {
        const std::uint32_t n = 1u << level;
        for (std::uint32_t y = 0; y < n; ++y) {
            for (std::uint32_t x = 0; x < n; ++x) {
                const TileId id{static_cast<std::uint8_t>(level), x, y};
                const Box b = info.scheme.bounds(id);
                w.addTile(sampleTile(id, b.min_x, b.min_y, info.scheme.tileSize(level)));
            }
        }
    }
    if (graph) w.setGraph(*graph);
    w.finish();
}

std::vector<std::uint8_t> readAll(const std::filesystem::path& p) {
    std::ifstream in(p, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), {}};
}

void writeAll(const std::filesystem::path& p, const std::vector<std::uint8_t>& bytes) {
    std::ofstream out(p, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
}

std::string openError(const std::filesystem::path& p) {
    try {
        TileStore::open(p);
    } catch (const StoreError& e) {
        return e.what();
    }
    return "";
}

}  // namespace

TEST(TileCodec, RoundTripKeepsValuesAtCentimetrePrecision) {
    const Tile in = sampleTile({6, 40, 33}, 123456.789, -98765.4321, 2000);
    const auto bytes = encodeTile(in);
    Tile out;
    std::string error;
    ASSERT_TRUE(decodeTile(bytes, out, error)) << error;
    EXPECT_EQ(out.id, in.id);
    EXPECT_DOUBLE_EQ(out.origin_x, in.origin_x);
    EXPECT_DOUBLE_EQ(out.origin_y, in.origin_y);
    ASSERT_EQ(out.roads.size(), 1u);
    const Road& r = out.roads[0];
    EXPECT_EQ(r.name, "Carrer de la Unió");
    EXPECT_EQ(r.ref, "CG-3");
    EXPECT_EQ(r.cls, RoadClass::Primary);
    EXPECT_EQ(r.flags, road_flags::kOneway | road_flags::kBridge);
    EXPECT_EQ(r.layer, -2);
    EXPECT_EQ(r.maxspeed_kmh, 50);
    EXPECT_EQ(r.osm_id, 123456789);
    ASSERT_EQ(r.points.size(), 3u);
    for (std::size_t i = 0; i < 3; ++i) {
        EXPECT_NEAR(r.points[i].x, in.roads[0].points[i].x, 0.0051);
        EXPECT_NEAR(r.points[i].y, in.roads[0].points[i].y, 0.0051);
    }
    ASSERT_EQ(out.buildings.size(), 1u);
    EXPECT_FLOAT_EQ(out.buildings[0].height_m, 12.5f);
    EXPECT_FLOAT_EQ(out.buildings[0].min_height_m, 3.0f);
    EXPECT_EQ(out.buildings[0].footprint.indices, in.buildings[0].footprint.indices);
    EXPECT_EQ(out.buildings[0].osm_id, -42);
    ASSERT_EQ(out.areas.size(), 1u);
    EXPECT_EQ(out.areas[0].cls, AreaClass::Forest);
    EXPECT_EQ(out.areas[0].name, "Bosc de l'Estany");
    ASSERT_EQ(out.labels.size(), 1u);
    EXPECT_EQ(out.labels[0].name, "Sant Julià de Lòria");
    EXPECT_NEAR(out.labels[0].anchor.x, 500.25f, 0.0051);
    EXPECT_FLOAT_EQ(out.labels[0].importance, 0.8f);
    ASSERT_EQ(out.dem.size, 5);
    for (std::size_t i = 0; i < 25; ++i) EXPECT_NEAR(out.dem.heights[i], in.dem.heights[i], 0.051);
}

TEST(TileCodec, RejectsTruncatedAndGarbledPayloads) {
    const auto bytes = encodeTile(sampleTile({1, 0, 1}, 0, 0, 1000));
    Tile out;
    std::string error;
    for (std::size_t cut : {std::size_t{0}, std::size_t{3}, std::size_t{40}, bytes.size() / 2, bytes.size() - 1}) {
        EXPECT_FALSE(decodeTile(std::span(bytes).first(cut), out, error)) << cut;
        EXPECT_FALSE(error.empty());
    }
    auto extra = bytes;
    extra.push_back(0);
    EXPECT_FALSE(decodeTile(extra, out, error));
    EXPECT_NE(error.find("trailing"), std::string::npos) << error;
}

TEST(TileCodec, FuzzEntryOnBadInputs) {
    // Corpus: empty, random bytes, every truncation and single-byte flips of a valid payload.
    LLVMFuzzerTestOneInput(nullptr, 0);
    const auto valid = encodeTile(sampleTile({2, 1, 3}, 10, 20, 500));
    std::mt19937 rng(1234);
    for (int i = 0; i < 200; ++i) {
        std::vector<std::uint8_t> junk(rng() % 300);
        for (auto& b : junk) b = static_cast<std::uint8_t>(rng());
        LLVMFuzzerTestOneInput(junk.data(), junk.size());
    }
    for (std::size_t cut = 0; cut < valid.size(); ++cut) LLVMFuzzerTestOneInput(valid.data(), cut);
    for (std::size_t i = 0; i < valid.size(); ++i) {
        auto flipped = valid;
        flipped[i] ^= static_cast<std::uint8_t>(1u << (i % 8));
        LLVMFuzzerTestOneInput(flipped.data(), flipped.size());
    }
    SUCCEED() << "no crash on " << 201 + 2 * valid.size() << " bad inputs";
}

// Every file of the checked-in libFuzzer corpus (tests/fuzz/corpus/tile_decode).
TEST(TileCodec, FuzzEntryOnCheckedInCorpus) {
    EXPECT_GE(navmap::test::runCheckedInCorpus(LLVMFuzzerTestOneInput, "tile_decode"), 20U);
}

TEST(TileStore, RoundTripAllTilesAndGraph) {
    ScratchDir dir("store-rt");
    RoadGraph g;
    g.nodes = {{0, 0, 1}, {100, 0, 2}};
    g.shape = {{0, 0}, {50, 1}, {100, 0}};
    g.edges = {{0, 1, 100.5f, 50, RoadClass::Primary, 0, 0, 3, 77},
               {1, 0, 100.5f, 50, RoadClass::Primary, edge_flags::kReversed, 0, 3, 77}};
    writeSmallStore(dir / "s.navmap", &g);
    const auto store = TileStore::open(dir / "s.navmap");
    EXPECT_EQ(store->info().tile_count, 21u);
    EXPECT_EQ(store->scheme().levelCount(), 3);
    EXPECT_DOUBLE_EQ(store->info().origin_lat, 42.5);
    for (const TileId& id : store->tileIds()) {
        const auto res = store->load(id);
        ASSERT_TRUE(res.tile) << res.error;
        EXPECT_EQ(res.tile->id, id);
        EXPECT_DOUBLE_EQ(res.tile->origin_x, store->scheme().bounds(id).min_x);
        EXPECT_EQ(res.tile->labels.at(0).name, "Sant Julià de Lòria");
    }
    const auto absent = store->load({2, 9, 9});
    EXPECT_TRUE(absent.missing);
    const RoadGraph back = store->loadGraph();
    ASSERT_EQ(back.edges.size(), 2u);
    EXPECT_EQ(back.outEdges(0).size(), 1u);
    EXPECT_EQ(back.outEdges(1)[0].to, 0u);
    EXPECT_EQ(back.outEdges(1)[0].flags, edge_flags::kReversed);
    EXPECT_FLOAT_EQ(back.edges[0].length_m, 100.5f);
    EXPECT_EQ(back.shape.size(), 3u);
}

TEST(TileStore, OtherVersionTruncatedAndNotAStoreAreClearErrors) {
    ScratchDir dir("store-bad");
    writeSmallStore(dir / "s.navmap");
    auto bytes = readAll(dir / "s.navmap");

    auto v4 = bytes;
    v4[8] = 4;  // format version field
    writeAll(dir / "v4.navmap", v4);
    std::string e = openError(dir / "v4.navmap");
    EXPECT_EQ(e, (dir / "v4.navmap").string() +
                     ": tile store format version 4, this build reads version 3 (recompile the store with this "
                     "navmap-compile)");

    writeAll(dir / "trunc.navmap",
             std::vector<std::uint8_t>(bytes.begin(), bytes.begin() + static_cast<long>(bytes.size() / 2)));
    e = openError(dir / "trunc.navmap");
    EXPECT_NE(e.find("trunc.navmap: truncated"), std::string::npos) << e;

    writeAll(dir / "junk.navmap", std::vector<std::uint8_t>(100, 0x41));
    e = openError(dir / "junk.navmap");
    EXPECT_NE(e.find("junk.navmap: not a navmap tile store"), std::string::npos) << e;

    auto hdr = bytes;
    hdr[20] ^= 0x10;  // inside origin_lat: header checksum must catch it
    writeAll(dir / "hdr.navmap", hdr);
    e = openError(dir / "hdr.navmap");
    EXPECT_NE(e.find("header checksum mismatch"), std::string::npos) << e;

    e = openError(dir / "missing.navmap");
    EXPECT_NE(e.find("open("), std::string::npos) << e;
    EXPECT_NE(e.find("No such file"), std::string::npos) << e;
}

TEST(TileCache, CorruptTileIsSkippedAndReportedRestKeepsWorking) {
    ScratchDir dir("store-corrupt");
    writeSmallStore(dir / "s.navmap");
    auto bytes = readAll(dir / "s.navmap");
    const TileId victim{2, 1, 2};
    std::uint64_t offset = 0;
    {
        const auto store = TileStore::open(dir / "s.navmap");
        ASSERT_GT(store->storedSize(victim), 0u);
        offset = store->blobOffset(victim) + store->storedSize(victim) / 2;
    }
    ASSERT_GT(offset, 0u);
    bytes[offset] ^= 0xFF;
    writeAll(dir / "c.navmap", bytes);
    const auto store = TileStore::open(dir / "c.navmap");
    const auto res = store->load(victim);
    EXPECT_FALSE(res.tile);
    EXPECT_NE(res.error.find("c.navmap: tile 2/1/2: checksum mismatch"), std::string::npos) << res.error;

    TileCache cache(store, {std::size_t{64} << 20, false});
    std::vector<TileRequest> want;
    for (std::uint32_t y = 0; y < 4; ++y)
        for (std::uint32_t x = 0; x < 4; ++x) want.push_back({{2, x, y}, 1.0f});
    cache.request(want);
    ASSERT_TRUE(cache.waitIdle(std::chrono::seconds(10)));
    const auto got = cache.request(want);
    int resident = 0;
    for (std::size_t i = 0; i < want.size(); ++i) {
        if (want[i].id == victim)
            EXPECT_FALSE(got[i]);
        else if (got[i])
            ++resident;
    }
    EXPECT_EQ(resident, 15);
    const auto m = cache.metrics();
    EXPECT_EQ(m.corrupt, 1u);
    EXPECT_NE(m.last_error.find("2/1/2"), std::string::npos);
    ASSERT_EQ(cache.corruptTiles().size(), 1u);
    EXPECT_EQ(cache.corruptTiles()[0], victim);
    // Not retried on later requests.
    cache.request(want);
    ASSERT_TRUE(cache.waitIdle(std::chrono::seconds(10)));
    EXPECT_EQ(cache.metrics().loads, m.loads);
}

TEST(TileCache, EvictsLeastRecentlyUsedUnderBudget) {
    ScratchDir dir("store-lru");
    writeSmallStore(dir / "s.navmap");
    const auto store = TileStore::open(dir / "s.navmap");
    const std::size_t one = store->load({2, 0, 0}).tile->byteSize();
    const std::size_t budget = one * 4 + one / 2;  // room for four tiles
    TileCache cache(store, {budget, false});
    std::size_t max_seen = 0;
    // Fly over the 16 leaf tiles two at a time; each request wants 2 tiles.
    for (std::uint32_t step = 0; step < 8; ++step) {
        const std::vector<TileRequest> want{{{2, (2 * step) % 4, (2 * step) / 4}, 2.0f},
                                            {{2, (2 * step + 1) % 4, (2 * step + 1) / 4}, 1.0f}};
        cache.request(want);
        ASSERT_TRUE(cache.waitIdle(std::chrono::seconds(10)));
        const auto got = cache.request(want);
        EXPECT_TRUE(got[0] && got[1]) << "step " << step;
        const auto m = cache.metrics();
        max_seen = std::max(max_seen, m.resident_bytes);
        EXPECT_LE(m.resident_bytes, budget);
        EXPECT_LE(m.resident_tiles, 4u);
    }
    const auto m = cache.metrics();
    EXPECT_EQ(m.loads, 16u);
    EXPECT_EQ(m.evictions, 12u);
    EXPECT_EQ(m.misses, 16u);
    EXPECT_EQ(m.hits, 16u);
    EXPECT_LE(m.peak_resident_bytes, budget);
    EXPECT_GT(m.load_p99_ms, 0.0);
    EXPECT_GE(m.load_p99_ms, m.load_p50_ms);
    // The first tiles were evicted (least recently used), the last ones are resident.
    EXPECT_FALSE(cache.find({2, 0, 0}));
    EXPECT_TRUE(cache.find({2, 3, 3}));
}

TEST(TileCache, WantedSetLargerThanBudgetStaysBounded) {
    ScratchDir dir("store-over");
    writeSmallStore(dir / "s.navmap");
    const auto store = TileStore::open(dir / "s.navmap");
    // Room for three of the largest tiles (a tile inside the grid carries more heights beyond its
    // edges than one at a corner), never for four.
    std::size_t one = 0;
    std::vector<TileRequest> want;
    for (std::uint32_t i = 0; i < 16; ++i) {
        want.push_back({{2, i % 4, i / 4}, static_cast<float>(16 - i)});
        one = std::max(one, store->load(want.back().id).tile->byteSize());
    }
    TileCache cache(store, {one * 3, false});
    for (int frame = 0; frame < 3; ++frame) {
        cache.request(want);
        ASSERT_TRUE(cache.waitIdle(std::chrono::seconds(10)));
    }
    const auto got = cache.request(want);
    const auto m = cache.metrics();
    EXPECT_LE(m.resident_bytes, one * 3);
    EXPECT_EQ(m.resident_tiles, 3u);
    // The highest-priority tiles are the resident ones.
    EXPECT_TRUE(got[0] && got[1] && got[2]);
    EXPECT_GT(m.dropped_over_budget, 0u);
    EXPECT_LT(m.loads, 20u);  // no load-evict thrash across frames
}

// A store whose first load waits for the test: the requests made meanwhile are all queued.
class GatedSource : public TileSource {
public:
    explicit GatedSource(std::shared_ptr<const TileStore> store) : m_store(std::move(store)) {}
    [[nodiscard]] const TileScheme& scheme() const override { return m_store->scheme(); }
    [[nodiscard]] bool contains(TileId id) const override { return m_store->contains(id); }
    [[nodiscard]] std::uint32_t demSamples() const override { return m_store->demSamples(); }
    [[nodiscard]] TileLoadResult load(TileId id) const override {
        std::unique_lock lock(m_mutex);
        m_order.push_back(id);
        m_loading.notify_all();
        m_gate.wait(lock, [&] { return m_open; });
        lock.unlock();
        return m_store->load(id);
    }
    void waitForFirstLoad() const {
        std::unique_lock lock(m_mutex);
        m_loading.wait(lock, [&] { return !m_order.empty(); });
    }
    void open() {
        std::lock_guard lock(m_mutex);
        m_open = true;
        m_gate.notify_all();
    }
    std::vector<TileId> order() const {
        std::lock_guard lock(m_mutex);
        return m_order;
    }

private:
    std::shared_ptr<const TileStore> m_store;
    mutable std::mutex m_mutex;
    mutable std::condition_variable m_gate, m_loading;
    mutable std::vector<TileId> m_order;
    bool m_open = false;
};

// Displays sharing one cache request into queues of their own: a later request of one display
// does not drop what another asked for, and the lower queue (the cluster) loads first.
TEST(TileCache, EachQueueKeepsItsRequestsAndTheLowestQueueLoadsFirst) {
    ScratchDir dir("store-queues");
    writeSmallStore(dir / "s.navmap");
    const auto source = std::make_shared<GatedSource>(TileStore::open(dir / "s.navmap"));
    TileCache cache(source, {std::size_t{64} << 20, false});
    const TileId first{2, 0, 0};
    cache.request(std::vector<TileRequest>{{first, 1.0f}}, 2);
    source->waitForFirstLoad();  // the loader holds `first` until open()
    const std::vector<TileRequest> center{{{2, 1, 0}, 3.0f}, {{2, 2, 0}, 2.0f}, {{2, 3, 0}, 1.0f}};
    const std::vector<TileRequest> hud{{{2, 0, 3}, 1.0f}};
    const std::vector<TileRequest> cluster{{{2, 0, 1}, 1.0f}, {{2, 1, 1}, 2.0f}};
    cache.request(center, 2);
    cache.request(hud, 1);
    cache.request(cluster, 0);
    source->open();
    ASSERT_TRUE(cache.waitIdle(std::chrono::seconds(10)));
    const std::vector<TileId> want{first, {2, 1, 1}, {2, 0, 1}, {2, 0, 3}, {2, 1, 0}, {2, 2, 0}, {2, 3, 0}};
    EXPECT_EQ(source->order(), want);
    for (const auto& id : want) EXPECT_TRUE(cache.find(id)) << id.toString();
    EXPECT_EQ(cache.metrics().pending, 0u);
}

TEST(TileSelection, FootprintAndPrefetchAhead) {
    const TileScheme s(0, 0, 16000, 4);  // 2 km leaves, 8x8
    CameraFootprint cam;
    cam.position = {3000, 3000};
    cam.ground = {{2500, 2500}, {3500, 2500}, {3500, 3500}, {2500, 3500}};
    cam.heading_deg = 90;  // east
    cam.prefetch_m = 6000;
    const auto req = selectTiles(s, 3, cam);
    ASSERT_FALSE(req.empty());
    EXPECT_EQ(req[0].id, (TileId{3, 1, 1}));  // the visible tile first
    EXPECT_GE(req[0].priority, 1000.0f);
    bool east_prefetched = false;
    for (const auto& r : req) {
        if (r.id == TileId{3, 4, 1}) {
            east_prefetched = true;
            EXPECT_LT(r.priority, 1000.0f);
        }
    }
    EXPECT_TRUE(east_prefetched);
    // A rotated footprint covering 4 tiles around the corner point (4000, 4000).
    const std::vector<PlanarPoint> diamond{{4000, 3500}, {4500, 4000}, {4000, 4500}, {3500, 4000}};
    EXPECT_EQ(tilesInPolygon(s, 3, diamond, {4000, 4000}, 1000).size(), 4u);
    EXPECT_EQ(tilesInCircle(s, 3, {1000, 1000}, 100, 1000).size(), 1u);
}

TEST(Dem, VoidsAreFilledAndWrongSizeIsAnError) {
    ScratchDir dir("dem");
    // A synthetic SRTM3 tile: a tilted plane with a square void in the middle.
    std::vector<std::uint8_t> bytes(1201u * 1201u * 2u);
    std::size_t voids = 0;
    for (int r = 0; r < 1201; ++r) {
        for (int c = 0; c < 1201; ++c) {
            std::int16_t v = static_cast<std::int16_t>(500 + c / 2);
            if (r >= 500 && r < 520 && c >= 600 && c < 620) {
                v = -32768;
                ++voids;
            }
            const std::size_t i = (static_cast<std::size_t>(r) * 1201 + c) * 2;
            bytes[i] = static_cast<std::uint8_t>(static_cast<std::uint16_t>(v) >> 8);
            bytes[i + 1] = static_cast<std::uint8_t>(v & 0xff);
        }
    }
    writeAll(dir / "N42E001.hgt", bytes);
    Dem dem = loadHgt(dir / "N42E001.hgt");
    EXPECT_EQ(dem.void_count, voids);
    EXPECT_TRUE(std::isnan(dem.at(510, 610)));
    EXPECT_EQ(fillVoids(dem), voids);
    EXPECT_NEAR(dem.at(510, 610), 500 + 610 / 2, 5.0);  // smooth fill joins the rim
    DemMosaic mosaic;
    mosaic.add(std::move(dem));
    ASSERT_TRUE(mosaic.sample(42.5, 1.5));
    EXPECT_NEAR(*mosaic.sample(42.5, 1.5), 800.0f, 1.0f);
    EXPECT_FALSE(mosaic.sample(41.5, 1.5));  // outside: the compiler renders it flat and warns

    writeAll(dir / "N42E002.hgt", std::vector<std::uint8_t>(1000, 0));
    try {
        loadHgt(dir / "N42E002.hgt");
        FAIL() << "expected DemError";
    } catch (const DemError& e) {
        EXPECT_NE(std::string(e.what()).find("N42E002.hgt: 1000 bytes is not an SRTM tile"), std::string::npos)
            << e.what();
    }
}

namespace {

std::vector<std::string> listDir(const std::filesystem::path& d) {
    std::vector<std::string> names;
    for (const auto& e : std::filesystem::directory_iterator(d)) names.push_back(e.path().filename().string());
    std::sort(names.begin(), names.end());
    return names;
}

}  // namespace

TEST(Dem, FilesReadOnFirstUseAreDroppedOverTheBudgetAndSampleTheSame) {
    ScratchDir dir("dem-files");
    // Three SRTM3 tiles side by side, each a plane of its own height with a void.
    for (int k = 0; k < 3; ++k) {
        std::vector<std::uint8_t> bytes(1201u * 1201u * 2u);
        for (std::size_t i = 0; i < 1201u * 1201u; ++i) {
            const auto v =
                static_cast<std::int16_t>(i == 600u * 1201u + 600u ? -32768 : 100 * (k + 1) + int(i % 1201) / 10);
            bytes[2 * i] = static_cast<std::uint8_t>(static_cast<std::uint16_t>(v) >> 8);
            bytes[2 * i + 1] = static_cast<std::uint8_t>(v & 0xff);
        }
        writeAll(dir / ("N42E00" + std::to_string(k + 1) + ".hgt"), bytes);
    }
    DemMosaic eager, lazy;
    for (int k = 0; k < 3; ++k) {
        const auto file = dir / ("N42E00" + std::to_string(k + 1) + ".hgt");
        Dem dem = loadHgt(file);
        fillVoids(dem);
        eager.add(std::move(dem));
        lazy.addFile(file);
    }
    const std::size_t grid = 1201u * 1201u * sizeof(float);
    lazy.setBudget(grid, 1);  // one grid at a time
    EXPECT_EQ(lazy.fileLoads(), 0u) << "nothing read before a sample needs it";
    // West to east and back, as the bands of a bounded compile go, then across a border.
    std::size_t samples = 0;
    for (const double lon : {1.2, 1.7, 2.2, 2.9, 3.3, 3.8, 2.5, 1.5, 2.0, 2.00001}) {
        for (const double lat : {42.1, 42.5, 42.9, 42.5005}) {
            ASSERT_EQ(lazy.sample(lat, lon), eager.sample(lat, lon)) << lat << " " << lon;
            ++samples;
        }
    }
    EXPECT_EQ(samples, 40u);
    EXPECT_EQ(lazy.fileLoads(), 6u) << "E001, E002, E003, E002, E001 (the border at 2.0 from it), E002";
    EXPECT_LE(lazy.peakFileBytes(), 2 * grid) << "the one in use and the one being replaced";
    EXPECT_EQ(lazy.voidsFilled(), 3u) << "each file's void counted once";
    EXPECT_FALSE(lazy.sample(41.5, 1.5));
    EXPECT_THROW(lazy.addFile(dir / "N42E009.hgt"), DemError);

    // With a scratch folder, a grid dropped and needed again comes back from its filled copy
    // there: each file is read once, and the samples are the same.
    ScratchDir scratch("dem-scratch");
    DemMosaic copied;
    for (int k = 0; k < 3; ++k) copied.addFile(dir / ("N42E00" + std::to_string(k + 1) + ".hgt"));
    copied.setBudget(grid, 1);
    copied.setScratchDir(scratch.path());
    for (const double lon : {1.2, 1.7, 2.2, 2.9, 3.3, 3.8, 2.5, 1.5, 2.0, 2.00001}) {
        for (const double lat : {42.1, 42.5, 42.9, 42.5005}) {
            ASSERT_EQ(copied.sample(lat, lon), eager.sample(lat, lon)) << lat << " " << lon;
        }
    }
    EXPECT_EQ(copied.fileLoads(), 3u);
    EXPECT_EQ(copied.scratchReads(), 3u) << "E002, E001, E002 came back from their copies";
    EXPECT_EQ(copied.voidsFilled(), 3u);
    EXPECT_EQ(listDir(scratch.path()), (std::vector<std::string>{"dem-0.grid", "dem-1.grid", "dem-2.grid"}));
    // A damaged copy is an error naming it, not wrong heights.
    {
        std::fstream f(scratch / "dem-0.grid", std::ios::in | std::ios::out | std::ios::binary);
        f.seekg(100);
        const char c = static_cast<char>(f.get());
        f.seekp(100);
        f.put(static_cast<char>(~c));
    }
    EXPECT_TRUE(copied.sample(42.5, 3.5));  // E003 in use, E001 dropped
    try {
        (void)copied.sample(42.5, 1.5);
        ADD_FAILURE() << "a damaged copy was read";
    } catch (const SpillError& e) {
        EXPECT_EQ(std::string(e.what()),
                  (scratch / "dem-0.grid").string() + ": damaged: checksum mismatch in the record at byte 8");
    }
}

namespace {

std::string writerError(const std::filesystem::path& p) {
    try {
        StoreWriter w(p, smallInfo());
    } catch (const StoreError& e) {
        return e.what();
    }
    return "";
}

std::string fileText(const std::filesystem::path& p) {
    std::ifstream in(p, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), {}};
}

}  // namespace

TEST(StoreWriter, AMissingFolderIsAnErrorAndIsNotCreated) {
    ScratchDir dir("writer-folder");
    const auto out = dir / "missing/sub/x.navmap";
    EXPECT_EQ(writerError(out), out.string() + ": directory " + (dir / "missing/sub").string() + " does not exist");
    EXPECT_FALSE(std::filesystem::exists(dir / "missing"));
    std::ofstream(dir / "file") << "x";
    EXPECT_EQ(writerError(dir / "file/x.navmap"),
              (dir / "file/x.navmap").string() + ": " + (dir / "file").string() + " is not a directory");
    EXPECT_EQ(listDir(dir.path()), std::vector<std::string>{"file"});
}

TEST(StoreWriter, ASecondWriterIsRefusedWithTheFirstOnesPid) {
    ScratchDir dir("writer-lock");
    const auto out = dir / "s.navmap";
    {
        StoreWriter first(out, smallInfo());
        EXPECT_EQ(fileText(dir / "s.navmap.lock"), std::to_string(::getpid()) + "\n");
        EXPECT_EQ(writerError(out),
                  out.string() + " is being written by another process (pid " + std::to_string(::getpid()) + ")");
        // The refused writer left the first one's files alone.
        EXPECT_TRUE(std::filesystem::exists(first.temporaryPath()));
        EXPECT_TRUE(std::filesystem::exists(dir / "s.navmap.lock"));
        first.finish();
    }
    // Released: the next writer goes ahead, and only the store is left.
    writeSmallStore(out);
    EXPECT_EQ(listDir(dir.path()), std::vector<std::string>{"s.navmap"});
    EXPECT_EQ(TileStore::open(out)->tileIds().size(), 21u);
}

TEST(StoreWriter, PlantedSymlinksAreNeverFollowed) {
    ScratchDir dir("writer-symlink");
    const auto out = dir / "s.navmap";
    const auto victim = dir / "victim.txt";
    std::ofstream(victim) << "precious\n";
    // At the old fixed temporary name, at a name of the temporary pattern, and at the store itself.
    std::filesystem::create_symlink(victim, dir / "s.navmap.tmp");
    std::filesystem::create_symlink(victim, dir / "s.navmap.tmp-0123456789abcdef");
    std::filesystem::create_symlink(victim, out);
    writeSmallStore(out);
    EXPECT_EQ(fileText(victim), "precious\n");
    EXPECT_TRUE(std::filesystem::is_symlink(dir / "s.navmap.tmp"));
    EXPECT_TRUE(std::filesystem::is_symlink(dir / "s.navmap.tmp-0123456789abcdef"));
    EXPECT_FALSE(std::filesystem::is_symlink(out));  // replaced by the store, not written through
    EXPECT_EQ(TileStore::open(out)->tileIds().size(), 21u);

    // At the lock name: refused, nothing written, the target untouched (or not created).
    std::filesystem::create_symlink(victim, dir / "t.navmap.lock");
    EXPECT_EQ(writerError(dir / "t.navmap"),
              (dir / "t.navmap.lock").string() + ": is a symbolic link; refusing to follow it");
    std::filesystem::create_symlink(dir / "absent", dir / "u.navmap.lock");
    EXPECT_EQ(writerError(dir / "u.navmap"),
              (dir / "u.navmap.lock").string() + ": is a symbolic link; refusing to follow it");
    EXPECT_FALSE(std::filesystem::exists(dir / "absent"));
    // A hard link at the lock name would have its target truncated: refused too.
    std::filesystem::create_hard_link(victim, dir / "v.navmap.lock");
    EXPECT_EQ(writerError(dir / "v.navmap"),
              (dir / "v.navmap.lock").string() + ": not a regular file with a single link; refusing to use it");
    EXPECT_EQ(fileText(victim), "precious\n");
    EXPECT_EQ(listDir(dir.path()),
              (std::vector<std::string>{"s.navmap", "s.navmap.tmp", "s.navmap.tmp-0123456789abcdef", "t.navmap.lock",
                                        "u.navmap.lock", "v.navmap.lock", "victim.txt"}));
}

TEST(StoreWriter, FailuresLeaveNoTemporaryOrLockFileAndLeftoversAreRemoved) {
    ScratchDir dir("writer-cleanup");
    const auto out = dir / "s.navmap";
    {
        StoreWriter w(out, smallInfo());
        w.addTile(sampleTile({0, 0, 0}, -4000, -4000, 8000));
        EXPECT_EQ(listDir(dir.path()).size(), 2u);  // the temporary file and the lock
    }                                               // abandoned without finish(): as after an exception
    EXPECT_TRUE(listDir(dir.path()).empty());
    // A writer killed mid-way leaves its temporary file; the next writer of the store removes
    // it (only files of the store's temporary pattern).
    std::ofstream(dir / "s.navmap.tmp-00000000deadbeef") << "half a store";
    std::ofstream(dir / "s.navmap.tmp-notmine") << "kept";
    std::ofstream(dir / "other.navmap.tmp-00000000deadbeef") << "kept";
    writeSmallStore(out);
    EXPECT_EQ(listDir(dir.path()),
              (std::vector<std::string>{"other.navmap.tmp-00000000deadbeef", "s.navmap", "s.navmap.tmp-notmine"}));
}

// docs/tile-store.md "Damage": one policy for every section of a store. The header and the index
// are fatal (nothing can be found without them) with an error naming the section; a damaged tile
// or road graph leaves everything else loading and is reported by what reads it.
namespace {

RoadGraph smallGraph() {
    RoadGraph g;
    g.nodes = {{0, 0, 1}, {100, 0, 2}};
    g.shape = {{0, 0}, {50, 1}, {100, 0}};
    g.edges = {{0, 1, 100.5f, 50, RoadClass::Primary, 0, 0, 3, 77},
               {1, 0, 100.5f, 50, RoadClass::Primary, edge_flags::kReversed, 0, 3, 77}};
    return g;
}

/// Tiles of `store` that fail to load, as "L/X/Y".
std::vector<std::string> unloadable(const TileStore& store) {
    std::vector<std::string> bad;
    for (const auto& id : store.tileIds()) {
        if (!store.load(id).tile) bad.push_back(id.toString());
    }
    return bad;
}

}  // namespace

TEST(StoreDamage, EveryBitOfTheHeaderAndTheIndexIsFatalNamingTheSection) {
    ScratchDir dir("damage-fatal");
    const RoadGraph g = smallGraph();
    writeSmallStore(dir / "s.navmap", &g);
    const auto bytes = readAll(dir / "s.navmap");
    const std::uint64_t index_offset = TileStore::open(dir / "s.navmap")->info().index_offset;
    ASSERT_EQ(bytes.size(), index_offset + 21 * 29);
    const auto path = dir / "d.navmap";
    writeAll(path, bytes);
    // Flipped in place and back: one byte written per case.
    const int fd = ::open(path.c_str(), O_RDWR | O_CLOEXEC);
    ASSERT_GE(fd, 0);
    const auto poke = [&](std::size_t at, std::uint8_t value) {
        return ::pwrite(fd, &value, 1, static_cast<off_t>(at)) == 1;
    };
    std::size_t checked = 0;
    for (std::size_t byte = 0; byte < bytes.size(); byte = byte + 1 == 144 ? index_offset : byte + 1) {
        for (int bit = 0; bit < 8; ++bit) {
            ASSERT_TRUE(poke(byte, static_cast<std::uint8_t>(bytes[byte] ^ (1u << bit))));
            const std::string e = openError(path);
            ASSERT_TRUE(poke(byte, bytes[byte]));
            const std::string expected = byte < 8     ? "not a navmap tile store (bad magic)"
                                         : byte < 12  ? "tile store format version "
                                         : byte < 16  ? "truncated or malformed header"
                                         : byte < 144 ? "header checksum mismatch"
                                                      : "tile index checksum mismatch";
            ASSERT_EQ(e.rfind(path.string() + ": " + expected, 0), 0u)
                << "byte " << byte << " bit " << bit << ": " << e;
            ++checked;
        }
    }
    ::close(fd);
    EXPECT_EQ(checked, (144 + 21 * 29) * 8u);
}

TEST(StoreDamage, ADamagedTileOrGraphLeavesTheRestUsableAndIsReported) {
    ScratchDir dir("damage-degrade");
    const RoadGraph g = smallGraph();
    writeSmallStore(dir / "s.navmap", &g);
    const auto bytes = readAll(dir / "s.navmap");
    const auto clean = TileStore::open(dir / "s.navmap");
    const auto path = dir / "d.navmap";

    // Every tile, one level after another: its first, middle and last byte.
    for (const TileId& victim : clean->tileIds()) {
        const std::uint64_t begin = clean->blobOffset(victim), size = clean->storedSize(victim);
        for (const std::uint64_t at : {begin, begin + size / 2, begin + size - 1}) {
            auto d = bytes;
            d[at] ^= 0x04;
            writeAll(path, d);
            const auto store = TileStore::open(path);
            const auto res = store->load(victim);
            EXPECT_FALSE(res.tile);
            EXPECT_EQ(res.error, path.string() + ": tile " + victim.toString() + ": checksum mismatch (corrupt tile)");
            EXPECT_EQ(unloadable(*store), std::vector<std::string>{victim.toString()});
            EXPECT_TRUE(store->tryLoadGraph().ok());
        }
    }

    // The road graph: the map loads whole, the graph says why it is unavailable.
    const std::uint64_t graph_at = clean->info().graph_offset, graph_size = clean->info().graph_stored_size;
    ASSERT_GT(graph_size, 0u);
    for (const std::uint64_t at : {graph_at, graph_at + graph_size / 2, graph_at + graph_size - 1}) {
        auto d = bytes;
        d[at] ^= 0x80;
        writeAll(path, d);
        const auto store = TileStore::open(path);
        EXPECT_TRUE(unloadable(*store).empty());
        const auto graph = store->tryLoadGraph();
        EXPECT_FALSE(graph.ok());
        EXPECT_EQ(graph.problem, "checksum mismatch");
        EXPECT_EQ(graph.error, path.string() + ": road graph: checksum mismatch");
        EXPECT_TRUE(graph.graph.nodes.empty() && graph.graph.edges.empty());
        try {
            (void)store->loadGraph();
            ADD_FAILURE() << "loadGraph() accepted a damaged graph";
        } catch (const StoreError& e) {
            EXPECT_EQ(std::string(e.what()), graph.error);
        }
    }

    // The undamaged store's graph loads.
    const auto intact = TileStore::open(dir / "s.navmap")->tryLoadGraph();
    ASSERT_TRUE(intact.ok()) << intact.error;
    EXPECT_EQ(intact.graph.edges.size(), 2u);
}

TEST(StoreDamage, EveryKindOfTilePayloadDamageIsAnErrorForThatTileOnly) {
    // The payload sections (roads, buildings, areas, labels, DEM) are compressed together, so
    // damage on disk fails the tile's checksum as a whole (above). Damage the checksum cannot
    // see (a broken writer) must still be caught by the decoder, section by section: each
    // section's count is made implausible, the blob written with a valid checksum.
    ScratchDir dir("damage-payload");
    const StoreInfo info = smallInfo();
    const TileId victim{2, 1, 2};
    const Box vb = info.scheme.bounds(victim);
    const Tile tile = sampleTile(victim, vb.min_x, vb.min_y, info.scheme.tileSize(2));
    const auto full = encodeTile(tile);
    // Section starts: the payload header is 37 bytes; a section's length is what clearing it saves
    // (plus its one-byte zero count).
    auto without = [&](auto clear) {
        Tile t = tile;
        clear(t);
        return full.size() - encodeTile(t).size() + 1;
    };
    const std::size_t roads = 37;
    const std::size_t buildings = roads + without([](Tile& t) { t.roads.clear(); });
    const std::size_t areas = buildings + without([](Tile& t) { t.buildings.clear(); });
    const std::size_t labels = areas + without([](Tile& t) { t.areas.clear(); });
    const std::size_t dem = labels + without([](Tile& t) { t.labels.clear(); });
    struct Kind {
        const char* name;
        std::size_t at;
        std::vector<std::uint8_t> bytes;
        std::string error;
    };
    const Kind kinds[] = {
        {"roads", roads, {0x7F}, "implausible road count 127"},
        {"buildings", buildings, {0x7F}, "implausible building count 127"},
        {"areas", areas, {0x7F}, "implausible area count 127"},
        {"labels", labels, {0x7F}, "implausible label count 127"},
        {"dem", dem, {0xFF, 0xFF}, "implausible DEM size 65535"},
    };
    for (const auto& k : kinds) {
        ASSERT_EQ(full.at(k.at), k.name == std::string("dem") ? 5 : 1) << k.name;  // one of each; DEM 5x5
        auto payload = full;
        std::copy(k.bytes.begin(), k.bytes.end(), payload.begin() + static_cast<long>(k.at));
        const auto path = dir / (std::string(k.name) + ".navmap");
        {
            StoreWriter w(path, info);
            for (int level = 0; level < 3; ++level) {
                const std::uint32_t n = 1u << level;
                for (std::uint32_t y = 0; y < n; ++y) {
                    for (std::uint32_t x = 0; x < n; ++x) {
                        const TileId id{static_cast<std::uint8_t>(level), x, y};
                        const Box b = info.scheme.bounds(id);
                        if (id == victim)
                            w.addRawTile(id, payload);
                        else
                            w.addTile(sampleTile(id, b.min_x, b.min_y, info.scheme.tileSize(level)));
                    }
                }
            }
            w.finish();
        }
        const auto store = TileStore::open(path);
        const auto res = store->load(victim);
        EXPECT_FALSE(res.tile) << k.name;
        EXPECT_EQ(res.error, path.string() + ": tile 2/1/2: malformed payload: " + k.error + " at byte " +
                                 std::to_string(k.at + k.bytes.size()))
            << k.name;
        EXPECT_EQ(unloadable(*store), std::vector<std::string>{"2/1/2"}) << k.name;
    }
    // And every single-bit flip in every section decodes to an error or a tile, never a crash.
    std::size_t errors = 0;
    for (std::size_t byte = 0; byte < full.size(); ++byte) {
        for (int bit = 0; bit < 8; ++bit) {
            auto p = full;
            p[byte] ^= static_cast<std::uint8_t>(1u << bit);
            Tile t;
            std::string error;
            if (!decodeTile(p, t, error)) {
                EXPECT_FALSE(error.empty());
                ++errors;
            }
        }
    }
    EXPECT_GT(errors, 0u);
}

// docs/tile-store.md "Sizes": every size a store declares is checked against the file, the stored
// (compressed) size and the format's limits before anything is allocated, and streams inflate in
// pieces. A store that lies is refused, or its graph or tile reported, for what it is, never for
// what it claims: the peak resident memory of each case stays far below the claim.
namespace {

namespace fs = std::filesystem;

/// Growth of the peak resident memory (VmHWM, reset first through /proc/self/clear_refs) over the
/// resident memory before `f`, in MiB; -1 when the peak cannot be reset.
long peakGrowthMib(const std::function<void()>& f) {
    const auto status = [](const char* key) -> long {
        std::ifstream in("/proc/self/status");
        std::string line;
        while (std::getline(in, line)) {
            if (line.rfind(key, 0) == 0) return std::stol(line.substr(std::strlen(key))) / 1024;
        }
        return -1;
    };
    {
        std::ofstream clear("/proc/self/clear_refs");
        if (!(clear << "5" << std::flush)) return -1;
    }
    const long before = status("VmRSS:");
    f();
    return status("VmHWM:") - before;
}

/// Rewrites the header of the store at `path` with `edit` applied to its fields (checksum kept valid).
void editHeader(const fs::path& path, const std::function<void(StoreInfo&)>& edit) {
    auto bytes = readAll(path);
    StoreInfo info;
    std::string error;
    ASSERT_TRUE(detail::decodeHeader(bytes, info, error)) << error;
    edit(info);
    const auto header = detail::encodeHeader(info);
    std::copy(header.begin(), header.end(), bytes.begin());
    writeAll(path, bytes);
}

/// Sets every index entry's raw size with `raw(stored_size)`; both checksums kept valid.
void editIndexRawSizes(const fs::path& path, const std::function<std::uint32_t(std::uint32_t)>& raw) {
    auto bytes = readAll(path);
    StoreInfo info;
    std::string error;
    ASSERT_TRUE(detail::decodeHeader(bytes, info, error)) << error;
    for (std::uint32_t i = 0; i < info.tile_count; ++i) {
        const std::size_t at = info.index_offset + std::size_t{i} * detail::kIndexEntrySize;
        std::uint32_t stored = 0;
        std::memcpy(&stored, &bytes[at + 17], 4);  // level u8, x u32, y u32, offset u64, stored u32, raw u32
        const std::uint32_t value = raw(stored);
        std::memcpy(&bytes[at + 21], &value, 4);
    }
    info.index_crc = detail::crc32Of(std::span<const std::uint8_t>(bytes).subspan(
        info.index_offset, std::size_t{info.tile_count} * detail::kIndexEntrySize));
    const auto header = detail::encodeHeader(info);
    std::copy(header.begin(), header.end(), bytes.begin());
    writeAll(path, bytes);
}

/// zlib data (level 9) of `raw_bytes` zero bytes, deflated piece by piece: a "zlib bomb".
std::vector<std::uint8_t> zeroBomb(std::uint64_t raw_bytes) {
    z_stream z{};
    EXPECT_EQ(deflateInit(&z, 9), Z_OK);
    std::vector<std::uint8_t> zeros(std::size_t{1} << 20), out, piece(std::size_t{1} << 16);
    std::uint64_t left = raw_bytes;
    int rc = Z_OK;
    do {
        const auto n = static_cast<uInt>(std::min<std::uint64_t>(left, zeros.size()));
        z.next_in = zeros.data();
        z.avail_in = n;
        left -= n;
        const int flush = left == 0 ? Z_FINISH : Z_NO_FLUSH;
        do {
            z.next_out = piece.data();
            z.avail_out = static_cast<uInt>(piece.size());
            rc = deflate(&z, flush);
            out.insert(out.end(), piece.data(), piece.data() + (piece.size() - z.avail_out));
        } while (z.avail_out == 0);
    } while (left > 0);
    EXPECT_EQ(rc, Z_STREAM_END);
    deflateEnd(&z);
    return out;
}

}  // namespace

TEST(StoreSizes, AGraphDeclaringMoreThanZlibCanMakeOfItIsRefusedBeforeAllocating) {
    ScratchDir dir("sizes-graph");
    const RoadGraph g = smallGraph();
    const auto path = dir / "s.navmap";
    writeSmallStore(path, &g);
    const std::uint64_t stored = TileStore::open(path)->info().graph_stored_size;
    // 4 GiB (the format's limit), 1 GiB, and one byte over what the stored bytes can inflate to.
    for (const std::uint64_t claim : {detail::kMaxGraphRawBytes, std::uint64_t{1} << 30, stored * 1032 + 1}) {
        editHeader(path, [&](StoreInfo& i) { i.graph_raw_size = claim; });
        TileStore::GraphResult r;
        const long growth = peakGrowthMib([&] { r = TileStore::open(path)->tryLoadGraph(); });
        EXPECT_EQ(r.error, path.string() + ": road graph: declares " + std::to_string(claim) + " bytes from " +
                               std::to_string(stored) + " compressed, more than zlib's 1032:1 allows");
        if (growth >= 0) {
            EXPECT_LT(growth, 32) << "claim " << claim;
        }
    }
    // Past the format's limit, whatever the stored size.
    editHeader(path, [&](StoreInfo& i) { i.graph_raw_size = detail::kMaxGraphRawBytes + 1; });
    EXPECT_EQ(TileStore::open(path)->tryLoadGraph().error,
              path.string() + ": road graph: declares 4294967297 bytes, more than a road graph may have (4294967296)");
    // Fewer raw bytes than zlib could have stored them in.
    editHeader(path, [&](StoreInfo& i) { i.graph_raw_size = 1; });
    EXPECT_EQ(TileStore::open(path)->tryLoadGraph().error, path.string() + ": road graph: declares " +
                                                               std::to_string(stored) +
                                                               " compressed bytes for 1, more than zlib makes of them");
    // A plausible claim that is not the truth: the stream ends short, said so, nothing kept.
    editHeader(path, [&](StoreInfo& i) { i.graph_raw_size = stored * 1032; });
    const auto r = TileStore::open(path)->tryLoadGraph();
    EXPECT_EQ(r.problem.rfind("decompression failed (inflates to ", 0), 0u) << r.problem;
    EXPECT_TRUE(r.graph.edges.empty());
}

TEST(StoreSizes, AZlibBombGraphIsCaughtOnItsFirstPieceNotAfterInflatingIt) {
    ScratchDir dir("sizes-bomb");
    const RoadGraph g = smallGraph();
    const auto path = dir / "s.navmap";
    writeSmallStore(path, &g);
    // 256 MiB of zeros in about 250 KB, appended to the store, the header pointing at it: a ratio
    // zlib can make, so only inflating tells, and the zeros are no road graph.
    const std::uint64_t raw = std::uint64_t{256} << 20;
    const auto bomb = zeroBomb(raw);
    ASSERT_LT(bomb.size(), raw / 1000);
    auto bytes = readAll(path);
    const std::uint64_t at = bytes.size();
    bytes.insert(bytes.end(), bomb.begin(), bomb.end());
    writeAll(path, bytes);
    editHeader(path, [&](StoreInfo& i) {
        i.graph_offset = at;
        i.graph_stored_size = bomb.size();
        i.graph_raw_size = raw;
        i.graph_crc = detail::crc32Of(bomb);
    });
    TileStore::GraphResult r;
    const long growth = peakGrowthMib([&] { r = TileStore::open(path)->tryLoadGraph(); });
    EXPECT_EQ(r.error, path.string() + ": road graph: not a road graph (bad magic)");
    if (growth >= 0) {
        EXPECT_LT(growth, 32);
    }
    // The tiles are untouched.
    EXPECT_TRUE(unloadable(*TileStore::open(path)).empty());
}

TEST(StoreSizes, IndexEntriesDeclaringMoreThanTheirTileCanHoldAreFatalAtOpen) {
    ScratchDir dir("sizes-index");
    const auto path = dir / "s.navmap";
    writeSmallStore(path);
    // 256 MiB each (the size navmapd used to zero-fill per tile), and one byte past zlib's ratio.
    editIndexRawSizes(path, [](std::uint32_t) { return detail::kMaxTileRawBytes; });
    std::string e;
    const long growth = peakGrowthMib([&] { e = openError(path); });
    EXPECT_NE(e.find(path.string() + ": index entry 0 (tile 0/0/0) declares 268435456 bytes from "), std::string::npos)
        << e;
    EXPECT_NE(e.find(" compressed, more than zlib's 1032:1 allows"), std::string::npos) << e;
    if (growth >= 0) {
        EXPECT_LT(growth, 32);
    }

    writeSmallStore(path);
    editIndexRawSizes(path, [](std::uint32_t stored) { return stored * 1032 + 1; });
    e = openError(path);
    EXPECT_NE(e.find(": index entry 0 (tile 0/0/0) declares "), std::string::npos) << e;
    EXPECT_NE(e.find("more than zlib's 1032:1 allows"), std::string::npos) << e;

    // Fewer raw bytes than zlib could have stored them in: as impossible.
    writeSmallStore(path);
    editIndexRawSizes(path, [](std::uint32_t) { return 1u; });
    e = openError(path);
    EXPECT_NE(e.find(": index entry 0 (tile 0/0/0) declares "), std::string::npos) << e;
    EXPECT_NE(e.find(" compressed bytes for 1, more than zlib makes of them"), std::string::npos) << e;

    // Plausible but false: the store opens, each tile says how short it fell, and holds no memory.
    writeSmallStore(path);
    editIndexRawSizes(path, [](std::uint32_t stored) { return stored * 1032; });
    const auto store = TileStore::open(path);
    const auto res = store->load(TileId{0, 0, 0});
    EXPECT_FALSE(res.tile);
    EXPECT_NE(res.error.find(": tile 0/0/0: decompression failed (inflates to "), std::string::npos) << res.error;
    EXPECT_EQ(unloadable(*store).size(), 21u);
}

TEST(StoreSizes, MoreTilesThanAStoreMayHoldIsFatalBeforeTheIndexIsRead) {
    ScratchDir dir("sizes-count");
    const auto path = dir / "s.navmap";
    writeSmallStore(path);
    // A sparse file long enough for the index the header claims: 116 MiB that cost no disk.
    StoreInfo info;
    editHeader(path, [&](StoreInfo& i) {
        i.tile_count = detail::kMaxStoreTiles + 1;
        info = i;
    });
    ASSERT_EQ(::truncate(path.c_str(), static_cast<off_t>(info.index_offset + std::uint64_t{info.tile_count} * 29)), 0);
    std::string e;
    const long growth = peakGrowthMib([&] { e = openError(path); });
    EXPECT_EQ(e, path.string() + ": the header declares 4194305 tiles, more than the 4194304 a store may hold");
    if (growth >= 0) {
        EXPECT_LT(growth, 32);
    }
}

TEST(StoreSizes, AStoreThatIsNoRegularFileIsRefusedWithoutBlocking) {
    ScratchDir dir("sizes-fifo");
    const auto fifo = dir / "fifo.navmap";
    ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
    EXPECT_EQ(openError(fifo), fifo.string() + ": is a FIFO, not a regular file (tile store)");
    EXPECT_EQ(openError("/dev/zero"), "/dev/zero: is a character device, not a regular file (tile store)");
    EXPECT_EQ(openError(dir.path()), dir.path().string() + ": is a directory, not a regular file (tile store)");
}

TEST(StoreSizes, BoundedInflateStopsAtEveryKindOfLie) {
    std::vector<std::uint8_t> raw(100000);
    for (std::size_t i = 0; i < raw.size(); ++i) raw[i] = static_cast<std::uint8_t>(i * 7 / 3);
    uLongf len = compressBound(static_cast<uLong>(raw.size()));
    std::vector<std::uint8_t> z(len);
    ASSERT_EQ(compress2(z.data(), &len, raw.data(), static_cast<uLong>(raw.size()), 6), Z_OK);
    z.resize(len);
    std::vector<std::uint8_t> out;
    std::string problem;
    // The truth, in pieces (more than the first 64 KiB).
    ASSERT_TRUE(detail::inflateBounded(z, raw.size(), out, problem)) << problem;
    EXPECT_EQ(out, raw);
    // Longer than declared: stopped at the declared size.
    EXPECT_FALSE(detail::inflateBounded(z, raw.size() - 1, out, problem));
    EXPECT_EQ(problem, "decompression failed (inflates to more than the declared 99999 bytes)");
    EXPECT_TRUE(out.empty());
    // Shorter than declared.
    EXPECT_FALSE(detail::inflateBounded(z, raw.size() + 1, out, problem));
    EXPECT_EQ(problem, "decompression failed (inflates to 100000 of the declared 100001 bytes)");
    // Cut off.
    EXPECT_FALSE(detail::inflateBounded(std::span(z).first(z.size() / 2), raw.size(), out, problem));
    EXPECT_EQ(problem, "decompression failed (the stream ends without its end mark)");
    // Garbled.
    auto bad = z;
    bad[2] ^= 0xFF;
    bad[3] ^= 0xFF;
    EXPECT_FALSE(detail::inflateBounded(bad, raw.size(), out, problem));
    EXPECT_EQ(problem.rfind("decompression failed", 0), 0u) << problem;
    // More than zlib's ratio allows: refused before inflating.
    EXPECT_FALSE(detail::inflateBounded(z, z.size() * 1032 + 1, out, problem));
    EXPECT_EQ(problem, "declares " + std::to_string(z.size() * 1032 + 1) + " bytes from " + std::to_string(z.size()) +
                           " compressed, more than zlib's 1032:1 allows");
    // The check on the first bytes.
    std::size_t seen = 0;
    const detail::PrefixCheck never = [&](std::span<const std::uint8_t> head, std::string& why) {
        seen = head.size();
        why = "refused";
        return false;
    };
    EXPECT_FALSE(detail::inflateBounded(z, raw.size(), out, problem, 4, never));
    EXPECT_EQ(problem, "refused");
    EXPECT_GE(seen, 4u);
    EXPECT_LE(seen, std::size_t{64} << 10);  // the first piece, not the whole output
}
