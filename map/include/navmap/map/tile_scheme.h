// SPDX-License-Identifier: Apache-2.0
#pragma once
// The quadtree over the store's planar frame (seed 3.6 and 6.5: quadtree tiles, one pyramid
// level per detail step). The root tile is a square of root_size_m metres whose south-west
// corner is (root_min_x, root_min_y); level L has 2^L x 2^L tiles of root_size_m / 2^L.

#include <cstdint>
#include <optional>

#include "navmap/map/geometry.h"
#include "navmap/map/tile.h"

namespace navmap::map {

struct TileRange {
    std::uint32_t x0 = 0, y0 = 0, x1 = 0, y1 = 0;  ///< inclusive
    bool empty = true;
};

class TileScheme {
public:
    TileScheme() = default;
    TileScheme(double root_min_x, double root_min_y, double root_size_m, int level_count);

    /// Picks the smallest power-of-two multiple of leaf_size_m that covers `bounds`, centred on
    /// it; the leaf level then has tiles of exactly leaf_size_m.
    static TileScheme covering(const Box& bounds, double leaf_size_m);

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
};

}  // namespace navmap::map
