// SPDX-License-Identifier: Apache-2.0
#include "navmap/map/store_set.h"

#include <algorithm>

#include "navmap/map/store_info.h"

namespace navmap::map {
namespace {

void scalePoints(std::vector<LocalPoint>& points, float s) {
    for (auto& p : points) p = {p.x * s, p.y * s};
}

}  // namespace

std::shared_ptr<StoreSet> StoreSet::mount(std::vector<std::shared_ptr<const TileStore>> stores, Projection frame) {
    if (stores.empty()) throw StoreError("no store to mount");
    std::shared_ptr<StoreSet> set(new StoreSet());
    set->m_frame = frame;
    set->m_dem_samples = stores.front()->info().dem_samples;
    WorldTileId common = stores.front()->scheme().worldRoot();
    int deepest = 0;
    for (const auto& s : stores) {
        if (s->info().dem_samples != set->m_dem_samples) {
            throw StoreError(s->path().string() + ": " + std::to_string(s->info().dem_samples) +
                             " DEM samples per tile side, " + stores.front()->path().string() + " has " +
                             std::to_string(set->m_dem_samples) + " (stores mounted together need the same grid)");
        }
        const WorldTileId root = s->scheme().worldRoot();
        while (!common.contains(root)) common = common.parent();
        deepest = std::max(deepest, root.z + s->scheme().levelCount() - 1);
        set->m_stores.push_back(
            {s, frame.transformFrom(s->projection()), std::make_shared<std::atomic<std::uint64_t>>(0)});
    }
    if (deepest - common.z + 1 > 28) {
        throw StoreError("the mounted stores span " + std::to_string(deepest - common.z + 1) +
                         " levels of the world tile scheme under " + common.toString() + " (at most 28)");
    }
    set->m_scheme = TileScheme(frame, common, deepest - common.z + 1);
    for (const auto& m : set->m_stores) {
        const auto root = set->m_scheme.fromWorld(m.store->scheme().worldRoot());
        if (root && std::find(set->m_roots.begin(), set->m_roots.end(), *root) == set->m_roots.end())
            set->m_roots.push_back(*root);
    }
    return set;
}

std::shared_ptr<StoreSet> StoreSet::inFrame(const Projection& frame) const {
    std::shared_ptr<StoreSet> set(new StoreSet(*this));
    set->m_frame = frame;
    set->m_scheme = TileScheme(frame, m_scheme.worldRoot(), m_scheme.levelCount());
    for (Mounted& m : set->m_stores) m.to_frame = frame.transformFrom(m.store->projection());
    return set;
}

std::optional<std::size_t> StoreSet::storeOf(TileId id) const {
    if (!m_scheme.valid(id)) return std::nullopt;
    const WorldTileId w = m_scheme.worldTile(id);
    for (std::size_t i = 0; i < m_stores.size(); ++i) {
        const auto local = m_stores[i].store->scheme().fromWorld(w);
        if (local && m_stores[i].store->contains(*local)) return i;
    }
    return std::nullopt;
}

TileLoadResult StoreSet::load(TileId id) const {
    TileLoadResult r;
    std::shared_ptr<Tile> tile = loadAlone(id, r);
    if (!tile) return r;
    m_stores[*storeOf(id)].loads->fetch_add(1);
    // The heights beyond each edge from the tile of the set there, whichever store holds it, read
    // from that store (heights are the same in every frame: nothing to re-express).
    attachDemBorders(*tile, [this](TileId across) -> std::shared_ptr<const Tile> {
        const auto holder = storeOf(across);
        if (!holder) return nullptr;
        const TileStore& store = *m_stores[*holder].store;
        TileLoadResult ignored;
        return store.loadAlone(*store.scheme().fromWorld(m_scheme.worldTile(across)), ignored);
    });
    r.tile = std::move(tile);
    return r;
}

std::shared_ptr<Tile> StoreSet::loadAlone(TileId id, TileLoadResult& r) const {
    const auto which = storeOf(id);
    if (!which) {
        r.missing = true;
        return nullptr;
    }
    const Mounted& m = m_stores[*which];
    const TileId own = *m.store->scheme().fromWorld(m_scheme.worldTile(id));
    std::shared_ptr<Tile> tile = m.store->loadAlone(own, r);
    if (!tile) return nullptr;
    if (own == id && m.to_frame.identity()) return tile;  // the set's scheme is this store's (shards)
    const Box square = m_scheme.bounds(id);
    reexpressTile(*tile, m.to_frame, id, {square.min_x, square.min_y}, m_scheme.tileSize(id.level));
    return tile;
}

void reexpressTile(Tile& tile, const FrameTransform& t, TileId id, PlanarPoint origin, double size_m) {
    tile.id = id;
    tile.origin_x = origin.x;
    tile.origin_y = origin.y;
    tile.size_m = size_m;
    if (t.scale == 1.0) return;
    const auto s = static_cast<float>(t.scale);
    for (auto& road : tile.roads) scalePoints(road.points, s);
    for (auto& b : tile.buildings) scalePoints(b.footprint.vertices, s);
    for (auto& a : tile.areas) scalePoints(a.polygon.vertices, s);
    for (auto& l : tile.labels) {
        l.anchor = {l.anchor.x * s, l.anchor.y * s};
        l.segment_start = {l.segment_start.x * s, l.segment_start.y * s};
        l.segment_end = {l.segment_end.x * s, l.segment_end.y * s};
    }
    tile.dem.spacing_m *= s;
}

}  // namespace navmap::map
