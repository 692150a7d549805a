// SPDX-License-Identifier: Apache-2.0
#pragma once
// A store's quadtree (seed 3.6 and 6.5: quadtree tiles, one pyramid level per detail step): a
// subtree of the world tile scheme (world_tiles.h) seen in the store's frame. The root is one world
// tile; store level L is world level root.z + L, and store tile L/x/y is world tile
// (root.z + L, root.x * 2^L + x, root.y * 2^L + y). In the store frame (a Projection) the root is a
// square of rootSize() metres whose south-west corner is (rootMinX(), rootMinY()); level L has
// 2^L x 2^L tiles of rootSize() / 2^L.

#include <cstdint>
#include <optional>

#include "navmap/map/geometry.h"
#include "navmap/map/projection.h"
#include "navmap/map/tile.h"

namespace navmap::map {

struct TileRange {
    std::uint32_t x0 = 0, y0 = 0, x1 = 0, y1 = 0;  ///< inclusive
    bool empty = true;
};

class TileScheme {
public:
    TileScheme() = default;
    /// A quadtree over a planar square that is not on the world scheme (worldRoot() is 0/0/0 and
    /// means nothing): for the geometry of tile selection and terrain level of detail alone.
    TileScheme(double root_min_x, double root_min_y, double root_size_m, int level_count);
    /// The subtree of `level_count` levels under the world tile `root`, in `frame`.
    TileScheme(const Projection& frame, WorldTileId root, int level_count);

    /// The scheme of a store with data in a lat/lon box: the leaf level is the world level whose
    /// tiles are nearest to leaf_size_m ground metres at the frame's origin
    /// (worldZoomForGroundSize), the root the finest world tile holding the whole box.
    static TileScheme forData(const Projection& frame, double south, double west, double north, double east,
                              double leaf_size_m);

    [[nodiscard]] WorldTileId worldRoot() const { return m_root; }
    /// The world address of a tile of this scheme.
    [[nodiscard]] WorldTileId worldTile(TileId id) const;
    /// The tile of this scheme with a world address, or nullopt outside the subtree.
    [[nodiscard]] std::optional<TileId> fromWorld(WorldTileId id) const;

    [[nodiscard]] int levelCount() const { return m_levels; }
    [[nodiscard]] int leafLevel() const { return m_levels - 1; }
    [[nodiscard]] double rootMinX() const { return m_min_x; }
    [[nodiscard]] double rootMinY() const { return m_min_y; }
    [[nodiscard]] double rootSize() const { return m_size; }
    [[nodiscard]] double tileSize(int level) const;
    [[nodiscard]] Box bounds(TileId id) const;
    [[nodiscard]] bool valid(TileId id) const;
    /// The tile of `level` containing p, or nullopt outside the root square.
    [[nodiscard]] std::optional<TileId> tileAt(int level, PlanarPoint p) const;
    /// Tiles of `level` overlapping a box (clamped to the root square).
    [[nodiscard]] TileRange range(int level, const Box& box) const;
    /// The coarsest level whose tiles are no larger than size_m (the leaf level if none is).
    [[nodiscard]] int levelForTileSize(double size_m) const;

private:
    double m_min_x = 0, m_min_y = 0, m_size = 1;
    int m_levels = 1;
    WorldTileId m_root;
};

}  // namespace navmap::map
