// SPDX-License-Identifier: Apache-2.0
#pragma once
// Several stores mounted together (region packages, as NDS update regions): one tile source in
// one frame, across the stores' borders. Every store is a subtree of the world tile scheme
// (world_tiles.h), so the set's scheme is the world subtree under the stores' common ancestor,
// and a tile of it comes from the first mounted store that holds that world tile. Tiles are
// re-expressed from their store's frame into the set's frame (a uniform scale and a translation:
// FrameTransform), so the squares of neighbouring stores meet edge to edge.

#include <atomic>
#include <cstddef>
#include <memory>
#include <optional>
#include <vector>

#include "navmap/map/projection.h"
#include "navmap/map/tile_source.h"
#include "navmap/map/tile_store.h"

namespace navmap::map {

class StoreSet : public TileSource {
public:
    /// Mounts `stores` (at least one; the first wins where two hold the same tile) in `frame`.
    /// Throws StoreError naming the stores when they cannot be drawn together: different DEM
    /// grids per tile, or a common subtree deeper than 28 levels.
    static std::shared_ptr<StoreSet> mount(std::vector<std::shared_ptr<const TileStore>> stores, Projection frame);
    /// The same stores mounted in another frame (the daemon re-centres its frame as the vehicle
    /// moves): the same scheme and tile ids, every tile re-expressed into `frame`; the load
    /// counters are shared with this set, so they keep counting.
    [[nodiscard]] std::shared_ptr<StoreSet> inFrame(const Projection& frame) const;

    [[nodiscard]] const Projection& frame() const { return m_frame; }
    [[nodiscard]] const TileScheme& scheme() const override { return m_scheme; }
    [[nodiscard]] std::vector<TileId> roots() const override { return m_roots; }
    [[nodiscard]] bool contains(TileId id) const override { return storeOf(id).has_value(); }
    [[nodiscard]] TileLoadResult load(TileId id) const override;
    [[nodiscard]] std::uint32_t demSamples() const override { return m_dem_samples; }

    [[nodiscard]] std::size_t storeCount() const { return m_stores.size(); }
    [[nodiscard]] const TileStore& store(std::size_t i) const { return *m_stores[i].store; }
    /// The mounted store a tile of the set comes from, or nullopt.
    [[nodiscard]] std::optional<std::size_t> storeOf(TileId id) const;
    /// Tiles loaded from store i so far.
    [[nodiscard]] std::uint64_t loads(std::size_t i) const { return m_stores[i].loads->load(); }

private:
    struct Mounted {
        std::shared_ptr<const TileStore> store;
        FrameTransform to_frame;
        std::shared_ptr<std::atomic<std::uint64_t>> loads;
    };
    StoreSet() = default;
    /// A tile of the set re-expressed into its frame, without the heights beyond its edges.
    std::shared_ptr<Tile> loadAlone(TileId id, TileLoadResult& r) const;
    Projection m_frame{0.0, 0.0};
    TileScheme m_scheme;
    std::vector<TileId> m_roots;
    std::vector<Mounted> m_stores;
    std::uint32_t m_dem_samples = 0;
};

/// A tile in another frame, with the address `id` there: its origin and size (the tile's square
/// there, as that frame's scheme computes them) and every horizontal coordinate scaled by t.scale;
/// heights stay metres.
void reexpressTile(Tile& tile, const FrameTransform& t, TileId id, PlanarPoint origin, double size_m);

}  // namespace navmap::map
