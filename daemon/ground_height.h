// SPDX-License-Identifier: Apache-2.0
#pragma once
// GroundHeight: the terrain height under the vehicle, one query for the whole daemon. It reads
// the finest terrain resident in the shared tile cache, so the pose's height does not depend on
// which display is listed first or which tiles a display selected. Render thread only.

#include <memory>

#include "navmap/map/tile_cache.h"
#include "navmap/render/map_view.h"

namespace navmap::daemon {

class GroundHeight {
public:
    explicit GroundHeight(std::shared_ptr<map::TileCache> cache) : m_view(std::move(cache)) {}

    /// Height of the finest resident terrain at a store-frame position, metres (0 where none).
    [[nodiscard]] double operator()(double x, double y) const { return m_view.terrainHeight(x, y); }

private:
    // Only its height query is used: it reads the cache and selects no tiles of its own.
    render::MapView m_view;
};

}  // namespace navmap::daemon
